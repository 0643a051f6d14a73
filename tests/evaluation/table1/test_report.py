"""dptbd.evaluation.table1.report: paper 001's Table 1 beside the measured rows."""

from dptbd.evaluation.metrics import DetectionCounts
from dptbd.evaluation.table1.experiment import DETECTORS, PAPER_TABLE1, Table1Row
from dptbd.evaluation.table1.report import format_table


def test_one_setting_row_beside_the_paper():
    (snr, vel), paper = next(iter(PAPER_TABLE1.items()))
    rows = [Table1Row(snr, vel, name, DetectionCounts(12, 24, 48, 24)) for name in DETECTORS]
    lines = format_table(rows).splitlines()
    assert lines[0] == ("| SNR | V | paper Pd | paper false pts | " + " | ".join(
        f"{n} Pd [95% CI] | {n} false pts" for n in DETECTORS) + " |")
    assert len(lines) == 3
    assert lines[2] == (f"| {snr} | ({vel[0]:g}, {vel[1]:g}) | {paper[1]:.2f} | {paper[2]:.1f} | "
                        + " | ".join(["0.50 [0.31, 0.69] | 2.0"] * len(DETECTORS)) + " |")
