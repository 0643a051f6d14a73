"""``dptbd table1``: refusals before the Monte Carlo run, the --markdown file, where it runs."""

import re

import pytest

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


def test_table1_refuses_a_bad_worker_count(capsys):
    assert main(["table1", "--trials", "1", "--workers", "0"]) == 2
    assert capsys.readouterr().err == ("dptbd table1: error: workers must be an integer in "
                                       "[1, 1024], got 0\n")


def test_table1_on_a_cluster_with_fewer_workers_than_asked_is_refused(capsys):
    """--scheduler, --workers and --dashboard reach the execution layer: the dashboard's
    address, then the refusal after waiting CONNECT_TIMEOUT (5 s) for the workers."""
    distributed = pytest.importorskip("distributed")
    with distributed.LocalCluster(n_workers=1, threads_per_worker=1, processes=False,
                                  dashboard_address="127.0.0.1:0") as cluster:
        address = cluster.scheduler_address
        assert main(["table1", "--trials", "1", "--scheduler", address, "--workers", "3",
                     "--dashboard"]) == 2
    assert re.fullmatch(rf"dask dashboard: http://[\w.]+:\d+/status\n"
                        rf"dptbd table1: error: the dask cluster at {re.escape(address)} has 1 "
                        rf"worker\(s\), 3 asked for\n", capsys.readouterr().err)
