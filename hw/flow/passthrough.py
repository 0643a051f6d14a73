"""The options a user passes through to the synthesis tools (the bench's ``--nextpnr-args``
and ``--yosys-args``): split like a shell's words, and refused where the flow sets the
option itself."""

from __future__ import annotations

import shlex

from dptbd.hw.flow.synth import FAMILIES

__all__ = ["FLOW_SETS", "YOSYS_FLOW_SETS", "split_nextpnr_args", "split_yosys_args"]

#: nextpnr options the flow sets itself, and the bench option that sets each.
FLOW_SETS = {"--seed": "--seeds", "--freq": "--freq", "--package": "--package",
             "--speed": "--speed", "--router": "--router", "--json": None, "--report": None,
             "-l": None, "--log": None, "-q": None, "--quiet": None,
             **{f"--{d}": "--device" for fam in FAMILIES.values() for d in fam.devices}}


def split_nextpnr_args(text: str) -> tuple[str, ...]:
    """``--nextpnr-args``: split like a shell's words; ``ValueError`` for an option the flow
    sets itself (the seed, the target, the device, the router, the speed, the files)."""
    words = _words("--nextpnr-args", text)
    for word in words:
        flag = word.split("=", 1)[0]
        if flag in FLOW_SETS:
            use = FLOW_SETS[flag]
            how = (f"set it with the bench's {use}" if use
                   else "the flow writes its own files")
            raise ValueError(f"--nextpnr-args may not set {flag}: {how}; allowed: nextpnr's "
                             f"other options, e.g. --tmg-ripup")
    return words


#: Options of the Yosys synthesis command the flow sets itself: why each is refused.
YOSYS_FLOW_SETS = {"-top": "the flow names the top module", "-json": "the flow writes its own "
                   "files", "-edif": "the flow writes its own files", "-noflatten": "the "
                   "flow's per-block pass has it (the bench's --no-breakdown drops that pass)",
                   "-run": "the flow runs the whole command"}


def split_yosys_args(text: str | None) -> tuple[str, ...] | None:
    """``--yosys-args``: ``None`` (not given: the family's ``Family.synth_args``) or the
    words, split like a shell's; ``ValueError`` for an option the flow sets itself."""
    if text is None:
        return None
    words = _words("--yosys-args", text)
    for word in words:
        if word in YOSYS_FLOW_SETS:
            raise ValueError(f"--yosys-args may not set {word}: {YOSYS_FLOW_SETS[word]}; "
                             f"allowed: the synthesis command's other options, e.g. "
                             f"-nowidelut")
    return words


def _words(option: str, text: str) -> tuple[str, ...]:
    """``text`` split like a shell's words; ``ValueError`` naming ``option`` if it cannot be."""
    try:
        return tuple(shlex.split(text))
    except ValueError as exc:
        raise ValueError(f"{option} must split into words like a shell's: {exc}; "
                         f"got {text!r}") from None
