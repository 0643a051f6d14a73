"""The register map of the AXI top level (``dptbd_axi``), as data: the one source.

:func:`register_map` returns, for a :class:`~dptbd.config.DPConfig`, every register of the
AXI4-Lite control port: its byte address, its fields (bit position, width, kind, reset value,
allowed range, meaning) and the weight LUT's register window. Everything else reads it:

- the Amaranth register block (:mod:`dptbd.hw.register_file`) decodes it,
- ``docs/registers.md``, the C header ``dptbd_regs.h`` and the Python constants the
  testbenches use are rendered from it (:mod:`dptbd.hw.flow.register_export`).

The control port is AXI4-Lite with 32-bit data and byte addresses (``docs/integration.md``
says why). Every register is one aligned 32-bit word (:data:`BUS_RULES`: what the port
answers to unaligned, unmapped and window accesses). A field's *kind* says who writes it:

=========== ======= ==================================================================
kind        access  behaviour
=========== ======= ==================================================================
constant    ro      a build parameter; reads its reset value, writes are refused
setting     rw      a run-time setting driving the core; a write outside ``limits`` is
                    refused (value not taken, ``ERROR.write_refused`` set, SLVERR)
enable      rw      interrupt enable bit, any value taken
pulse       wo      writing 1 makes a one-cycle pulse; reads 0
counter     ro      32-bit event counter, wraps modulo 2**32, cleared by
                    ``CONTROL.clear_counters``; writes are refused
sticky      w1c     set by its event, cleared by writing 1 (a set in the same cycle wins)
interrupt   w1c     pending interrupt: as ``sticky``; ``irq`` = any pending & enabled
status      ro      the core's state now (a level, not latched); writes are refused
=========== ======= ==================================================================
"""

from __future__ import annotations

import dataclasses

from dptbd.config import DPConfig

__all__ = [
    "MAGIC",
    "MAP_VERSION",
    "BUS_RULES",
    "ADDRESS_BITS",
    "DATA_BITS",
    "COUNTER_BITS",
    "FIELD_KINDS",
    "FIELD_ACCESS",
    "EVENTS",
    "STORE_EVENTS",
    "FAULTS",
    "Field",
    "Register",
    "Window",
    "RegisterMap",
    "register_map",
]

#: ``ID`` register: ASCII "DPTB".
MAGIC = 0x44505442
#: (major, minor) of this map; major changes when an existing register moves or changes.
MAP_VERSION = (1, 1)
#: Byte-address bits of the control port: a 4 KiB window.
ADDRESS_BITS = 12
#: AXI4-Lite data width.
DATA_BITS = 32
#: Width of every counter.
COUNTER_BITS = 32
#: What the control port answers besides the field kinds (``docs/registers.md`` prints it).
BUS_RULES = (
    "An address that is not a multiple of 4 is unaligned: a read returns 0 with SLVERR, a "
    "write is refused (nothing changes, ERROR.write_refused set, SLVERR). Reading an "
    "unmapped address returns 0 with SLVERR; writing one is ignored with SLVERR. The LUT "
    "window is write-only: a read returns 0 with SLVERR; a write must strobe all four "
    "bytes (wstrb = 1111) and hold a code in range, else it is refused (entry unchanged, "
    "ERROR.write_refused set, SLVERR).")
#: Byte address of the weight LUT window's entry 0.
LUT_WINDOW_BASE = 0x400

FIELD_KINDS = ("constant", "setting", "enable", "pulse", "counter", "sticky", "interrupt",
               "status")
#: Bus access of each field kind.
FIELD_ACCESS = {"constant": "ro", "setting": "rw", "enable": "rw", "pulse": "wo", "counter": "ro",
           "sticky": "w1c", "interrupt": "w1c", "status": "ro"}

