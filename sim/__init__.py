"""RTL simulation: generated Verilog, cocotb 2 testbenches on Icarus, scored against the model.

Modules
-------
``dptbd.sim.runner``
    :func:`~dptbd.sim.runner.build` generates ``dptbd_dp.v`` and its manifest for a
    :class:`~dptbd.config.DPConfig` into ``build/sim/<parameter set>/`` and compiles it with
    ``cocotb_tools.runner`` (Icarus, timescale 1ns/1ps, optional FST waves);
    :func:`~dptbd.sim.runner.simulate` writes the scene (``scene.npy``) and the job
    (``job.json``) into a run directory and runs one cocotb test on the build.
``dptbd.sim.tb_dp``
    The cocotb test module (``run_scene``, ``mid_frame_reset``, ``truncated_frame_resync``);
    it reads ``DPTBD_SIM_JOB`` and ``DPTBD_SIM_SCENE``.
``dptbd.sim.components``
    Driver (:class:`~dptbd.sim.components.StreamSource`), back-pressure sink, monitor, pause
    generators, LUT writes.
``dptbd.sim.scoreboard``
    The golden model's expected ``states`` words (:mod:`dptbd.model.fixed` frame by frame)
    and the comparison that reports the first mismatching frame, row, column and field.
``dptbd.sim.scenarios``
    Integer scenes from :mod:`dptbd.model.scenes` (targets, noise, saturation, ties, edges).

From the command line: ``dptbd sim`` (one scene, cycle count, verdict) and
``dptbd verilog`` (Verilog + manifest). Tests: ``pytest tests/sim`` (``-m slow`` for the
long 128 x 128 run). Speed: ``python benchmarks/bench_sim.py``.
"""
