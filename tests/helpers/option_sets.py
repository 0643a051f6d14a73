"""Parameter sets of implementation options: every combination, the default suite every
pair.

A test over every combination of n options grows as the product of their value counts;
the default suite runs a subset that holds every pair of values of every two options
(allpairspy), the slow suite (``-m slow``) the rest of the product.
"""

from __future__ import annotations

import itertools
from typing import Mapping, Sequence

import pytest
from allpairspy import AllPairs


def option_params(varied: Mapping[str, Sequence[str]], base: Mapping[str, str],
                  last: Mapping[str, str]) -> list:
    """``pytest.param`` of every combination of ``varied``'s values over ``base`` (the
    combinations outside an all-pairs subset marked ``slow``), then ``last``; each id the
    options' values joined by ``-``."""
    names = list(varied)
    pairs = {tuple(row) for row in AllPairs([list(varied[name]) for name in names])}
    params = []
    for values in itertools.product(*(varied[name] for name in names)):
        options = {**base, **dict(zip(names, values))}
        marks = () if values in pairs else (pytest.mark.slow,)
        params.append(pytest.param(options, marks=marks, id="-".join(options.values())))
    params.append(pytest.param(dict(last), id="-".join(last.values())))
    return params
