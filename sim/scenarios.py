"""Integer scenes for RTL simulation, from the scene generators of :mod:`dptbd.scenes.synthetic`.

Each scenario returns ``(T, H, W)`` ``uint16`` frames that satisfy ``docs/arithmetic.md``
§1 for the configuration's B_in (quantised like an ADC, :func:`~dptbd.scenes.synthetic.quantise`).
The ADC gain scales paper 001's noise (mean 30, variance 3) with B_in: ``16 * 2**(B_in - 12)``,
paper 001's 12-bit gain of 16 (:data:`dptbd.scenes.synthetic.ADC_GAIN`) at B_in = 12.

=========== ===========================================================================
name        scene
=========== ===========================================================================
table1      001 Table 1: one target, SNR 2.3, velocity (1, 1), centred trajectory
two-targets 001's second experiment: two targets, SNR 2.0 (starts scaled to W x H)
noise       001's noise only
mixed       noise + a diagonal target + targets along all four edges + full-scale pixels
saturating  bright noise near full scale and a full-scale target: pixels clip at 2**B_in-1
ties        pixels 0 and 1 only: many equal candidates, argmax tie-breaking
edges       bright targets moving along the four image edges and through the corners
random      uniform pixels over the whole range
=========== ===========================================================================
"""

from __future__ import annotations

import numpy as np

from dptbd.config import DPConfig
from dptbd.scenes import synthetic as scenes
from dptbd.scenes.synthetic import ADC_GAIN, INPUT_BITS

__all__ = ["SCENARIOS", "adc_gain", "make_frames", "describe"]

SCENARIOS = ("table1", "two-targets", "noise", "mixed", "saturating", "ties", "edges", "random")


def adc_gain(cfg: DPConfig) -> float:
    """ADC gain that puts 001's background (mean 30) at the same fraction of full scale."""
    return ADC_GAIN * 2.0 ** (cfg.input_bits - INPUT_BITS)


def _edge_targets(cfg: DPConfig, amplitude: float) -> list[scenes.Target]:
    h, w = cfg.height - 1, cfg.width - 1
    return [
        scenes.Target((0.0, 0.0), (0.0, 1.0), amplitude),             # along the top row
        scenes.Target((h, w), (0.0, -1.0), amplitude),                # along the bottom row
        scenes.Target((0.0, w), (1.0, 0.0), amplitude),               # down the right column
        scenes.Target((h, 0.0), (-1.0, 0.0), amplitude),              # up the left column
        scenes.Target((0.0, w / 2), (0.5, -0.7), amplitude * 0.5),    # leaves through an edge
    ]


def make_frames(name: str, cfg: DPConfig, n_frames: int, seed: int = 0) -> np.ndarray:
    """``n_frames`` integer frames of scenario ``name`` for ``cfg`` (see the module table)."""
    if name not in SCENARIOS:
        raise ValueError(f"unknown scenario {name!r}; choose one of {', '.join(SCENARIOS)}")
    if isinstance(n_frames, bool) or not isinstance(n_frames, int) or n_frames < 1:
        raise ValueError(f"frames must be an integer >= 1, got {n_frames!r}")
    shape = (cfg.height, cfg.width)
    top = cfg.pixel_max
    mu, sigma = scenes.TABLE1_MU, scenes.TABLE1_SIGMA
    gain = adc_gain(cfg)
    if name == "table1":
        vel = (1.0, 1.0)
        start = tuple(float(np.rint((s - 1) / 2.0 - v * (n_frames - 1) / 2.0))
                      for s, v in zip(shape, vel))
        target = scenes.Target(start, vel, scenes.amplitude_from_snr(2.3, sigma))
        scene = scenes.make_scene(shape, n_frames, [target], mu=mu, sigma=sigma, seed=seed)
        return scene.quantised(cfg.input_bits, gain=gain)
    if name == "two-targets":
        if shape == (128, 128) and n_frames <= 100:
            scene = scenes.paper001_two_targets(snr=2.0, seed=seed)
            return scene.quantised(cfg.input_bits, gain=gain)[:n_frames]
        amp = scenes.amplitude_from_snr(2.0, sigma)
        sy, sx = cfg.height / 128.0, cfg.width / 128.0
        targets = [scenes.Target((30.0 * sy, 100.0 * sx), (0.8, -0.4), amp),
                   scenes.Target((54.0 * sy, 40.0 * sx), (0.4, 0.6), amp)]
        scene = scenes.make_scene(shape, n_frames, targets, mu=mu, sigma=sigma, seed=seed)
        return scene.quantised(cfg.input_bits, gain=gain)
    if name == "noise":
        scene = scenes.make_scene(shape, n_frames, [], mu=mu, sigma=sigma, seed=seed)
        return scene.quantised(cfg.input_bits, gain=gain)
    if name == "mixed":
        amp = 8 * sigma
        targets = [scenes.Target((0.5, 0.5), (0.7, 0.9), amp)] + _edge_targets(cfg, amp)
        scene = scenes.make_scene(shape, n_frames, targets, mu=mu, sigma=sigma, seed=seed)
        frames = scene.quantised(cfg.input_bits, gain=gain)
        rng = np.random.default_rng(seed + 1)
        hot = rng.random(frames.shape) < 0.03
        frames[hot] = top                                        # full-scale pixels
        return frames
    if name == "saturating":
        target = scenes.Target((cfg.height / 2.0, 0.0), (0.0, 1.0), float(top))
        scene = scenes.make_scene(shape, n_frames, [target], mu=0.9 * top,
                                  sigma=max(0.1 * top, 0.5), seed=seed)
        return scene.quantised(cfg.input_bits)
    if name == "ties":
        noise = scenes.make_noise(shape, n_frames, seed=seed)
        return (noise > 0.0).astype(np.uint16)
    if name == "edges":
        amp = max(10 * sigma, 0.5 * top / gain)
        scene = scenes.make_scene(shape, n_frames, _edge_targets(cfg, amp), mu=mu, sigma=sigma,
                                  seed=seed)
        return scene.quantised(cfg.input_bits, gain=gain)
    rng = np.random.default_rng(seed)
    return rng.integers(0, top + 1, size=(n_frames,) + shape).astype(np.uint16)


def describe(frames: np.ndarray, cfg: DPConfig) -> str:
    """One line: size, range and how many pixels sit at full scale."""
    full = int(np.count_nonzero(frames == cfg.pixel_max))
    return (f"{frames.shape[0]} frames of {cfg.width}x{cfg.height}, pixels "
            f"{int(frames.min())}…{int(frames.max())} ({full} at full scale "
            f"{cfg.pixel_max}, {100.0 * full / max(1, frames.size):.1f} %)")

