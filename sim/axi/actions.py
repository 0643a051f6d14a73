"""The register traffic of a random AXI run (:func:`dptbd.sim.axi.runs.draw_run`):
:class:`Drawer` draws the steps' actions (settings, refused writes, strobes, ``no_sof``,
``IRQ_ENABLE``, LUT tables and entries, refused bus accesses, checked reads) tracking what
the registers hold, and :func:`fill_checks` fills in the reads only the model knows (ERROR,
the fault counters). Both take the build's register map: with ``store`` (the
:class:`~dptbd.config.AxiStoreConfig` of a ``--state-store axi`` build) the store's
registers are mapped (not drawn as unmapped), read by the checks, and ``STATE_BASE``
draws refused writes of its own (:data:`STORE_REFUSALS`)."""

from __future__ import annotations

import numpy as np

from dptbd.config import DPConfig
from dptbd.hw.register_map import FAULTS, register_map
from dptbd.sim.axi.stimulus import SETTINGS, Beats
from dptbd.sim.verilator.axi import OKAY, SLVERR

__all__ = ["ACTIONS", "REFUSALS", "STORE_REFUSALS", "Drawer", "fill_checks"]

#: What a run's steps do besides the checked reads, counted in :attr:`AxiPlan.drawn`.
ACTIONS = ("settings", "no_strobe", "no_sof", "irq_enable", "lut_table", "lut_entry",
           "soft_reset", "soft_reset_now", "aresetn", "aresetn_now",
           "clear_counters", "w1c_error", "w1c_irq", "check")
#: The refused accesses, counted in :attr:`AxiPlan.drawn`: a setting out of range, a
#: setting's strobed byte out of range, a LUT code out of range, a LUT write without all
#: strobes, an unaligned write / read, a read of the LUT window, a read / write of an
#: unmapped address, a write to a read-only register.
REFUSALS = ("setting_range", "setting_strobe", "lut_code", "lut_strobe", "unaligned_write",
            "unaligned_read", "lut_read", "unmapped_read", "unmapped_write", "read_only_write")
#: The refused accesses a store build's runs add, counted in :attr:`AxiPlan.drawn`: a
#: ``STATE_BASE`` write that is not a multiple of the burst size, one above the highest
#: base (each refused with SLVERR, ``ERROR.write_refused`` set, the base kept).
STORE_REFUSALS = ("state_base_unaligned", "state_base_range")
#: Probability that a refused bus access of a store build's run is a ``STATE_BASE`` one.
STATE_BASE_SHARE = 0.3