#: The frame-sync fault classes of the frame monitor (:mod:`dptbd.hw.frame_monitor`).
FAULTS = ("sof_unexpected", "frame_short", "frame_long", "line_length")
#: Event pulses the register block counts, in the order of its ``events`` port: the core's
#: (``frame_done`` … ``saturated``), the frame monitor's faults, and the stream stalls.
EVENTS = ("frame_done", "segment_done", "list_done", "saturated", *FAULTS,
          "input_stall", "output_stall")
#: Event pulses added by the build with the state store in external memory
#: (``--state-store axi``): an error response (SLVERR / DECERR) to a state read burst's beat
#: or a state write burst.
STORE_EVENTS = ("state_read_error", "state_write_error")


@dataclasses.dataclass(frozen=True)
class Field:
    """One bit field of a register.

    ``event`` names the pulse that counts / sets a ``counter``, ``sticky`` or ``interrupt``
    field: one of :data:`EVENTS`, ``"write_refused"`` or ``"fault"`` (any sticky bit set).
    ``limits`` is the allowed ``(lo, hi)`` of a ``setting``, checked on the whole written word;
    ``align`` (a setting's, optional): the written word must also be a multiple of it.
    """

    name: str
    lsb: int
    width: int
    kind: str
    reset: int
    doc: str
    limits: tuple[int, int] | None = None
    event: str | None = None
    align: int | None = None

    @property
    def mask(self) -> int:
        """The field's bits in the register word."""
        return ((1 << self.width) - 1) << self.lsb

    @property
    def access(self) -> str:
        return FIELD_ACCESS[self.kind]


@dataclasses.dataclass(frozen=True)
class Register:
    """One 32-bit register at byte ``address``; all its fields share one kind."""

    name: str
    address: int
    group: str
    doc: str
    fields: tuple[Field, ...]

    @property
    def kind(self) -> str:
        return self.fields[0].kind

    @property
    def access(self) -> str:
        return self.fields[0].access

    @property
    def reset(self) -> int:
        """The word read after reset."""
        return sum(f.reset << f.lsb for f in self.fields if f.kind != "pulse")


@dataclasses.dataclass(frozen=True)
class Window:
    """A write-only array of registers: entry i at ``base + 4 * i`` (reads answer SLVERR,
    a write must strobe every byte: :data:`BUS_RULES`)."""

    name: str
    base: int
    entries: int
    field: Field
    doc: str

    @property
    def end(self) -> int:
        """First byte address after the window."""
        return self.base + 4 * self.entries


@dataclasses.dataclass(frozen=True)
class RegisterMap:
    """Every register and window of one configuration."""

    registers: tuple[Register, ...]
    windows: tuple[Window, ...]
    address_bits: int = ADDRESS_BITS
    #: the event pulses the register block counts, in the order of its ``events`` port
    events: tuple[str, ...] = EVENTS

    def __getitem__(self, name: str) -> Register:
        for reg in self.registers:
            if reg.name == name:
                return reg
        raise KeyError(f"no register {name!r}; the map has "
                       f"{[r.name for r in self.registers]}")

    def window(self, name: str) -> Window:
        return next(w for w in self.windows if w.name == name)

    def fields(self, kind: str) -> list[tuple[Register, Field]]:
        """Every (register, field) of one kind, in address order."""
        return [(r, f) for r in self.registers for f in r.fields if f.kind == kind]


def _bits(hi: int) -> int:
    return max(1, int(hi).bit_length())


def _one(name, kind, reset, doc, *, width=32, limits=None, event=None, field=None):
    return (Field(field or name.lower(), 0, width, kind, reset, doc, limits, event),)


