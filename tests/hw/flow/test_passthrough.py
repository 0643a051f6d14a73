import re

import pytest

from dptbd.hw.flow.passthrough import split_nextpnr_args, split_yosys_args


def test_the_words_split_like_a_shell_s():
    assert split_nextpnr_args("--tmg-ripup --placer 'static'") == (
        "--tmg-ripup", "--placer", "static")
    assert split_nextpnr_args("") == ()
    assert split_yosys_args(None) is None          # the family's (Family.synth_args)
    assert split_yosys_args("-nowidelut -dff") == ("-nowidelut", "-dff")


NEXTPNR_ALLOWED = "; allowed: nextpnr's other options, e.g. --tmg-ripup"
YOSYS_ALLOWED = "; allowed: the synthesis command's other options, e.g. -nowidelut"


@pytest.mark.parametrize("split, text, message", [
    (split_nextpnr_args, "--seed 4",
     "--nextpnr-args may not set --seed: set it with the bench's --seeds" + NEXTPNR_ALLOWED),
    (split_nextpnr_args, "--json=x.json",
     "--nextpnr-args may not set --json: the flow writes its own files" + NEXTPNR_ALLOWED),
    (split_nextpnr_args, "--placer 'static",
     "--nextpnr-args must split into words like a shell's: No closing quotation; "
     "got \"--placer 'static\""),
    (split_yosys_args, "-top x",
     "--yosys-args may not set -top: the flow names the top module" + YOSYS_ALLOWED),
    (split_yosys_args, "-run begin:map",
     "--yosys-args may not set -run: the flow runs the whole command" + YOSYS_ALLOWED),
    (split_yosys_args, "-D 'x",
     "--yosys-args must split into words like a shell's: No closing quotation; got \"-D 'x\""),
])
def test_options_the_flow_sets_are_refused(split, text, message):
    with pytest.raises(ValueError, match=f"^{re.escape(message)}$"):
        split(text)
