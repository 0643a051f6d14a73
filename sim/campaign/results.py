"""The results of the verification campaign (:mod:`dptbd.sim.campaign`): a run's outcome
(:class:`RunOutcome`, with its functional coverage bins), a case's (:class:`CaseResult`) and
the campaign's (:class:`CampaignResult`: verdict, words, the bins added up)."""

from __future__ import annotations

import dataclasses

__all__ = ["RunOutcome", "CaseResult", "CampaignResult", "summarise"]


@dataclasses.dataclass(frozen=True)
class RunOutcome:
    case: str
    seed: int
    passed: bool
    report: str
    words_in: int
    words_out: int
    cycles: int
    sim_seconds: float
    wall_seconds: float
    notes: tuple[str, ...]
    #: functional coverage, {bin: hits} (:mod:`dptbd.sim.coverage.bins`)
    bins: dict = dataclasses.field(default_factory=dict, compare=False)


@dataclasses.dataclass(frozen=True)
class CaseResult:
    name: str
    design: str
    runs: int
    passed: bool
    words_in: int
    words_out: int
    cycles: int
    sim_seconds: float
    first_failure: RunOutcome | None

    @property
    def words_per_second(self) -> float:
        return self.words_out / self.sim_seconds if self.sim_seconds > 0 else float("nan")


@dataclasses.dataclass(frozen=True)
class CampaignResult:
    cases: tuple[CaseResult, ...]
    outcomes: tuple[RunOutcome, ...]
    wall_seconds: float
    workers: int

    @property
    def passed(self) -> bool:
        return all(c.passed for c in self.cases)

    @property
    def words_out(self) -> int:
        return sum(c.words_out for c in self.cases)

    @property
    def words_in(self) -> int:
        return sum(c.words_in for c in self.cases)

    @property
    def mismatches(self) -> int:
        return sum(not o.passed for o in self.outcomes)

    @property
    def bins(self) -> dict[str, int]:
        """Functional coverage: every bin the runs declared, hits added."""
        from dptbd.sim.coverage.bins import merge
        return merge(*(o.bins for o in self.outcomes))

    @property
    def empty_bins(self) -> list[str]:
        """The declared bins no run hit: the campaign fails on them."""
        from dptbd.sim.coverage.bins import empty_bins
        return empty_bins(self.bins)

    @property
    def covered(self) -> bool:
        """Every declared bin hit (the coverage verdict, beside :attr:`passed`)."""
        return not self.empty_bins


def summarise(name: str, design: str, outcomes: list[RunOutcome]) -> CaseResult:
    """The result of case ``name`` from its runs' outcomes: passed when every run passed, the
    first failing run kept."""
    failed = [o for o in outcomes if not o.passed]
    return CaseResult(name, design, len(outcomes), not failed,
                      sum(o.words_in for o in outcomes), sum(o.words_out for o in outcomes),
                      sum(o.cycles for o in outcomes), sum(o.sim_seconds for o in outcomes),
                      failed[0] if failed else None)