def _identification(cfg: DPConfig, k_max: int) -> list[tuple]:
    return [
        ("ID", "identification", "magic number, ASCII \"DPTB\"",
         _one("id", "constant", MAGIC, "0x44505442", field="magic")),
        ("VERSION", "identification", "register-map version",
         (Field("minor", 0, 16, "constant", MAP_VERSION[1], "minor version"),
          Field("major", 16, 16, "constant", MAP_VERSION[0], "major version"))),
        ("BUILD_FRAME", "identification", "frame size",
         (Field("width", 0, 16, "constant", cfg.width, "W, pixels per line"),
          Field("height", 16, 16, "constant", cfg.height, "H, lines per frame"))),
        ("BUILD_BITS", "identification", "arithmetic widths",
         (Field("input_bits", 0, 8, "constant", cfg.input_bits, "B_in"),
          Field("energy_bits", 8, 8, "constant", cfg.energy_bits, "B_E"),
          Field("weight_frac_bits", 16, 8, "constant", cfg.weight_frac_bits, "F"),
          Field("radius", 24, 8, "constant", cfg.radius, "r, search radius"))),
        ("BUILD_SEGMENT", "identification", "segment length",
         (Field("k_max", 0, 16, "constant", k_max, "K_max, largest run-time K"),
          Field("segment_frames", 16, 16, "constant", cfg.segment_frames,
                "K at reset"))),
        ("BUILD_CANDIDATES", "identification", "segmenter capacity",
         (Field("record_capacity", 0, 24, "constant", cfg.record_capacity,
                "C, largest run-time n, records per list"),
          Field("histogram_bits", 24, 8, "constant", cfg.histogram_bits,
                "b, 2**b histogram bins"))),
        ("BUILD_DEFAULTS", "identification", "segmenter settings at reset",
         (Field("candidate_count", 0, 24, "constant", cfg.n_candidates, "n at reset"),
          Field("histogram_shift", 24, 8, "constant", cfg.bin_shift, "s at reset"))),
        ("BUILD_LUT", "identification", "weight LUT window",
         (Field("lut_entries", 0, 16, "constant", cfg.lut_entries, "entries, (M+1)*M"),
          Field("weight_bits", 16, 8, "constant", cfg.weight_bits, "bits per code, F+1"))),
    ]


def _control(cfg: DPConfig, k_max: int) -> list[tuple]:
    return [
        ("CONTROL", "control", "write 1 to a bit for a one-cycle pulse; reads 0",
         (Field("soft_reset", 0, 1, "pulse", 0,
                "close the list being sent (a cut trailer) and, with m_axis_state, the line "
                "being sent (filler words), then reset the core and the frame monitor "
                "(resync); registers are kept"),
          Field("clear_counters", 1, 1, "pulse", 0, "set every counter to 0"))),
        ("SEGMENT_FRAMES", "control", "run-time K",
         _one("segment_frames", "setting", cfg.segment_frames, "K, frames per segment",
              width=16, limits=(1, k_max))),
        ("CANDIDATE_COUNT", "control", "run-time n",
         _one("candidate_count", "setting", cfg.n_candidates,
              "n, candidate points per list", width=_bits(cfg.record_capacity),
              limits=(0, cfg.record_capacity))),
        ("HISTOGRAM_SHIFT", "control", "run-time s",
         _one("histogram_shift", "setting", cfg.bin_shift, "s, E >> s is the histogram bin",
              width=_bits(cfg.energy_bits - 1), limits=(0, cfg.energy_bits - 1))),
        ("IRQ_ENABLE", "control", "interrupt mask: 1 lets the pending bit raise irq",
         (Field("segment_done", 0, 1, "enable", 0, "end of segment"),
          Field("fault", 1, 1, "enable", 0, "any ERROR bit set"))),
        ("VIDEO_INPUT", "control", "video source",
         _one("no_sof", "setting", 0,
              "1: the source sends no start-of-frame markers (tuser[0] held 0), so a "
              "missing start of frame is no fault (ERROR.frame_long never set); 0: every "
              "frame must start with tuser[0]", width=1, limits=(0, 1))),
    ]


