"""RTL simulation: generated Verilog on Verilator (compiled, the main simulator) and cocotb 2
on Icarus (4-state protocol checks), scored against the golden model.

Modules
-------
``dptbd.sim.verilator_build``
    :func:`~dptbd.sim.verilator_build.build` verilates one top level (``dp``, ``core`` with a
    C++ external store, ``segmenter``) with the harness ``sim/harness/dptbd_harness.cpp``
    into a cached executable (the build cache).
``dptbd.sim.verilator``
    :func:`~dptbd.sim.verilator.run` streams a whole input sequence through a build with
    seeded stalls, resets, LUT writes; re-exports the build cache's public names
    (``verilator.build``, ``verilator.check_tools``, …).
``dptbd.sim.stream_model``
    The golden model's output for an arbitrary accepted stream (resets, misaligned, short
    and long frames, LUT changes), by the gateware's counter rule.
``dptbd.sim.rtl_check``
    One compiled run checked against the model with the scoreboards below.
``dptbd.sim.rtl_trials``
    Monte Carlo trials accumulated on the compiled RTL (``compare --rtl``, ``table1 --rtl``).
``dptbd.sim.campaign``
    The verification campaign (``dptbd verify``).
``dptbd.sim.x_store``
    4-state (Icarus) check that an X- or garbage-initialised external store never reaches
    an output.
``dptbd.sim.stimulus``
    Pixel words and LUT writes, packed with the gateware's layouts.
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
``dptbd.sim.checker``
    The one in-order checker (expected items from the model, received items from a monitor,
    the first mismatch with its position) behind every scoreboard.
``dptbd.sim.scoreboard``, ``dptbd.sim.candidate_scoreboard``
    Its two users: the golden model's expected ``states`` words (:mod:`dptbd.model.fixed`
    frame by frame), reported by frame, row, column and field; the candidate lists, by
    segment, record and field.
``dptbd.sim.job``
    The job behind ``dptbd sim``: one scene through the generated Verilog on Verilator or
    Icarus, its cycle count, speed and verdict.
``dptbd.sim.build_dirs``
    Build-directory names and locking shared by the Verilator and cocotb builds.
``dptbd.sim.scenarios``
    Integer scenes from :mod:`dptbd.scenes.synthetic` (targets, noise, saturation, ties, edges).

From the command line: ``dptbd sim`` (one scene, cycle count, verdict), ``dptbd verify``
(the campaign) and ``dptbd verilog`` (Verilog + manifest). Tests: ``pytest tests/sim`` (``-m slow`` for the
long 128 x 128 run). Speed: ``python benchmarks/bench_sim.py``.
"""
