"""``dptbd.hw.flow.variants``: every variant's Verilog is module ``dptbd_dp`` with the ports
its description promises (no tools needed)."""

import re

import pytest

from dptbd.config import DPConfig
from dptbd.hw.flow.variants import SEGMENTER_TOPS, VARIANTS, variant_verilog

# the smallest frame the AXI4 state store's default bursts allow
CFG = DPConfig(width=16, height=12, segment_frames=2, input_bits=6, energy_bits=8)
FOLDED = ("axi-ext", "core-folded", "dp-axi", "axi-store")


def ports(text):
    head = re.search(r"^module dptbd_dp\((.*?)\);", text, re.M | re.S)
    assert head is not None, "no module dptbd_dp"
    return [p.strip() for p in head.group(1).split(",")]


@pytest.fixture(scope="module")
def verilog(tmp_path_factory):
    texts, manifests = {}, {}
    for variant in VARIANTS:
        work = tmp_path_factory.mktemp(variant)
        texts[variant] = variant_verilog(CFG, variant, "auto", {}, work)
        manifests[variant] = sorted(p.name for p in work.iterdir())
    return texts, manifests


def test_every_variant_is_module_dptbd_dp_with_its_ports(verilog):
    texts, manifests = verilog
    for variant in VARIANTS:
        names = ports(texts[variant])
        if variant in FOLDED:   # folded onto two pins beside the clock and reset
            assert len(names) == 4, (variant, names)
        else:
            assert len(names) > 4, (variant, names)
        external = any(name.startswith("state_store__") for name in names)
        assert external == (variant in ("core", "core-regio", "segmenter-ext")), variant
        # the manifest beside the Verilog for the two DP tops only
        assert manifests[variant] == (["dptbd_dp.json"] if variant in ("core", "top") else [])
    for wrapped, bare in (("core-regio", "core"), ("axi-regio", "axi")):
        assert ports(texts[wrapped]) == ports(texts[bare])
        assert texts[wrapped] != texts[bare]


def test_segmenter_tops_are_the_variants_with_candidates_out(verilog):
    texts, _ = verilog
    for variant in VARIANTS:
        names = ports(texts[variant])
        if variant not in FOLDED:
            candidates = any("cand" in name for name in names)
            states = any(name.startswith("states__") for name in names)
            assert (candidates, states) == ((True, False) if variant in SEGMENTER_TOPS
                                            else (False, True)), variant