def _status(cfg: DPConfig, store=None) -> list[tuple]:
    sticky = tuple(Field(name, i, 1, "sticky", 0, doc, event=name) for i, (name, doc) in
                   enumerate([*zip(FAULTS, ("start of frame in the middle of a line",
                                            "start of frame at the first column of lines "
                                            "1 ... H-1 (H-1 included): frame of fewer than "
                                            "H lines",
                                            "no start of frame where a frame should start: "
                                            "frame longer than W*H",
                                            "a line (the beats up to tlast) whose length "
                                            "is not W: one event per such line")),
                              ("write_refused", "a register write was refused")]))
    if store is not None:
        sticky += _store_sticky(len(sticky))
    counters = [("FRAMES", "frame_done", "frames output by the DP pipeline"),
                ("SEGMENTS", "segment_done", "segments output by the DP pipeline"),
                ("LISTS", "list_done", "candidate lists (trailers) sent"),
                ("SATURATED", "saturated", "state words whose E saturated at e_max"),
                *[(f"FAULT_{name.upper()}", name, f"ERROR.{name} events") for name in FAULTS],
                ("INPUT_STALLS", "input_stall",
                 "cycles with s_axis_video_tvalid high and tready low"),
                ("OUTPUT_STALLS", "output_stall",
                 "cycles with an output stalled (back-pressure): m_axis_cand, or "
                 "m_axis_state with --state-output, tvalid high and tready low")]
    return [
        ("ERROR", "status", "sticky error bits, write 1 to clear", sticky),
        ("IRQ_STATUS", "status", "pending interrupts, write 1 to clear",
         (Field("segment_done", 0, 1, "interrupt", 0, "a segment ended", event="segment_done"),
          Field("fault", 1, 1, "interrupt", 0, "an ERROR bit was set", event="fault"))),
        *[(name, "status", doc, _one(name, "counter", 0, doc, event=event, field="count"))
          for name, event, doc in counters],
        ("STATUS", "status", "the core's state now",
         (Field("soft_reset_busy", 0, 1, "status", 0,
                "a CONTROL.soft_reset is in progress: the list (with m_axis_state also the "
                "line) being sent is being closed (waiting for m_axis_cand_tready, "
                "m_axis_state_tready) and the input is held"),)),
    ]


def register_map(cfg: DPConfig, store=None) -> RegisterMap:
    """The register map of ``dptbd_axi`` built for ``cfg``; with ``store`` (an
    :class:`~dptbd.config.AxiStoreConfig` of ``cfg``) the map of the build with the state
    store in external memory (``--state-store axi``), which adds the registers of
    :func:`!_store_registers` after each group's own and the bits ``state_read`` /
    ``state_write`` to ``ERROR``.

    Identification registers from 0x000, control from 0x040, status from 0x080, the weight
    LUT window from 0x400 (entry ``cfg.lut_address(p, m)`` at ``0x400 + 4 * address``).

    Raises
    ------
    dptbd.errors.ConfigError
        ``store`` with more than 32 address bits (``STATE_BASE`` is one 32-bit register) or
        made for another configuration.
    """
    k_max = cfg.k_max
    registers = []
    groups = [_identification(cfg, k_max), _control(cfg, k_max), _status(cfg, store)]
    if store is not None:
        for group, extra in zip(groups, _store_registers(cfg, store)):
            group.extend(extra)
    for base, group in zip((0x000, 0x040, 0x080), groups):
        for i, (name, _group, doc, fields) in enumerate(group):
            registers.append(Register(name, base + 4 * i, _group, doc, fields))
    unity = 1 << cfg.weight_frac_bits
    lut = Window("LUT", LUT_WINDOW_BASE, cfg.lut_entries,
                 Field("code", 0, cfg.weight_bits, "setting", 0,
                       f"weight code c in [0, 2**F = {unity}], weight c / 2**F",
                       limits=(0, unity)),
                 "weight LUT entry [p, m] at LUT + 4 * (p * M + m) (DPConfig.lut_address); "
                 "write-only (reads SLVERR), whole-word writes (wstrb = 1111)")
    assert lut.end <= 1 << ADDRESS_BITS
    assert all(r.address < 0x040 for r in registers if r.group == "identification")
    assert all(r.address < 0x080 for r in registers if r.group == "control")
    events = EVENTS if store is None else (*EVENTS, *STORE_EVENTS)
    return RegisterMap(tuple(registers), (lut,), events=events)


