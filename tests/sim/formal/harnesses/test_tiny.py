"""The small build of the proofs (:mod:`dptbd.sim.formal.harnesses.tiny`)."""

from dptbd.sim.formal.harnesses.tiny import tiny_config


def test_tiny_config_is_the_smallest_build_with_lists():
    cfg = tiny_config()
    assert (cfg.width, cfg.height, cfg.segment_frames, cfg.record_capacity) == (5, 4, 2, 2)
    assert (cfg.input_bits, cfg.energy_bits, cfg.weight_frac_bits, cfg.n_bins) == (1, 4, 1, 2)
    assert tiny_config(width=6).width == 6
