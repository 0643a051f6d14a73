"""``dptbd table1``: refusals before the Monte Carlo run, the --markdown file."""

from dptbd.cli import main


def test_table1_refuses_bad_trials_and_overwrite(tmp_path, capsys):
    assert main(["table1", "--trials", "0"]) == 2
    assert capsys.readouterr().err == "dptbd table1: error: trials must be an integer in [1, inf), got 0\n"
    existing = tmp_path / "t.md"
    existing.write_text("mine")
    assert main(["table1", "--trials", "1", "--markdown", str(existing)]) == 2
    assert capsys.readouterr().err == (f"dptbd table1: error: --markdown {existing} exists; pass "
                                       f"--force to overwrite it\n")
    assert existing.read_text() == "mine"
