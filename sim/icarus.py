"""Build the generated Verilog for a configuration and run the cocotb tests on Icarus.

Layout of a build root (default ``build/sim``)::

    build/sim/<name>/                one directory per parameter set (see config_name)
        dptbd_dp.v  dptbd_dp.json    Verilog and manifest (dptbd.hw.flow.verilog)
        config.json                  the DPConfig, every field
        sim.vvp  cmds.f              Icarus build (cocotb_tools.runner, timescale 1ns/1ps)
        runs/<run>/                  one directory per simulation run
            scene.npy  job.json      what the cocotb test module reads (DPTBD_SIM_SCENE/JOB)
            summary.json  sim.log    what it reports
    build/sim/<name>-waves/          the same parameter set compiled with waveform dumping

The Verilog is regenerated on every build (the gateware may have changed) but written only
when its text changed, so Icarus recompiles only then. A lock file serialises concurrent
builds of one parameter set (pytest-xdist).
"""

from __future__ import annotations

import contextlib
import dataclasses
import json
import os
import pathlib
import shutil
import time
from typing import Any

import numpy as np

from dptbd.config import DPConfig
from dptbd.sim.build_dirs import CompiledDesign, config_name, locked

__all__ = [
    "TOPLEVEL",
    "TEST_MODULE",
    "TIMESCALE",
    "DESIGNS",
    "SimBuild",
    "SimResult",
    "build",
    "write_job",
    "simulate",
    "check_scene",
]

TOPLEVEL = "dptbd_dp"
TEST_MODULE = "dptbd.sim.benches.dp"
TIMESCALE = ("1ns", "1ps")

#: What :func:`build` can compile: design name -> (Verilog module, cocotb test module,
#: build-directory suffix). ``dp`` is the DP pipeline (``dptbd.hw.flow.verilog``), ``segmenter``
#: the DP pipeline plus segmenter (``dptbd.hw.flow.segmenter_verilog``, tests in
#: ``dptbd.sim.benches.segmenter``).
DESIGNS = {
    "dp": (TOPLEVEL, TEST_MODULE, ""),
    "segmenter": ("dptbd_seg", "dptbd.sim.benches.segmenter", "-seg"),
    "axi": ("dptbd_axi", "dptbd.sim.benches.axi", "-axi"),      # dptbd.hw.axi_top, docs/integration.md
    "axi-state": ("dptbd_axi", "dptbd.sim.benches.axi", "-axi-state"),   # with m_axis_state
}


@dataclasses.dataclass(frozen=True)
class SimBuild(CompiledDesign):
    """A compiled simulation of one parameter set (``latency`` and ``toplevel`` from
    :class:`~dptbd.sim.build_dirs.CompiledDesign`)."""

    designs = DESIGNS

    cfg: DPConfig
    directory: pathlib.Path
    verilog: pathlib.Path
    manifest: dict
    waves: bool
    seconds: float            # wall time of generation + compilation
    design: str = "dp"        # a key of DESIGNS

    @property
    def test_module(self) -> str:
        """The cocotb test module run by :func:`simulate`."""
        return DESIGNS[self.design][1]


def _write_if_changed(path: pathlib.Path, text: str) -> bool:
    if path.exists() and path.read_text() == text:
        return False
    tmp = path.with_suffix(path.suffix + ".tmp")
    tmp.write_text(text)
    os.replace(tmp, path)
    return True


def _get_runner():
    from cocotb_tools.runner import get_runner
    return get_runner("icarus")


