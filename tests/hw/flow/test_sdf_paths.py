"""``dptbd.hw.flow.sdf_paths``: the worst endpoints' longest paths of an SDF, with logic,
routing and the placement distance."""

import json

import pytest

from dptbd.hw.flow.sdf_paths import main, parse_sdf, placement, worst_paths

# r1 -> lut_a -> r2 (two routes), r1 -> lut_a -> lut_b -> r3; r3 -> r2 directly.
SDF = r"""(DELAYFILE
  (SDFVERSION "3.0")
  (DESIGN "top")
  (DIVIDER .)
  (TIMESCALE 1ps)
  (CELL (CELLTYPE "TRELLIS_FF") (INSTANCE r1)
    (DELAY (ABSOLUTE (IOPATH (posedge CLK) Q (400:500:500) (400:500:500)))))
  (CELL (CELLTYPE "TRELLIS_FF") (INSTANCE r\$2)
    (DELAY (ABSOLUTE (IOPATH (posedge CLK) Q (500:500:500) (500:500:500))))
    (TIMINGCHECK (SETUPHOLD DI (posedge CLK) (100:100:100) (0:0:0))))
  (CELL (CELLTYPE "TRELLIS_FF") (INSTANCE r3)
    (DELAY (ABSOLUTE (IOPATH (posedge CLK) Q (500:500:500) (500:500:500))))
    (TIMINGCHECK (SETUPHOLD DI (posedge CLK) (200:200:200) (0:0:0))))
  (CELL (CELLTYPE "TRELLIS_COMB") (INSTANCE lut_a)
    (DELAY (ABSOLUTE (IOPATH A F (200:250:300) (200:250:300)))))
  (CELL (CELLTYPE "TRELLIS_COMB") (INSTANCE lut_b)
    (DELAY (ABSOLUTE (IOPATH B F (300:300:300) (300:300:300)))))
  (CELL (CELLTYPE "top") (INSTANCE )
    (DELAY (ABSOLUTE
      (INTERCONNECT r1.Q lut_a.A (1000:1000:1000) (1000:1000:1000))
      (INTERCONNECT lut_a.F r\$2.DI (700:700:700) (900:900:900))
      (INTERCONNECT lut_a.F lut_b.B (2000:2000:2000) (2000:2000:2000))
      (INTERCONNECT lut_b.F r3.DI (100:100:100) (100:100:100))
      (INTERCONNECT r3.Q r\$2.DI (50:50:50) (50:50:50))
    ))
  )
)
"""

PLACED = {"modules": {"top": {"cells": {
    "r1": {"attributes": {"NEXTPNR_BEL": "X3/Y4/SLICEA"}},
    "r$2": {"attributes": {"NEXTPNR_BEL": "X10/Y2/SLICEB"}},
    "r3": {"attributes": {"NEXTPNR_BEL": "X3/Y20/SLICEC"}},
    "lut_a": {"attributes": {}}}}}}


def test_worst_endpoints_first_with_logic_routing_and_distance():
    paths = worst_paths(parse_sdf(SDF), placement(PLACED), n=5)
    # r3: 0.5 clock-to-out + 1.0 + 0.3 + 2.0 + 0.3 + 0.1 + 0.2 setup = 4.4 ns
    # r$2: 0.5 + 1.0 + 0.3 + 0.9 + 0.1 setup = 2.8 ns (beats r3.Q -> r$2: 0.5 + 0.05 + 0.1)
    assert [(p.start, p.end, p.cells, p.distance) for p in paths] == [
        ("r1", "r3", 4, 16), ("r1", "r$2", 3, 9)]
    assert [round(p.logic_ns, 6) for p in paths] == [1.3, 0.9]
    assert [round(p.routing_ns, 6) for p in paths] == [3.1, 1.9]
    assert [round(p.total_ns, 6) for p in paths] == [4.4, 2.8]
    assert [p.end for p in worst_paths(parse_sdf(SDF), n=1)] == ["r3"]
    assert worst_paths(parse_sdf(SDF))[0].distance is None


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
    assert lines[2] == "| 1 | `r1` | `r3` | 4.40 | 1.30 | 3.10 | 4 | 16 |"
    assert len(lines) == 3
