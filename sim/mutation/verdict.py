"""A mutant's verdict: :class:`MutantOutcome`, :func:`hang_verdict` for a run whose cycle
budget ran out and :func:`stream_hang` for a stream run's (the verdicts are described in
:mod:`dptbd.sim.mutation.run`)."""

from __future__ import annotations

import dataclasses

import numpy as np

__all__ = ["VERDICTS", "MutantOutcome", "hang_verdict", "stream_hang"]

#: Verdicts, in the order they are listed.
VERDICTS = ("killed", "survived", "timeout", "crashed", "no-build")


@dataclasses.dataclass(frozen=True)
class MutantOutcome:
    """The verdict of mutant ``index`` (0: the original), the run that decided it and its
    report."""

    index: int
    verdict: str
    run: str
    report: str
    seconds: float


#: What :class:`dptbd.sim.checker.InOrderChecker` reports for a wrong, an extra or a
#: missing output word: a run whose cycle budget ran out with one of these is killed.
_DETECTED = ("first mismatch at", "beyond the", "incomplete: ")


def hang_verdict(status: str, report: str) -> str | None:
    """``"timeout"`` if a run that did not finish (``status`` is not ``"done"``: its cycle
    budget, :func:`dptbd.sim.verilator.cycle_budget`, three times the cycles it needs, ran
    out) has a ``report`` with no wrong, extra or missing output word (the mutant hangs
    where the model expects no more output, e.g. the input stalls after the last list);
    ``None`` otherwise (the run's own check decides: a hang where the model expects more
    words is a failed check, ``incomplete: …``, and killed). A run past the wall-clock
    limit never gets here: it is a timeout (:func:`run_slice`)."""
    if status != "done" and not any(text in report for text in _DETECTED):
        return "timeout"
    return None


def _missing_of_offered(sim, words, stim, result) -> str:
    """For a run without resets whose cycle budget ran out with offered words not taken:
    the golden model fed every offered word against what the design delivered; the report
    of the missing (or wrong) words, or ``""`` if every word the model gives came out. At
    P > 1 pixels per clock ``words`` are beats, and words here count pixels and states."""
    from dptbd.sim.rtl.check import _checker, beat_state_words, expected_stream, split_beats, \
        split_words

    if stim.resets or result.raw.status == "done":
        return ""
    p = sim.cfg.pixels_per_clock
    pixels, first = (split_words(sim.cfg, np.asarray(words)) if p == 1
                     else split_beats(sim.cfg, np.asarray(words)))
    exp = expected_stream(sim.cfg, pixels, first,
                          {int(i) * p: codes for i, codes in stim.lut_changes},
                          {int(i) * p: entry for i, entry in stim.settings_changes})
    board = _checker(sim.cfg, sim.output, exp, cut_by_reset=False)
    out = result.raw.out_words
    board.receive_array(out if p == 1 or sim.output != "states"
                        else beat_state_words(sim.cfg, out))
    if board.done:
        return ""
    return (f"hang: {result.words_in} of {len(pixels)} offered words taken in "
            f"{result.raw.cycles} cycles; against the model of every offered word: "
            f"{board.report()}")


def stream_hang(sim, words, stim, result) -> tuple[str, str] | None:
    """The verdict of a stream run (:func:`dptbd.sim.rtl.check.check_stream`) whose cycle
    budget ran out: ``killed`` with the missing words when the model of every offered word
    gives words the design did not deliver, ``timeout`` otherwise (:func:`hang_verdict`);
    ``None`` for a run that finished or whose own check decides."""
    if not hang_verdict(result.raw.status, result.report):
        return None
    missing = _missing_of_offered(sim, words, stim, result)
    if missing:
        return "killed", missing
    return "timeout", f"cycle budget ({result.raw.cycles} cycles) ran out: {result.report}"
