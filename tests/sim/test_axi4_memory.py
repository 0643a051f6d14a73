"""dptbd.sim.axi4_memory: the rules it checks refuse what breaks them, with a clear message."""

import pytest

from dptbd.config import DPConfig
from dptbd.hw.axi_store.bus import BURST_INCR, RESP_DECERR, RESP_SLVERR
from dptbd.sim.axi4_memory import Axi4Memory, AxiRuleError
from helpers.refusals import whole

STORE = DPConfig(width=64, height=64).axi_store(data_bits=64, burst_beats=16,
                                                base_address=0x1000)   # 16 KiB from 0x1000


@pytest.mark.parametrize("args, message", [
    (("AR", 0x1000, 15, 3, 0b00), "AR: burst type 0, expected INCR"),
    (("AW", 0x1000, 15, 2, BURST_INCR), "AW: size 2, expected full beats"),
    (("AR", 0x1004, 0, 3, BURST_INCR), "AR: address 0x1004 not aligned to the beat"),
    (("AR", 0x1000, 256, 3, BURST_INCR), "AR: 257 beats > 256"),
    (("AW", 0x1f80, 16, 3, BURST_INCR),
     "AW: burst at 0x1f80 of 17 beats crosses a 4 KB boundary"),
    (("AR", 0x0ff8, 0, 3, BURST_INCR), "AR: burst at 0xff8 outside the frame's state"),
])
def test_address_rules(args, message):
    memory = Axi4Memory(None, STORE)
    with pytest.raises(AxiRuleError, match=whole(message)):
        memory.check_address(*args)


def test_a_legal_burst_passes():
    Axi4Memory(None, STORE).check_address("AW", 0x1f80, 15, 3, BURST_INCR)


@pytest.mark.parametrize("lasts, message", [
    ([0, 1], "W: WLAST 1 on beat 2 of 3"),
    ([0, 0, 0], "W: WLAST 0 on beat 3 of 3"),
])
def test_wlast_must_mark_exactly_the_last_beat(lasts, message):
    memory = Axi4Memory(None, STORE)
    memory.write_bursts.append([0x1000, 3, []])
    memory.write_data.extend((k, last) for k, last in enumerate(lasts))
    with pytest.raises(AxiRuleError, match=whole(message)):
        memory.take_write_beats()


def test_held_payload_rule():
    Axi4Memory.check_held("AR", None, (1, 2))
    Axi4Memory.check_held("AR", (1, 2), (1, 2))
    with pytest.raises(AxiRuleError, match=whole(
            "AR: valid or payload changed before the handshake ((1, 2) -> (1, 3))")):
        Axi4Memory.check_held("AR", (1, 2), (1, 3))


def test_error_responses_cover_the_addresses_of_a_burst():
    memory = Axi4Memory(None, STORE, errors={0x1010: RESP_SLVERR, 0x1100: RESP_DECERR})
    assert memory.resp(0x1000, 2) == 0                  # bytes 0x1000 … 0x100f
    assert memory.resp(0x1000, 3) == RESP_SLVERR        # … 0x1017
    assert memory.resp(0x1000, 64) == RESP_DECERR       # both: the worse
