"""A mutant's verdict: :class:`MutantOutcome`, and :func:`hang_verdict` for a run whose cycle
budget ran out (the verdicts are described in :mod:`dptbd.sim.mutation.run`)."""

from __future__ import annotations

import dataclasses

__all__ = ["VERDICTS", "MutantOutcome", "hang_verdict"]

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
