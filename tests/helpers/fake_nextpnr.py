"""A stand-in for nextpnr in the flow's tests: a shell script that copies a canned log to
its ``-l`` file and exits with a given code, optionally never finishing (on every seed or on
one)."""

import pathlib
import stat
import textwrap

__all__ = ["fake_nextpnr"]


def fake_nextpnr(folder: pathlib.Path, log: str, rc: int = 0, sleep: float = 0,
                 stall_seed: int | None = None) -> str:
    """Write the stand-in into ``folder``; its path. It writes ``log`` to its ``-l`` file and
    exits with ``rc``, after ``sleep`` seconds; run with ``--seed stall_seed`` it sleeps 60 s
    and writes nothing (the shell becomes ``sleep``, so that stopping it stops the sleep)."""
    (folder / "canned.log").write_text(log)
    script = folder / "fake-nextpnr"
    stall = (f'case " $* " in *" --seed {stall_seed} "*) exec sleep 60;; esac'
             if stall_seed is not None else "")
    script.write_text(textwrap.dedent(f"""\
        #!/bin/sh
        {stall}
        while [ $# -gt 0 ]; do
          if [ "$1" = "-l" ]; then cp "{folder / 'canned.log'}" "$2"; fi
          shift
        done
        {f"exec sleep {sleep}" if sleep else ""}
        exit {rc}
        """))
    script.chmod(script.stat().st_mode | stat.S_IXUSR)
    return str(script)