def build(cfg: DPConfig, root: str | os.PathLike = "build/sim", *, waves: bool = False,
          verbose: bool = False, design: str = "dp") -> SimBuild:
    """Generate the Verilog and manifest for ``cfg`` and compile them with Icarus.

    Parameters
    ----------
    cfg : DPConfig
        The parameter set; refused with :class:`~dptbd.errors.ConfigError` if the gateware
        does not implement it.
    root : path-like
        Build root; the parameter set gets ``root/config_name(cfg)`` (``-waves`` appended
        when compiled with waveform dumping).
    waves : bool
        Compile in cocotb's FST dump module (needed for ``simulate(..., waves=path)``).
    design : str
        ``"dp"`` (module ``dptbd_dp``) or ``"segmenter"`` (module ``dptbd_seg``, its build
        directory gets ``-seg`` appended), see :data:`DESIGNS`.
    """
    if design not in DESIGNS:
        raise ValueError(f"unknown design {design!r}; choose one of {', '.join(DESIGNS)}")
    toplevel, _, suffix = DESIGNS[design]
    if design == "segmenter":
        from dptbd.hw.flow.segmenter_verilog import generate_segmenter_verilog as generate
    elif design == "axi":
        from dptbd.hw.flow.axi_package import generate_axi_verilog as generate
    elif design == "axi-state":
        from dptbd.hw.flow.axi_package import generate_axi_state_verilog as generate
    else:
        from dptbd.hw.flow.verilog import generate_verilog as generate

    start = time.perf_counter()
    directory = pathlib.Path(root).resolve() / (config_name(cfg) + suffix
                                                + ("-waves" if waves else ""))
    with locked(directory / ".lock"):
        text, info = generate(cfg)
        verilog = directory / f"{toplevel}.v"
        _write_if_changed(verilog, text)
        _write_if_changed(directory / f"{toplevel}.json", json.dumps(info, indent=2) + "\n")
        _write_if_changed(directory / "config.json",
                          json.dumps(cfg.to_mapping(), indent=2) + "\n")
        runner = _get_runner()
        runner.build(sources=[verilog], hdl_toplevel=toplevel, build_dir=directory,
                     timescale=TIMESCALE, waves=waves, verbose=verbose)
    return SimBuild(cfg, directory, verilog, info, waves, time.perf_counter() - start, design)


@dataclasses.dataclass(frozen=True)
class SimResult:
    """What one simulation run reported (``summary.json`` of the cocotb test)."""

    passed: bool
    summary: dict
    run_dir: pathlib.Path
    log: pathlib.Path | None
    wall_seconds: float       # whole run, simulator start-up included

    @property
    def report(self) -> str:
        return self.summary.get("report", "no summary: the simulation did not finish")

    @property
    def cycles(self) -> int | None:
        return self.summary.get("cycles")

    def log_tail(self, lines: int = 30) -> str:
        if self.log is None or not self.log.exists():
            return ""
        return "\n".join(self.log.read_text(errors="replace").splitlines()[-lines:])


def check_scene(cfg: DPConfig, frames: Any) -> np.ndarray:
    """Refuse a scene the pipeline cannot take, with a message naming the problem.

    The frames must be an integer array ``(T, H, W)`` with ``H x W`` the configured frame
    size, at least one frame, and every pixel in ``[0, 2**B_in - 1]``.
    """
    arr = np.asarray(frames)
    if arr.dtype.kind not in "iu":
        raise ValueError(f"scene pixels must be integers, got dtype {arr.dtype}")
    if arr.ndim != 3:
        raise ValueError(f"scene must have shape (frames, height, width), got shape {arr.shape}")
    if arr.shape[1:] != (cfg.height, cfg.width):
        raise ValueError(
            f"scene frames are {arr.shape[2]}x{arr.shape[1]} (W x H) but the configuration "
            f"is width={cfg.width} x height={cfg.height}")
    if arr.shape[0] < 1:
        raise ValueError("scene has no frames")
    if arr.size and (arr.min() < 0 or arr.max() > cfg.pixel_max):
        bad = arr[(arr < 0) | (arr > cfg.pixel_max)]
        raise ValueError(
            f"scene pixels must fit input_bits={cfg.input_bits} (0 … {cfg.pixel_max}); found "
            f"{bad.size} outside, e.g. {bad.ravel()[:3].tolist()}")
    return arr.astype(np.uint16 if cfg.input_bits <= 16 else np.uint32)


