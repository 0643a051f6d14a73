"""DPCore's implementation options: the allowed values and the line buffer of each style."""

import re

import pytest

from dptbd.config import DPConfig
from dptbd.hw.dp_core import CORE_OPTIONS, check_core_options, core_line_buffer
from dptbd.hw.dp_core import options
from dptbd.hw.dp_core.core import DPCore
from dptbd.hw.layouts import state_word_layout


def test_core_options_are_what_dpcore_takes_and_reports():
    """Every option of ``CORE_OPTIONS`` is a DPCore keyword with its default among the
    allowed values, and ``core_options`` reports exactly these keys."""
    core = DPCore(DPConfig(width=6, height=5))
    assert set(core.core_options) == set(options.CORE_OPTIONS)
    for name, allowed in options.CORE_OPTIONS.items():
        assert core.core_options[name] in allowed, name
        other = DPCore(DPConfig(width=6, height=5), **{name: allowed[-1]})
        assert other.core_options[name] == allowed[-1]


@pytest.mark.parametrize("style, depth, chosen", [
    ("bram", 8, (None, False)), ("lutram", 8, ("distributed", True)),
    ("lutram", 4, ("distributed", True)), ("lutram", 6, ("distributed", True)),
    ("lutram", 7, ("distributed", False)), ("lutram", 2, ("distributed", False)),
    ("dp16kd", 8, ("dp16kd", False)),
], ids=lambda v: v if isinstance(v, (str, int)) else "-".join(map(str, v)))
def test_line_buffer_of_each_style(monkeypatch, style, depth, chosen):
    """LUT RAM reads interleaved at an even depth >= 4 only; the other styles never do."""
    made = []
    real = options.LineBuffer
    monkeypatch.setattr(options, "LineBuffer", lambda *a, **k: made.append(k) or real(*a, **k))
    cfg = DPConfig(width=6, height=5)
    core_line_buffer(state_word_layout(cfg), depth, 2, style)
    assert [(k["ram_style"], k["interleaved_read"]) for k in made] == [chosen]


def test_check_core_options_passes_every_allowed_value():
    for name, allowed in CORE_OPTIONS.items():
        for value in allowed:
            check_core_options(**{name: value})


@pytest.mark.parametrize("name", sorted(set(CORE_OPTIONS) - {"max_tree"}))
def test_check_core_options_refuses_a_value_not_allowed(name):
    allowed = re.escape(repr(CORE_OPTIONS[name]))
    with pytest.raises(ValueError, match=rf"^{name} must be one of {allowed}, got 'nope'$"):
        check_core_options(**{name: "nope"})


def test_check_core_options_leaves_max_tree_to_the_schedule():
    check_core_options(max_tree="nope")      # refused by check_supported, naming the builds
