"""What ``dptbd.sim.benches.axi.soft_reset_sweep`` checks of ``dptbd_axi``'s outputs around a soft
reset: the AXI4-Stream rules on every cycle (:class:`PortWatch`) and, per iteration, the
candidate lists (:func:`score_iteration`: whole, or the model's lists up to one cut by the
cut trailer) and the ``m_axis_state`` words (:func:`score_state_iteration`: lines of W words
with ``tlast``, the model's words, then filler words completing the last line).

Plain Python on the values the cocotb bench samples; no simulator needed to import it.
"""

from __future__ import annotations

import random

from dptbd.hw.layouts import pack_states

__all__ = ["PortWatch", "score_state_iteration", "score_iteration"]


class PortWatch:
    """One AXI4-Stream output of ``tb_axi.soft_reset_sweep``: its random ``tready`` (restarted
    from ``seed`` at every iteration), the AXI4-Stream rules checked on every cycle, and the
    transfers of the iteration."""

    FIELDS = ("tvalid", "tdata", "tuser", "tlast")

    def __init__(self, dut, prefix: str, pause: float, seed: int, problems: list):
        self.prefix, self.pause, self.seed, self.problems = prefix, pause, seed, problems
        self.handles = {f: getattr(dut, f"{prefix}_{f}") for f in self.FIELDS}
        self.tready = getattr(dut, f"{prefix}_tready")
        self.tready.value = 0
        self.previous = None       # (tvalid, tready, tdata, tuser, tlast) of the last cycle
        self.restart()

    def restart(self) -> None:
        self.rng = random.Random(self.seed)
        self.words = []            # (tdata, tuser, tlast) of every transfer
        self.timeline = []         # [cycle n, tready, tlast] of every cycle with tvalid

    def drive(self) -> int:
        self.ready = int(self.rng.random() >= self.pause)
        self.tready.value = self.ready
        return self.ready

    def sample(self, value, cycle: int, n: int | None) -> None:
        """After the edge of the cycle driven last: check and record it."""
        valid, data, user, last = (value(self.handles[f]) for f in self.FIELDS)
        now = (valid, self.ready, data, user, last)
        before = self.previous
        if before is not None and before[0] and not before[1]:
            if not valid:
                self.problems.append(f"cycle {cycle}: {self.prefix}_tvalid dropped without "
                                     "a handshake")
            elif now[2:] != before[2:]:
                self.problems.append(f"cycle {cycle}: {self.prefix} word changed while "
                                     "waiting")
        self.previous = now
        if valid and n is not None:
            self.timeline.append([n, self.ready, last])
        if valid and self.ready:
            self.words.append(now[2:])

    def idle(self) -> None:
        self.tready.value = 0
        self.previous = (0, 0, 0, 0, 0)


def score_state_iteration(cfg, expected, words, last: bool, problems, iteration) -> str:
    """``"whole"`` (no filler: every word the model's, all of them if ``last``) or
    ``"fill k"`` (the last line completed by k fillers); a problem otherwise.

    ``words`` are the (tdata, tuser, tlast) transfers on ``m_axis_state``: lines of exactly
    W words, each ending with ``tlast``; the words that are not fillers are the model's
    (``expected.state_words`` with ``tuser[0]`` = ``expected.state_first``), in order from
    the first; fillers (``tuser`` = ``tuser[3]`` only, ``tdata`` 0) only after the last of
    them, completing its line."""
    from dptbd.hw.axis_video import STATE_TUSER

    cut = 1 << STATE_TUSER["cut"]
    e_mask, d_mask = (1 << cfg.energy_bits) - 1, (1 << cfg.direction_bits) - 1
    before = len(problems)
    line = 0
    for i, (_data, _user, tlast) in enumerate(words):
        line += 1
        if bool(tlast) != (line == cfg.width):
            problems.append(f"iteration {iteration}: state word {i} is word {line} of its "
                            f"line, tlast = {tlast}")
            break
        if tlast:
            line = 0
    if line:
        problems.append(f"iteration {iteration}: the state stream ends in a line of {line} "
                        "words without tlast")
    data = [w for w in words if not w[1] & cut]
    fills = len(words) - len(data)
    if any(w[1] & cut for w in words[:len(data)]):
        problems.append(f"iteration {iteration}: a filler before a state word")
    if any(w != (0, cut, w[2]) for w in words[len(data):]) or fills >= cfg.width:
        problems.append(f"iteration {iteration}: fillers {words[len(data):]}")
    if len(data) > len(expected.state_words) or (last and len(data) < len(
            expected.state_words)):
        problems.append(f"iteration {iteration}: {len(data)} state words, the model gives "
                        f"{len(expected.state_words)}")
    for i, (word, user, tlast) in enumerate(data[:len(expected.state_words)]):
        packed = pack_states(cfg, energy=word & e_mask,
                             direction=(word >> cfg.energy_bits) & d_mask,
                             end_of_line=tlast, end_of_frame=(user >> 1) & 1,
                             end_of_segment=(user >> 2) & 1)
        if int(packed) != int(expected.state_words[i]) or bool(user & 1) != bool(
                expected.state_first[i]):
            problems.append(f"iteration {iteration}: state word {i} = {word:#x} tuser "
                            f"{user:#x}, the model gives {int(expected.state_words[i]):#x} "
                            f"first {int(expected.state_first[i])}")
            break
    if last and fills:
        problems.append(f"iteration {iteration}: {fills} fillers without a soft reset")
    if len(problems) > before:
        return "mismatch"
    return f"fill {fills}" if fills else "whole"


def score_iteration(cfg, want, words, last: bool, pack_cut_trailer, problems, iteration) -> str:
    """``"whole"`` (every list), ``"cut k"`` (the model's first lists whole, then one cut
    after k records, nothing after it) or ``"dropped"`` (the model's first lists whole, the
    others never began); a problem otherwise (and anything but ``"whole"`` if ``last``)."""
    packets, current = [], []
    for data, user, tlast in words:
        current.append((data, user))
        if tlast:
            packets.append(current)
            current = []
    if current:
        problems.append(f"iteration {iteration}: {len(current)} words without tlast")
    for i, packet in enumerate(packets):
        if [u for _, u in packet] != [1] + [0] * (len(packet) - 1):
            problems.append(f"iteration {iteration}: list {i}: tuser[0] "
                            f"{[u for _, u in packet]}")
    got = [[d for d, _ in p] for p in packets]
    whole = 0
    while whole < min(len(got), len(want)) and got[whole] == want[whole]:
        whole += 1
    if whole == len(want) and len(got) == whole:
        return "whole"
    if last or len(got) > whole + 1:
        problems.append(f"iteration {iteration}: lists {got} differ from the model's {want}")
        return "mismatch"
    if len(got) == whole:
        return "dropped"
    cut, model = got[whole], want[whole]
    k = len(cut) - 1
    if not (1 <= k < len(model) and cut[:k] == model[:k] and cut[k] == pack_cut_trailer(cfg, k)):
        problems.append(f"iteration {iteration}: cut list {cut} is not a prefix of "
                        f"{model} closed by the cut trailer")
        return "mismatch"
    return f"cut {k}"