class Drawer:
    """Draws the steps' actions, tracking what the registers hold."""

    def __init__(self, cfg: DPConfig, rng, drawn, aux=None, store=None):
        self.cfg, self.rng, self.drawn, self.store = cfg, rng, drawn, store
        self.aux = aux if aux is not None else rng     # draws added later: their own stream
        self.map = register_map(cfg, store)
        self.unity = 1 << cfg.weight_frac_bits
        self.reset_values()
        mapped = {r.address for r in self.map.registers}
        lut = self.map.window("LUT")
        self.unmapped = [a for a in range(0, 1 << self.map.address_bits, 4)
                         if a not in mapped and not lut.base <= a < lut.end]
        taken = mapped | set(range(lut.base, lut.end, 4))
        #: unmapped words next to a register or the LUT window (decoders' edges)
        self.edges = [a for a in self.unmapped if a - 4 in taken or a + 4 in taken]
        self.lut = lut

    def reset_values(self):
        """The writable registers' values after ``aresetn``."""
        names = (*SETTINGS, "VIDEO_INPUT", "IRQ_ENABLE",
                 *(("STATE_BASE",) if self.store is not None else ()))
        self.values = {name: self.map[name].reset for name in names}

    def pick(self, seq):
        return seq[int(self.rng.integers(0, len(seq)))]

    def settings(self, step):
        rng, writes = self.rng, step.setdefault("writes", [])
        for name in rng.permutation(list(SETTINGS))[:int(rng.integers(1, 4))]:
            lo, hi = self.map[name].fields[0].limits
            choices = [lo, hi, int(rng.integers(lo, hi + 1))]
            if name == "HISTOGRAM_SHIFT":        # mostly near the build's s: lists with records
                s = self.map[name].reset
                choices += [s, s, max(lo, s - 1), min(hi, s + 1)]
            elif name == "CANDIDATE_COUNT":      # small n: lists of exactly n records
                choices += [min(hi, 1), min(hi, 2)]
            value = int(self.pick(choices))
            writes.append([str(name), value])
            self.values[name] = value
        self.drawn["settings"] += 1

    def refused_setting(self, step):
        name = self.pick([*SETTINGS, "VIDEO_INPUT"])
        lo, hi = self.map[name].fields[0].limits
        value = self.pick(([lo - 1] if lo > 0 else []) + [hi + 1, 2**32 - 1])
        step.setdefault("writes", []).append([name, int(value)])
        self.drawn["setting_range"] += 1

    def strobed(self, step):
        """A setting written through one strobed byte: out of range (refused) or no strobe
        at all (taken, nothing changes)."""
        name = self.pick([*SETTINGS, "VIDEO_INPUT"])
        address = self.map[name].address
        if self.rng.random() < 0.5:
            lane = int(self.rng.integers(1, 4))
            assert self.map[name].fields[0].limits[1] < 256
            step.setdefault("bus", []).append(["w", address, 2**32 - 1, 1 << lane, SLVERR])
            self.drawn["setting_strobe"] += 1
        else:
            data = int(self.rng.integers(0, 2**32))
            step.setdefault("bus", []).append(["w", address, data, 0, OKAY])
            self.drawn["no_strobe"] += 1

    def no_sof(self, step):
        value = 1 - self.values["VIDEO_INPUT"]
        step.setdefault("writes", []).append(["VIDEO_INPUT", value])
        self.values["VIDEO_INPUT"] = value
        self.drawn["no_sof"] += 1

    def irq_enable(self, step):
        value = int(self.rng.integers(0, 2**32))
        step.setdefault("writes", []).append(["IRQ_ENABLE", value])
        self.values["IRQ_ENABLE"] = value & 3
        self.drawn["irq_enable"] += 1

    def lut_table(self, step):
        cfg, rng = self.cfg, self.rng
        codes = rng.integers(0, self.unity + 1, size=(cfg.n_moves + 1, cfg.n_moves))
        codes.flat[rng.integers(0, codes.size, size=2)] = [0, self.unity]
        step["lut_codes"] = codes.tolist()
        self.drawn["lut_table"] += 1

    def lut_entries(self, step):
        cfg, rng = self.cfg, self.rng
        top = (1 << cfg.weight_bits) - 1
        for _ in range(int(rng.integers(1, 5))):
            p, m = int(rng.integers(0, cfg.n_moves + 1)), int(rng.integers(0, cfg.n_moves))
            code = int(self.pick([0, self.unity, int(rng.integers(0, self.unity + 1)),
                                  self.unity + 1, top, 2**32 - 1]))
            strobe = 0xF if rng.random() < 0.75 else int(self.pick([0, 1, 7, 8, 0xE]))
            step.setdefault("lut_writes", []).append([p, m, code, strobe])
            if strobe != 0xF:
                self.drawn["lut_strobe"] += 1
            elif code > self.unity:
                self.drawn["lut_code"] += 1
            else:
                self.drawn["lut_entry"] += 1

    def bus(self, step):
        rng, ops = self.rng, step.setdefault("bus", [])
        if self.store is not None and self.aux.random() < STATE_BASE_SHARE:
            self.state_base(ops)
            return
        kind = self.pick(REFUSALS[4:])
        reg = self.pick(self.map.registers)
        if kind == "unaligned_write":
            ops.append(["w", reg.address + int(rng.integers(1, 4)),
                        int(rng.integers(0, 2**32)), 0xF, SLVERR])
        elif kind == "unaligned_read":
            ops.append(["r", reg.address + int(rng.integers(1, 4)), SLVERR, 0])
        elif kind == "lut_read":
            ops.append(["r", self.lut.base + 4 * int(rng.integers(0, self.lut.entries)),
                        SLVERR, 0])
        elif kind == "unmapped_read":
            ops.append(["r", self.pick(self.unmapped), SLVERR, 0])
        elif kind == "unmapped_write":
            address, data = self.pick(self.unmapped), int(rng.integers(0, 2**32))
            if self.aux.random() < 0.5:          # next to a decoded range, a word a LUT
                address = self.edges[int(self.aux.integers(0, len(self.edges)))]
                data = int(self.aux.integers(0, self.unity + 1))   # entry would take
            ops.append(["w", address, data, 0xF, SLVERR])
        else:                                    # a constant, a counter or the status
            ro_kind = self.pick(["constant", "counter", "status"])
            ro = [r for r in self.map.registers if r.access == "ro" and r.kind == ro_kind]
            ops.append(["w", self.pick(ro).address, int(rng.integers(0, 2**32)), 0xF,
                        SLVERR])
        self.drawn[kind] += 1

    def state_base(self, ops):
        """A refused ``STATE_BASE`` write (store builds): a base in range that is not a
        multiple of the burst size, or one above the highest (an aligned one above it half
        the time, else all ones)."""
        aux, field = self.aux, self.map["STATE_BASE"].fields[0]
        lo, hi = field.limits
        if aux.random() < 0.5:
            value = int(aux.integers(lo // field.align, hi // field.align + 1)) * field.align \
                + int(aux.integers(1, field.align))
            kind = "state_base_unaligned"
        else:
            value = hi + field.align if aux.random() < 0.5 and hi + field.align < 2**32 \
                else 2**32 - 1
            kind = "state_base_range"
        ops.append(["w", self.map["STATE_BASE"].address, value, 0xF, SLVERR])
        self.drawn[kind] += 1

    def check(self, step):
        """Reads of every readable register: the values known now, the rest filled in by
        :func:`fill_checks` (ERROR, fault counters) or left unchecked (None)."""
        want = {}
        for reg in self.map.registers:
            if reg.kind == "constant":
                want[reg.name] = reg.reset
            elif reg.name in self.values:
                want[reg.name] = self.values[reg.name]
            elif reg.name == "STATE_BASE_ACTIVE":  # the build's: no base write is taken
                want[reg.name] = reg.reset
            elif reg.name in ("STATE_READ_ERRORS", "STATE_WRITE_ERRORS"):
                want[reg.name] = 0               # the drawn runs' memory answers OKAY
            elif reg.kind in ("pulse", "status"):
                want[reg.name] = 0               # pulses read 0; no soft reset in progress
            elif reg.name == "ERROR" or reg.name.startswith("FAULT_"):
                want[reg.name] = "model"
            else:
                want[reg.name] = None
        step["check"] = want
        self.drawn["check"] += 1


def fill_checks(cfg: DPConfig, beats: Beats, steps: list[dict], store=None) -> np.ndarray:
    """ERROR and FAULT_* of every check from the frame monitor's pulses
    (:func:`~dptbd.sim.verilator.axi.fault_pulse_array`, returned), refused writes, W1C
    clears and counter clears, in the order :func:`~dptbd.sim.verilator.axi.step_operations`
    performs them; ``store``: the build's state store (its map), if any."""
    from dptbd.sim.verilator.axi import fault_pulse_array

    regmap = register_map(cfg, store)
    error = {f.name: f for f in regmap["ERROR"].fields}
    pulses = fault_pulse_array(cfg, beats, steps)
    seen = np.cumsum(np.vstack([np.zeros((1, len(FAULTS)), np.int64), pulses]), axis=0)
    counted_from = 0                                  # beat of the last clear_counters
    cleared_at = {name: 0 for name in FAULTS}         # beat of each bit's last W1C
    refused = False
    unity = 1 << cfg.weight_frac_bits
    start = 0
    for step in steps:
        check = step.get("check") or {}
        for i, name in enumerate(FAULTS):
            if check.get(f"FAULT_{name.upper()}") == "model":
                check[f"FAULT_{name.upper()}"] = int(seen[start, i] - seen[counted_from, i])
        if check.get("ERROR") == "model":
            word = sum(error[name].mask for i, name in enumerate(FAULTS)
                       if seen[start, i] > seen[cleared_at[name], i])
            check["ERROR"] = word | (error["write_refused"].mask if refused else 0)
        if step.get("aresetn"):                   # everything but the LUT back to reset
            counted_from, refused = start, False
            cleared_at = {name: start for name in FAULTS}
        if step.get("clear_counters"):
            counted_from = start
        for name, value in step.get("writes", []):
            reg = regmap[name]
            if reg.kind == "setting":
                lo, hi = reg.fields[0].limits
                refused |= not lo <= value <= hi
        for p, m, code, strobe in step.get("lut_writes", []):
            refused |= strobe != 0xF or not 0 <= code <= unity
        for kind, address, *rest in step.get("bus", []):
            if kind != "w":
                continue
            if address % 4:
                refused = True
            elif address == regmap["ERROR"].address:
                data = rest[0]
                for i, name in enumerate(FAULTS):
                    if data >> error[name].lsb & 1:
                        cleared_at[name] = start
                if data >> error["write_refused"].lsb & 1:
                    refused = False
            elif rest[2] == SLVERR and any(r.address == address and r.kind == "setting"
                                           for r in regmap.registers):
                refused = True
        start = step["stop"]
    return pulses
