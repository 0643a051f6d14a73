import re

import pytest

from dptbd.hw.flow.passthrough import split_nextpnr_args, split_yosys_args


def test_nextpnr_words_split_like_a_shell_s():
    assert split_nextpnr_args("--tmg-ripup --placer 'static'") == (
        "--tmg-ripup", "--placer", "static")
    assert split_nextpnr_args("") == ()


@pytest.mark.parametrize("text, message", [
    ("--seed 4", "--nextpnr-args may not set --seed: set it with the bench's --seeds; "
                 "allowed: nextpnr's other options, e.g. --tmg-ripup"),
    ("--json=x.json", "--nextpnr-args may not set --json: the flow writes its own files; "
                      "allowed: nextpnr's other options, e.g. --tmg-ripup"),
    ("--placer 'static", "--nextpnr-args must split into words like a shell's: No closing "
                         "quotation; got \"--placer 'static\""),
])
def test_nextpnr_options_the_flow_sets_are_refused(text, message):
    with pytest.raises(ValueError, match=f"^{re.escape(message)}$"):
        split_nextpnr_args(text)


def test_yosys_words_none_is_the_family_s():
    assert split_yosys_args(None) is None
    assert split_yosys_args("-nowidelut -dff") == ("-nowidelut", "-dff")


@pytest.mark.parametrize("text, message", [
    ("-top x", "--yosys-args may not set -top: the flow names the top module; allowed: the "
               "synthesis command's other options, e.g. -nowidelut"),
    ("-run begin:map", "--yosys-args may not set -run: the flow runs the whole command; "
                       "allowed: the synthesis command's other options, e.g. -nowidelut"),
])
def test_yosys_options_the_flow_sets_are_refused(text, message):
    with pytest.raises(ValueError, match=f"^{re.escape(message)}$"):
        split_yosys_args(text)