def write_job(run_dir: pathlib.Path, sim: SimBuild, frames: np.ndarray, **options) -> dict:
    """Write ``scene.npy`` and ``job.json`` into ``run_dir``; return the environment to pass.

    ``options``: ``lut_codes`` ((M+1) x M codes written at run time before the first frame),
    ``valid_pause``/``ready_pause`` (:func:`dptbd.sim.benches.drivers.pause_generator` specs),
    ``exact_cycles`` (assert ``T*W*H + latency``), ``reset`` (``{"pre_frames", "cut_pixel",
    "hold_cycles"}`` for the ``mid_frame_reset`` test), ``truncate`` (``{"pre_frames",
    "keep_pixels"}`` for ``truncated_frame_resync``), ``corrupt_expected`` (``{"index",
    "xor"}``: the checker's self-check).
    """
    run_dir.mkdir(parents=True, exist_ok=True)
    scene = run_dir / "scene.npy"
    np.save(scene, frames)
    summary = run_dir / "summary.json"
    with contextlib.suppress(FileNotFoundError):
        summary.unlink()
    job = {
        "config": sim.cfg.to_mapping(),
        "latency": sim.latency,
        "summary": str(summary),
        **{k: (v.tolist() if isinstance(v, np.ndarray) else v) for k, v in options.items()},
    }
    (run_dir / "job.json").write_text(json.dumps(job, indent=2) + "\n")
    return {"DPTBD_SIM_JOB": str(run_dir / "job.json"), "DPTBD_SIM_SCENE": str(scene)}


def simulate(sim: SimBuild, frames: np.ndarray, *, testcase: str = "run_scene",
             run_name: str = "run", waves: str | os.PathLike | None = None,
             log_to_file: bool = True, seed: int = 1, **options) -> SimResult:
    """Run one cocotb test of the build's test module on a compiled build:
    :mod:`dptbd.sim.benches.dp` for ``design="dp"``, :mod:`dptbd.sim.benches.segmenter` (test
    ``run_scene``) for ``design="segmenter"``.

    Parameters
    ----------
    sim : SimBuild
        From :func:`build` (with ``waves=True`` if ``waves`` is given).
    frames : array
        Integer frames ``(T, H, W)`` (checked by :func:`check_scene`).
    testcase : str
        ``run_scene``, ``mid_frame_reset`` or ``truncated_frame_resync`` (``dp``);
        ``run_scene`` (``segmenter``).
    run_name : str
        Subdirectory of ``<build>/runs`` for this run's files.
    waves : path, optional
        Write an FST waveform there (GTKWave, Surfer).
    log_to_file : bool
        Send the simulator's output to ``<run>/sim.log`` instead of the console.
    **options
        Passed to :func:`write_job`.
    """
    frames = check_scene(sim.cfg, frames)
    if options.get("lut_codes") is not None:
        # refused here, before anything is written or the simulator starts (shape, range)
        sim.cfg.with_weight_codes(options["lut_codes"])
    if waves is not None and not sim.waves:
        raise ValueError("waves need a build compiled with waves=True")
    run_dir = sim.directory / "runs" / run_name
    if run_dir.exists():
        shutil.rmtree(run_dir)
    env = write_job(run_dir, sim, frames, **options)
    log = run_dir / "sim.log" if log_to_file else None
    plusargs = []
    if waves is not None:
        waves = pathlib.Path(waves).resolve()
        waves.parent.mkdir(parents=True, exist_ok=True)
        plusargs.append(f"+dumpfile_path={waves}")
    runner = _get_runner()
    start = time.perf_counter()
    try:
        runner.test(test_module=sim.test_module, hdl_toplevel=sim.toplevel,
                    hdl_toplevel_lang="verilog",
                    build_dir=sim.directory, test_dir=run_dir, testcase=testcase,
                    extra_env=env, waves=waves is not None, plusargs=plusargs, seed=seed,
                    log_file=log, timescale=TIMESCALE)
    except SystemExit:
        # under pytest the runner exits on a failing test; the summary says why
        pass
    except RuntimeError:
        pass
    wall = time.perf_counter() - start
    summary_path = run_dir / "summary.json"
    summary = json.loads(summary_path.read_text()) if summary_path.exists() else {}
    passed = summary.get("verdict") == "bit-exact" and _xml_passed(run_dir)
    return SimResult(passed, summary, run_dir, log, wall)


def _xml_passed(run_dir: pathlib.Path) -> bool:
    """True when every cocotb test in the run's results XML passed."""
    import xml.etree.ElementTree as ET

    files = list(run_dir.glob("*.xml"))
    if not files:
        return False
    for path in files:
        root = ET.parse(path).getroot()
        cases = list(root.iter("testcase"))
        if not cases:
            return False
        for case in cases:
            if case.find("failure") is not None or case.find("error") is not None \
                    or case.find("skipped") is not None:
                return False
    return True
