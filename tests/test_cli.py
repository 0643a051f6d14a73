"""The dptbd command line: one module per command, errors reported as ``dptbd X: error: …``."""

import importlib
import re

import pytest

from dptbd import cli
from dptbd.cli import main


def test_every_command_lives_in_the_module_of_its_name():
    for name, (module, help_text) in cli.COMMANDS.items():
        assert module == f"dptbd.commands.{name}" and help_text
        command = importlib.import_module(module)
        assert callable(command.add_arguments) and callable(command.main)


def test_help_names_every_command(capsys):
    with pytest.raises(SystemExit) as exc:
        main(["--help"])
    assert exc.value.code == 0
    out = capsys.readouterr().out
    for name in cli.COMMANDS:
        assert re.search(rf"^    {name}\b", out, re.M)


def test_a_refusal_is_one_line_and_exit_2(capsys, tmp_path):
    missing = tmp_path / "missing.toml"
    assert main(["run", "--scenario", str(missing), "--out", str(tmp_path / "r")]) == 2
    err = capsys.readouterr().err
    assert err.startswith("dptbd run: error: ") and err.count("\n") == 1
    assert "Traceback" not in err


def test_unknown_command_exits_with_usage():
    with pytest.raises(SystemExit) as exc:
        main(["frobnicate"])
    assert exc.value.code == 2
