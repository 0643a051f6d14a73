"""``dptbd.hw.flow.sdf_paths``: the worst endpoints' longest paths of an SDF, with logic,
routing and the placement distance."""

import json

import pytest

from dptbd.hw.flow.sdf_paths import main, parse_sdf, placement, signal, worst_paths

# nextpnr-ecp5's form: r1 -> lut_a -> r$2 (the worse of rise and fall), r1 -> lut_a ->
# lut_b -> r3; r3 -> r$2 directly; r1 a register with a clock enable and no path into it.
SDF = r"""(DELAYFILE
  (SDFVERSION "3.0")
  (DESIGN "top")
  (DIVIDER /)
  (TIMESCALE 1ps)
  (CELL (CELLTYPE "TRELLIS_FF") (INSTANCE r1)
    (DELAY (ABSOLUTE (IOPATH CLK Q (400:500:500) (400:500:500))))
    (TIMINGCHECK (SETUPHOLD (posedge CE) (posedge CLK) (0:0:0) (90:90:90))))
  (CELL (CELLTYPE "TRELLIS_FF") (INSTANCE r\$2)
    (DELAY (ABSOLUTE (IOPATH CLK Q (500:500:500) (500:500:500))))
    (TIMINGCHECK (SETUPHOLD (posedge DI) (posedge CLK) (100:100:100) (0:0:0))))
  (CELL (CELLTYPE "TRELLIS_FF") (INSTANCE r3)
    (DELAY (ABSOLUTE (IOPATH CLK Q (500:500:500) (500:500:500))))
    (TIMINGCHECK (SETUPHOLD (posedge DI) (posedge CLK) (200:200:200) (0:0:0))))
  (CELL (CELLTYPE "TRELLIS_FF") (INSTANCE q_TRELLIS_FF_Q_1)
    (DELAY (ABSOLUTE (IOPATH CLK Q (500:500:500) (500:500:500))))
    (TIMINGCHECK (SETUPHOLD (posedge M) (posedge CLK) (0:0:0) (0:0:0))))
  (CELL (CELLTYPE "TRELLIS_FF") (INSTANCE q_TRELLIS_FF_Q_2)
    (DELAY (ABSOLUTE (IOPATH CLK Q (500:500:500) (500:500:500))))
    (TIMINGCHECK (SETUPHOLD (posedge M) (posedge CLK) (0:0:0) (0:0:0))))
  (CELL (CELLTYPE "TRELLIS_COMB") (INSTANCE lut_a)
    (DELAY (ABSOLUTE (IOPATH A F (200:250:300) (200:250:300)))))
  (CELL (CELLTYPE "TRELLIS_COMB") (INSTANCE lut_b)
    (DELAY (ABSOLUTE (IOPATH B F (300:300:300) (300:300:300)))))
  (CELL (CELLTYPE "top") (INSTANCE )
    (DELAY (ABSOLUTE
      (INTERCONNECT r1/Q lut_a/A (1000:1000:1000) (1000:1000:1000))
      (INTERCONNECT lut_a/F r\$2/DI (700:700:700) (900:900:900))
      (INTERCONNECT lut_a/F lut_b/B (2000:2000:2000) (2000:2000:2000))
      (INTERCONNECT lut_b/F r3/DI (100:100:100) (100:100:100))
      (INTERCONNECT r3/Q r\$2/DI (50:50:50) (50:50:50))
      (INTERCONNECT r1/Q q_TRELLIS_FF_Q_1/M (100:100:100) (100:100:100))
      (INTERCONNECT r1/Q q_TRELLIS_FF_Q_2/M (200:200:200) (200:200:200))
    ))
  )
)
"""

PLACED = {"modules": {"top": {"cells": {
    "r1": {"attributes": {"NEXTPNR_BEL": "X3/Y4/SLICEA"}},
    "r$2": {"attributes": {"NEXTPNR_BEL": "X10/Y2/SLICEB"}},
    "r3": {"attributes": {"NEXTPNR_BEL": "X3/Y20/SLICEC"}},
    "lut_a": {"attributes": {}},
    "q_TRELLIS_FF_Q_1": {"attributes": {"NEXTPNR_BEL": "X4/Y4/SLICEA"}},
    "q_TRELLIS_FF_Q_2": {"attributes": {"NEXTPNR_BEL": "X3/Y6/SLICEA"}}}}}}


def test_worst_endpoints_first_with_logic_routing_and_distance():
    paths = worst_paths(parse_sdf(SDF), placement(PLACED), n=5)
    # r3: 0.5 clock-to-out + 1.0 + 0.3 + 2.0 + 0.3 + 0.1 + 0.2 setup = 4.4 ns
    # r$2: 0.5 + 1.0 + 0.3 + 0.9 + 0.1 setup = 2.8 ns (beats r3.Q -> r$2: 0.5 + 0.05 + 0.1)
    # q (two bits, one row): the worse bit, 0.5 + 0.2 = 0.7 ns
    assert [(p.start, p.end, p.cells, p.distance, p.bits) for p in paths] == [
        ("r1", "r3", 4, 16, 1), ("r1", "r$2", 3, 9, 1), ("r1", "q_TRELLIS_FF_Q_2", 2, 2, 2)]
    assert [round(p.logic_ns, 6) for p in paths] == [1.3, 0.9, 0.5]
    assert [round(p.routing_ns, 6) for p in paths] == [3.1, 1.9, 0.2]
    assert [round(p.total_ns, 6) for p in paths] == [4.4, 2.8, 0.7]
    assert [p.span for p in paths] == [None, None, 2]     # lut_a is not placed
    assert [p.nets for p in paths] == [3, 2, 1]
    assert [p.end for p in worst_paths(parse_sdf(SDF), n=1)] == ["r3"]
    assert worst_paths(parse_sdf(SDF))[0].distance is None


def test_span_follows_the_cells():
    tiles = placement(PLACED) | {"lut_a": (10, 10), "lut_b": (3, 10)}
    paths = worst_paths(parse_sdf(SDF), tiles, n=2)
    # r1 (3, 4) -> lut_a (10, 10) -> lut_b (3, 10) -> r3 (3, 20): 13 + 7 + 10
    assert [p.span for p in paths] == [30, 13 + 8]
    assert signal("a.b_TRELLIS_FF_Q_12") == signal("a.b_TRELLIS_FF_Q") == "a.b"


def test_unbalanced_sdf_is_refused():
    with pytest.raises(ValueError, match=r"^SDF: unbalanced '\('$"):
        parse_sdf("(DELAYFILE (CELL ")
    with pytest.raises(ValueError, match=r"^SDF: unbalanced '\)'$"):
        parse_sdf("(DELAYFILE))")


def test_command_prints_the_table(tmp_path, capsys):
    (tmp_path / "r.sdf").write_text(SDF)
    (tmp_path / "p.json").write_text(json.dumps(PLACED))
    assert main([str(tmp_path / "r.sdf"), str(tmp_path / "p.json"), "-n", "1"]) == 0
    lines = capsys.readouterr().out.splitlines()
    assert lines[2] == "| 1 | `r1` | `r3` | 1 | 4.40 | 1.30 | 3.10 | 3 | 4 | 16 | — |"
    assert len(lines) == 3
