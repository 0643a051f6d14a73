"""ECP5 ``DP16KD`` block RAMs as a simple dual-port memory whose read goes through the block
RAM's own output register (``REGMODE_B = "OUTREG"``), which Yosys does not infer
(``docs/synthesis.md``, "Block RAM reads"): a read issued in cycle r (``read_en``) reaches
the output register at the end of r+1 (``out_en``), so the data come from a register in
r+2, without the ~5.8 ns clock-to-out of the array.

Port A writes, port B reads. The configuration is the widest whose depth holds the words
(18 x 1024, 9 x 2048, 4 x 4096, 2 x 8192, 1 x 16384), as many side by side as the width
needs; the address and data pins are those of Yosys's own mapping (ADx[13:k] the address
for ``k`` = 4, 3, 2, 1, 0; at 18 bits ADA[1:0] are the write's byte enables, both set).
"""

from __future__ import annotations

from amaranth.hdl import ClockSignal, Instance, Module, Signal

__all__ = ["DP16KD_CONFIGS", "DP16KD_MAX_DEPTH", "dp16kd_config", "dp16kd_memory"]

#: (data width, depth) of the DP16KD's true-dual-port configurations, widest first.
DP16KD_CONFIGS = ((18, 1024), (9, 2048), (4, 4096), (2, 8192), (1, 16384))
#: The deepest configuration.
DP16KD_MAX_DEPTH = 16384
_ADDRESS_LSB = {18: 4, 9: 3, 4: 2, 2: 1, 1: 0}


def dp16kd_config(depth: int) -> tuple[int, int]:
    """The (data width, depth) configuration for ``depth`` words: the widest that holds
    them. ``ValueError`` above 16384 words."""
    for config in DP16KD_CONFIGS:
        if depth <= config[1]:
            return config
    raise ValueError(f"depth must be an integer in [1, {DP16KD_MAX_DEPTH}] for one DP16KD "
                     f"bank, got {depth}")


def dp16kd_memory(m: Module, name: str, *, width: int, depth: int, read_addr, read_en,
                  out_en, write_addr, write_data, write_en, cell=None) -> Signal:
    """Build the DP16KDs of a ``width`` x ``depth`` memory in ``m``; return the output
    registers' data (``width`` bits).

    ``read_en`` registers ``read_addr`` (the array's read), ``out_en`` loads the output
    register with the array's word, both at the same edge; ``write_en`` writes
    ``write_data`` at ``write_addr``. ``cell(**ports)`` builds one DP16KD from
    ``Instance`` keyword arguments (default ``Instance("DP16KD", …)``; tests pass a
    behavioural model).
    """
    cell = cell or (lambda **ports: Instance("DP16KD", **ports))
    data_width, _ = dp16kd_config(depth)
    lsb = _ADDRESS_LSB[data_width]
    out = Signal(width, name=f"{name}_data")
    write_bits = write_data.as_value() if hasattr(write_data, "as_value") else write_data
    for index, low in enumerate(range(0, width, data_width)):
        bits = min(data_width, width - low)
        ports = {
            "p_DATA_WIDTH_A": data_width, "p_DATA_WIDTH_B": data_width,
            "p_REGMODE_A": "NOREG", "p_REGMODE_B": "OUTREG",
            "p_RESETMODE": "SYNC", "p_GSR": "DISABLED",
            "p_CSDECODE_A": "0b000", "p_CSDECODE_B": "0b000",
            "p_WRITEMODE_A": "NORMAL", "p_WRITEMODE_B": "NORMAL",
            "i_CLKA": ClockSignal("sync"), "i_CEA": 1, "i_OCEA": 1, "i_RSTA": 0,
            "i_WEA": write_en,
            "i_CLKB": ClockSignal("sync"), "i_CEB": read_en, "i_OCEB": out_en, "i_RSTB": 0,
            "i_WEB": 0,
        }
        for k in range(3):
            ports[f"i_CSA{k}"] = 0
            ports[f"i_CSB{k}"] = 0
        for k in range(14):
            if k < lsb:                 # x18: the byte enables of the write; else unused
                ports[f"i_ADA{k}"] = 1 if data_width == 18 and k < 2 else 0
                ports[f"i_ADB{k}"] = 0
            else:
                a = k - lsb
                ports[f"i_ADA{k}"] = write_addr[a] if a < len(write_addr) else 0
                ports[f"i_ADB{k}"] = read_addr[a] if a < len(read_addr) else 0
        for k in range(data_width):
            ports[f"i_DIA{k}"] = write_bits[low + k] if k < bits else 0
        for k in range(bits):
            ports[f"o_DOB{k}"] = out[low + k]
        m.submodules[f"{name}_{index}"] = cell(**ports)
    return out
