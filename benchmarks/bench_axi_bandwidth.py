"""External-memory bandwidth of the AXI4 state store (``hw/axi_store/pipeline.py``).

    python benchmarks/bench_axi_bandwidth.py

Every frame reads each pixel's state slot once and writes it once (``docs/gateware.md``,
"State store in external memory"), so the traffic is ``2 * AxiStoreConfig.frame_bytes``
per frame, computed here from the layout (no simulation) for the sizes and rates of the
sensor-scale goals, against the peak of one 16-bit DDR3-800 channel
(800 MT/s x 2 bytes = 1600 MB/s). Slots are the state width rounded up to a power of two
(:attr:`DPConfig.state_slot_bits`).
"""

from __future__ import annotations

import warnings

from dptbd.config import DPConfig, EnergyWidthWarning

DDR3_800_X16_MB_S = 800e6 * 2 / 1e6

#: (name, DPConfig fields, frames per second)
CASES = [
    ("640 x 512, 100 Hz", dict(width=640, height=512), 100),
    ("1280 x 1024, 200 Hz", dict(width=1280, height=1024), 200),
    ("1280 x 1024, 200 Hz, K = 64, B_in = 16", dict(width=1280, height=1024, segment_frames=64,
                                              input_bits=16, energy_bits=22), 200),
    ("4096 x 256, 1 kHz", dict(width=4096, height=256), 1000),
]


def main() -> None:
    print("| scene | state bits | slot bits | bytes read = written per frame | MB/s (read + write) "
          "| of one DDR3-800 x16 (1600 MB/s) |")
    print("|---|---|---|---|---|---|")
    for name, fields, rate in CASES:
        with warnings.catch_warnings():
            warnings.simplefilter("ignore", EnergyWidthWarning)
            cfg = DPConfig(**fields).build_config()
        store = cfg.axi_store()
        mb_s = 2 * store.frame_bytes * rate / 1e6
        print(f"| {name} | {cfg.state_bits} | {store.slot_bits} | {store.frame_bytes:,} | "
              f"{mb_s:,.0f} | {100 * mb_s / DDR3_800_X16_MB_S:.0f} % |")


if __name__ == "__main__":
    main()
