"""The DSP stage's error class, in a module of its own so that the record formats
(:mod:`dptbd.dsp.records`) and the association (:mod:`dptbd.dsp.association`) can both raise
it whichever of them is imported first."""

from __future__ import annotations

from dptbd.errors import DptbdError

__all__ = ["AssociationError"]


class AssociationError(DptbdError):
    """An association parameter or input is invalid; the message names it."""
