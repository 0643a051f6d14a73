"""The register block's harness (:mod:`dptbd.sim.formal.harnesses.registers`) converts and
asserts, for every storing field, that a refused write leaves it and that W1C bits clear only
on a written 1, and, as induction invariants, that a held AW's and the read being answered's
registered decodes are their addresses' and that ``busy`` is what it mirrors; its proof runs in ``tests/sim/formal/test_runner.py``."""

from dptbd.hw.register_map import register_map
from dptbd.sim.formal.harnesses.registers import RegistersHarness
from dptbd.sim.formal.harnesses.tiny import tiny_config


def test_the_registers_harness_asserts_every_storing_field(messages):
    got = messages(RegistersHarness())
    expected = {"LUT: written by a refused write", "AW outstanding != held",
                "W outstanding != held",
                "AR outstanding != the read being answered + rvalid",
                "busy != bvalid | rvalid | the read being answered",
                "read_unmapped != the read address's",
                "write_unaligned != the held address's", "write_at_lut != the held address's"}
    for reg in register_map(tiny_config()).registers:
        expected.add(f"write_at_{reg.name.lower()} != the held address's")
        expected.add(f"read_at_{reg.name.lower()} != the read address's")
        for field in reg.fields:
            what = f"{reg.name}.{field.name}"
            if field.kind == "setting" or field.kind == "enable":
                expected.add(f"{what}: changed by a refused write")
            if field.kind == "setting":
                expected.add(f"{what}: outside its limits")
                expected.add(f"write_ok_{reg.name.lower()} != the held W beat's check")
            elif field.kind in ("sticky", "interrupt"):
                expected.add(f"{what}: cleared by a refused write")
                expected |= {f"{what}[{bit}]: cleared without a written 1 (W1C)"
                             for bit in range(field.width)}
    assert {m for m in got if not m.startswith("s_axil")} == expected
    assert "IRQ_STATUS.segment_done[0]: cleared without a written 1 (W1C)" in expected
    assert "s_axil: write response without both AW and W accepted" in got


def test_the_bytes_harness_asserts_the_kept_flags(messages):
    """``bounds_registered=True``: also each setting's kept byte flags and a held W beat's
    flags, per limit byte of the field."""
    got = messages(RegistersHarness(bounds_registered=True))
    regmap = register_map(tiny_config())
    k = next(reg for reg in regmap.registers if reg.name == "SEGMENT_FRAMES")
    assert k.fields[0].limits[0] == 1                  # K has a lower limit: hi and lo flags
    for tag in ("hi", "lo"):
        for flag in ("in", "eq"):
            assert f"segment_frames_{tag}0_{flag} != the setting's byte's" in got
            assert f"segment_frames_{tag}0_{flag}_w != the held W beat's byte's" in got
