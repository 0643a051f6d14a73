"""The C header of the candidate record is generated from the gateware's layout
(dptbd.hw.candidate_layout): the checked-in copy is current, and C unpacks and packs every
payload exactly as the Python helpers of the gateware's testbenches do."""

import subprocess

import numpy as np
import pytest

from amaranth.hdl import unsigned
from amaranth.lib import data

from dptbd.config import DPConfig
from dptbd.dsp import record_header as rh
from dptbd.dsp.firmware import FIRMWARE_DIR, WARNING_FLAGS, find_compiler
from dptbd.hw.candidate_layout import (candidate_layout, pack_record, record_layout,
                                       unpack_candidate)

ROUND_TRIP = r"""
#include <inttypes.h>
#include <stdio.h>
#include "dptbd_candidate_record.h"
int main(void)
{
    uint64_t w;
    while (scanf("%" SCNu64, &w) == 1) {
        if (dptbd_payload_is_trailer(w)) {
            dptbd_fpga_trailer t = dptbd_unpack_trailer(w);
            printf("trailer %lu %lu %u %u %u %u %u\n", (unsigned long)t.count,
                   (unsigned long)t.threshold, (unsigned)t.overflow, (unsigned)t.primed,
                   (unsigned)t.aligned, (unsigned)t.missed, (unsigned)t.cut);
        } else {
            dptbd_fpga_record r = dptbd_unpack_record(w);
            printf("record %u %u %lu %u %" PRIu64 "\n", (unsigned)r.row, (unsigned)r.col,
                   (unsigned long)r.energy, (unsigned)r.direction, dptbd_pack_record(&r));
        }
    }
    return 0;
}
"""


def test_checked_in_header_is_current():
    text = (FIRMWARE_DIR / rh.HEADER_NAME).read_text()
    assert text == rh.candidate_record_header(DPConfig()), (
        "stale: python -m dptbd.dsp.record_header --out dptbd/dsp/firmware/"
        "dptbd_candidate_record.h")


def test_main_writes_the_header(tmp_path):
    assert rh.main(["--out", str(tmp_path / "h.h")]) == 0
    assert (tmp_path / "h.h").read_text() == rh.candidate_record_header()


@pytest.mark.parametrize("cfg", [DPConfig(), DPConfig(height=100, width=300),
                                 DPConfig(width=4096, height=4096, input_bits=16, energy_bits=32,
                                          radius=2)])
def test_c_unpacks_and_packs_like_the_gateware_helpers(cfg, tmp_path):
    rh.write_candidate_record_header(tmp_path / rh.HEADER_NAME, cfg)
    (tmp_path / "rt.c").write_text(ROUND_TRIP)
    exe = tmp_path / "rt"
    subprocess.run([find_compiler(), *WARNING_FLAGS, f"-I{tmp_path}", str(tmp_path / "rt.c"),
                    "-o", str(exe)], check=True)
    rng = np.random.default_rng(1)
    width = candidate_layout(cfg).size
    words = [int(rng.integers(0, 2 ** (width - 1))) | (int(rng.integers(0, 2)) << (width - 1))
             for _ in range(300)] + [0, 2 ** width - 1]
    out = subprocess.run([str(exe)], input=" ".join(map(str, words)), capture_output=True,
                         text=True, check=True).stdout.splitlines()
    assert len(out) == len(words)
    for word, line in zip(words, out):
        kind, fields = unpack_candidate(cfg, word)
        if kind == "trailer":
            assert line == "trailer " + " ".join(str(fields[k]) for k in rh.TRAILER_FIELDS)
        else:
            packed = pack_record(cfg, **fields)
            assert line == "record " + " ".join(str(fields[k]) for k in rh.RECORD_FIELDS) + \
                f" {packed}"


def test_signature_names_the_record_fields():
    assert rh.record_layout_signature(DPConfig()) == (35, 0, 7, 7, 7, 14, 16, 30, 4)


def test_layouts_the_firmware_cannot_hold_are_refused(monkeypatch):
    cfg = DPConfig()
    wide = data.StructLayout({"row": unsigned(17), "col": unsigned(7), "energy": unsigned(16),
                              "direction": unsigned(4)})
    monkeypatch.setattr(rh, "record_layout", lambda c: wide)
    monkeypatch.setattr(rh, "candidate_layout", lambda c: data.StructLayout({
        "body": data.UnionLayout({"record": wide}), "end_of_list": unsigned(1)}))
    monkeypatch.setattr(rh, "trailer_layout", lambda c: data.StructLayout({}))
    with pytest.raises(ValueError, match=r"^candidate record field row is 17 bits wide but the "
                                         r"tracker's CANDIDATE_DTYPE holds 16$"):
        rh.candidate_record_header(cfg)
    huge = data.StructLayout({"body": unsigned(64), "end_of_list": unsigned(1)})
    monkeypatch.setattr(rh, "candidate_layout", lambda c: huge)
    with pytest.raises(ValueError, match=r"^the candidate payload is 65 bits wide; the C header "
                                         r"holds a payload in a uint64_t \(at most 64 bits\)$"):
        rh.candidate_record_header(cfg)


def test_the_header_follows_the_gateware_layout():
    """A different frame size moves the fields in the header (one source)."""
    text = rh.candidate_record_header(DPConfig(height=100, width=300))
    layout = record_layout(DPConfig(height=100, width=300))
    assert f"#define DPTBD_RECORD_COL_WIDTH {layout['col'].width}\n" in text
    assert f"#define DPTBD_RECORD_ENERGY_OFFSET {layout['energy'].offset}\n" in text