#: Most address bits of the state store of ``dptbd_axi`` (``STATE_BASE`` is one register).
STORE_ADDRESS_BITS = 32


def _store_sticky(first_bit: int) -> tuple[Field, ...]:
    """The ``ERROR`` bits of the build with the state store in external memory."""
    return (Field("state_read", first_bit, 1, "sticky", 0,
                  "a state read burst was answered with SLVERR or DECERR (on any beat)",
                  event="state_read_error"),
            Field("state_write", first_bit + 1, 1, "sticky", 0,
                  "a state write burst was answered with SLVERR or DECERR",
                  event="state_write_error"))


def _store_registers(cfg: DPConfig, store) -> tuple[list, list, list]:
    """The registers the state store in external memory adds, per group (identification,
    control, status); see ``docs/integration.md``, "State store in external memory"."""
    from dptbd.errors import ConfigError

    if store.frame != cfg:
        raise ConfigError("the state store was made for another configuration than the "
                          "register map's")
    if store.address_bits > STORE_ADDRESS_BITS:
        raise ConfigError(
            f"address_bits={store.address_bits}: dptbd_axi's STATE_BASE register holds "
            f"{STORE_ADDRESS_BITS} bits; use address_bits <= {STORE_ADDRESS_BITS}")
    top = (1 << store.address_bits) - store.frame_bytes
    highest = top - top % store.burst_bytes
    identification = [
        ("BUILD_STATE_STORE", "identification", "the state store's AXI4 manager port",
         (Field("data_bits", 0, 8, "constant", store.data_bits, "data width"),
          Field("address_bits", 8, 8, "constant", store.address_bits, "address width"),
          Field("id_bits", 16, 8, "constant", store.id_bits, "ID width (ID 0 is used)"),
          Field("outstanding", 24, 8, "constant", store.outstanding,
                "most bursts in flight per direction"))),
        ("BUILD_STATE_LAYOUT", "identification", "the state's layout in memory",
         (Field("burst_beats", 0, 16, "constant", store.burst_beats, "beats of a full burst"),
          Field("slot_bits", 16, 8, "constant", store.slot_bits, "bits per state slot"))),
        ("BUILD_STATE_BYTES", "identification", "bytes of one frame's state",
         _one("frame_bytes", "constant", store.frame_bytes,
              "W * H * slot_bits / 8, from STATE_BASE")),
    ]
    control = [
        ("STATE_BASE", "control", "state store base address",
         (Field("state_base", 0, store.address_bits, "setting", store.base_address,
                f"byte address of pixel 0's state slot, a multiple of the burst size "
                f"({store.burst_bytes} bytes) with the frame's {store.frame_bytes} bytes "
                f"below 2**{store.address_bits}, else refused; taken by the store at the "
                f"next CONTROL.soft_reset (STATE_BASE_ACTIVE)",
                limits=(0, highest), align=store.burst_bytes),)),
    ]
    status = [
        *[(name, "status", doc, _one(name, "counter", 0, doc, event=event, field="count"))
          for name, event, doc in (
              ("STATE_READ_ERRORS", "state_read_error",
               "state read beats answered with SLVERR or DECERR"),
              ("STATE_WRITE_ERRORS", "state_write_error",
               "state write bursts answered with SLVERR or DECERR"))],
        ("STATE_BASE_ACTIVE", "status", "the state base address in use",
         (Field("state_base_active", 0, store.address_bits, "status", store.base_address,
                "the STATE_BASE the store uses: taken at aresetn and at every "
                "CONTROL.soft_reset"),)),
    ]
    return identification, control, status
