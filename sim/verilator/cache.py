"""The Verilator build cache: the generated Verilog verilated once per parameter set.

:func:`build` generates the Verilog of one of three top levels (:data:`DESIGNS`), verilates
it with the C++ harness ``sim/harness/dptbd_harness.cpp`` and compiles one executable.
Builds are cached under a key that hashes everything that determines the executable: the
configuration, the design, the LUT storage style, the gateware's source
(:func:`dptbd.hw.flow.source_hash.gateware_hash`), the harness, the flags and the Verilator and
compiler versions. A second build of the same key checks the cached executable against its
stamp (key and SHA-256) and reuses it; a build directory whose stamp is missing, foreign or
does not match is rebuilt, never reused. A build is made in a temporary directory and
renamed into place, so an interrupted build leaves nothing half-written behind.

``build(..., coverage=True)`` is the coverage build (:mod:`dptbd.sim.coverage`): Verilator's
line and toggle points (:data:`COVERAGE_FLAGS`) on the text of
:func:`dptbd.sim.coverage.source_text.coverage_verilog` (Amaranth's processes kept, each
decision marked with its Amaranth source line), a key and a directory of its own; each run
given a ``coverage`` file writes its ``VerilatedCov`` data there. The plain build's key,
text and flags do not change with it.

The tools, flags and harness sources, and Verilator's runtime library kept beside the builds:
:mod:`dptbd.sim.verilator.toolchain` (its public names importable from here too). Running a
build is :mod:`dptbd.sim.verilator` (which re-exports this module's public names).
Use Debian's ``verilator`` (5.006; ``scripts/setup.sh`` installs it).
"""

from __future__ import annotations

import dataclasses
import hashlib
import json
import os
import pathlib
import shutil
import tempfile
import time
from typing import Sequence

from dptbd.config import DPConfig
from dptbd.sim.build_dirs import CompiledDesign, config_name, locked
from dptbd.sim.verilator import toolchain
from dptbd.sim.verilator.toolchain import (
    COVERAGE_FLAGS,
    CXX_FLAGS,
    HARNESS,
    HARNESSES,
    VERILATOR_FLAGS,
    ToolMissingError,
    check_tools,
)

__all__ = [
    "DESIGNS",
    "VERILATOR_FLAGS",
    "CXX_FLAGS",
    "COVERAGE_FLAGS",
    "HARNESS",
    "ToolMissingError",
    "EXECUTABLE",
    "STAMP",
    "VerilatorBuild",
    "default_build_root",
    "check_tools",
    "build",
    "family_options",
]

#: Top levels the harness drives: design name -> (Verilog module, harness define, output
#: stream). ``dp`` is ``DPPipeline`` (on-chip state store), ``core`` is ``DPCore`` with the
#: harness's C++ model of the external state store, ``segmenter`` is ``DPSegmenter``.
DESIGNS = {
    "dp": ("dptbd_dp", "DPTBD_DESIGN_DP", "states"),
    "core": ("dptbd_dp", "DPTBD_DESIGN_CORE", "states"),
    "segmenter": ("dptbd_seg", "DPTBD_DESIGN_SEG", "candidates"),
    "axi": ("dptbd_axi", "DPTBD_DESIGN_AXI", "m_axis_cand"),     # hw/axi_top.py
}

EXECUTABLE = "dptbd_sim"
STAMP = "build.json"


def default_build_root() -> pathlib.Path:
    """``$DPTBD_BUILD_DIR/verilator`` if set, else ``$XDG_CACHE_HOME/dptbd/verilator``
    (``~/.cache/dptbd/verilator``): builds are reused by every checkout and run."""
    if os.environ.get("DPTBD_BUILD_DIR"):
        return pathlib.Path(os.environ["DPTBD_BUILD_DIR"]) / "verilator"
    base = os.environ.get("XDG_CACHE_HOME") or str(pathlib.Path.home() / ".cache")
    return pathlib.Path(base) / "dptbd" / "verilator"


@dataclasses.dataclass(frozen=True)
class VerilatorBuild(CompiledDesign):
    """One compiled simulation executable (``latency`` and ``toplevel`` from
    :class:`~dptbd.sim.build_dirs.CompiledDesign`)."""

    designs = DESIGNS

    cfg: DPConfig
    design: str
    directory: pathlib.Path
    executable: pathlib.Path
    manifest: dict
    key: str
    seconds: float        # wall time of this build() call (generation + compilation, or the cache check)
    cached: bool          # the executable came from the cache
    waves: bool
    coverage: bool = False   # a coverage build (COVERAGE_FLAGS): runs may write coverage data
    state_store: object = None   # design "axi" with the state in external memory: its AxiStoreConfig
    mutant: bool = False     # a mutant build (mutations given): mutsel, counter presets (axi)
    family: str | None = None   # the FPGA family of its core options (None: DPCore's defaults)

    @property
    def output(self) -> str:
        """The output stream: ``states`` or ``candidates``."""
        return DESIGNS[self.design][2]


def _store_fields(store) -> dict:
    """The parameters of an :class:`~dptbd.config.AxiStoreConfig` but its frame."""
    return {f.name: getattr(store, f.name) for f in dataclasses.fields(store) if f.name != "frame"}


def _build_key(cfg: DPConfig, design: str, lut_style: str, waves: bool,
               coverage: bool = False, mutations: tuple[str, ...] = (), store=None,
               family: str | None = None) -> str:
    from dptbd.hw.flow.source_hash import gateware_hash

    extra = {}                                # the plain build's key unchanged
    if coverage:                              # its text comes from source_text.py
        text = pathlib.Path(__file__).resolve().parents[1] / "coverage" / "source_text.py"
        extra = {"coverage": COVERAGE_FLAGS, "text": _sha256(text)}
    if mutations:
        extra.update(mutations=list(mutations), mutant_netlist=_mutant_netlist_hash())
    if store is not None:
        extra["state_store"] = _store_fields(store)
    if family is not None:                    # its options, and the cell models it may need
        from dptbd.sim.cell_models import CELL_MODELS, model_path
        extra.update(family=family, core_options=family_options(cfg, family),
                     cell_models={cell: _sha256(model_path(cell)) for cell in CELL_MODELS})
    blob = json.dumps({**extra,
        "config": cfg.to_mapping(), "design": design, "lut_style": lut_style,
        "waves": waves, "gateware": gateware_hash(),
        "harness": hashlib.sha256(b"".join(
            path.read_bytes() for path in toolchain.harness_sources(design))).hexdigest(),
        "verilator_flags": VERILATOR_FLAGS, "cxx_flags": CXX_FLAGS, "tools": check_tools(),
    }, sort_keys=True)
    return hashlib.sha256(blob.encode()).hexdigest()


def _mutant_netlist_hash() -> str:
    """SHA-256 of the mutant design's generators (``sim/mutation/netlist.py`` and
    ``presets.py``)."""
    from dptbd.sim.mutation import netlist, presets
    return hashlib.sha256(b"".join(pathlib.Path(m.__file__).read_bytes()
                                   for m in (netlist, presets))).hexdigest()


def _sha256(path: pathlib.Path) -> str:
    return hashlib.sha256(path.read_bytes()).hexdigest()


def _stamp_ok(directory: pathlib.Path, key: str) -> dict | None:
    """The stamp's manifest if ``directory`` holds a finished build of ``key``."""
    try:
        stamp = json.loads((directory / STAMP).read_text())
        exe = directory / EXECUTABLE
        if stamp.get("key") == key and stamp.get("executable_sha256") == _sha256(exe):
            return stamp["manifest"]
    except (OSError, ValueError, KeyError, TypeError, AttributeError):  # e.g. a JSON list
        return None
    return None


def family_options(cfg: DPConfig, family: str) -> dict:
    """The core options ``dptbd verilog --family family`` builds ``cfg`` with
    (``ValueError`` naming the families for another)."""
    from dptbd.hw.flow.family import get_family
    return dict(get_family(family).options_for(cfg))


def _generate(cfg: DPConfig, design: str, lut_style: str, coverage: bool = False,
              store=None, family: str | None = None) -> tuple[str, dict]:
    if coverage:
        from dptbd.sim.coverage.source_text import coverage_text
        with coverage_text():
            return _generate(cfg, design, lut_style, store=store, family=family)
    options = None if family is None else family_options(cfg, family)
    if design == "axi":
        from dptbd.hw.flow.axi_package import generate_axi_verilog
        if lut_style != "auto":
            raise ValueError("the AXI top takes the default lut_style 'auto' only")
        return generate_axi_verilog(cfg, state_store=store, core_options=options)
    if design == "segmenter":
        from dptbd.hw.flow.segmenter_verilog import generate_segmenter_verilog
        if lut_style != "auto":
            raise ValueError("the segmenter top takes the default lut_style 'auto' only")
        return generate_segmenter_verilog(cfg, core_options=options)
    from dptbd.hw.flow.verilog import generate_verilog
    return generate_verilog(cfg, external_state_store=design == "core", lut_style=lut_style,
                            core_options=options)


def build(cfg: DPConfig, design: str = "dp", *, root: str | os.PathLike | None = None,
          waves: bool = False, lut_style: str = "auto", verbose: bool = False,
          coverage: bool = False, mutations: Sequence[str] = (),
          state_store=None, family: str | None = None) -> VerilatorBuild:
    """Verilate and compile ``design`` for ``cfg``, or reuse the cached executable.

    Parameters
    ----------
    cfg : DPConfig
        Refused with :class:`~dptbd.errors.ConfigError` if the gateware does not implement it.
    design : str
        A key of :data:`DESIGNS`.
    root : path-like, optional
        Build root (default :func:`default_build_root`); the build goes to
        ``root/<parameter set>-<design>-<key>``.
    waves : bool
        Compile FST tracing in (``run(..., trace=path)``).
    lut_style : str
        The weight LUT's storage (``docs/gateware.md``); the simulation is the same.
    coverage : bool
        The coverage build (see the module doc): slower; runs write coverage data.
    mutations : sequence of str
        Yosys ``mutate`` commands (:mod:`dptbd.sim.mutation.netlist`): the build carries
        mutation ``i`` behind ``mutsel == i`` and its harness selects one from the
        environment (``DPTBD_MUTANT``; 0 or unset: the original). Designs ``segmenter``,
        ``axi`` and ``dp`` only; at ``pixels_per_clock`` > 1, ``dp`` only.
    state_store : AxiStoreConfig, optional
        Design ``axi`` only: ``dptbd_axi --state-store axi`` of ``state_store`` (made for
        ``cfg``), its port served by the harness's AXI4 memory model (``axi4_memory.h``).
    family : str, optional
        Build the DP core with the implementation options of this FPGA family
        (:meth:`~dptbd.hw.flow.family.Family.options_for`, as ``dptbd verilog --family``
        writes it), the vendor cells it instantiates simulated by their models
        (:mod:`dptbd.sim.cell_models`: the ECP5 ``DP16KD``). ``None`` (default): DPCore's
        defaults. Not with ``mutations``.
    """
    if design not in DESIGNS:
        raise ValueError(f"design must be one of {', '.join(DESIGNS)}, got {design!r}")
    from dptbd.hw.schedule import check_supported

    if cfg.pixels_per_clock == 1:
        check_supported(cfg)
    if cfg.pixels_per_clock > 1 and design == "axi":
        from dptbd.hw.wide.axis_video import lane_bits
        bits = cfg.pixels_per_clock * lane_bits(cfg)
        if bits > 32:
            raise ValueError(f"design 'axi' at pixels_per_clock={cfg.pixels_per_clock}: "
                             f"s_axis_video_tdata of {bits} bits; the AXI harness drives at "
                             f"most 32")
    if cfg.pixels_per_clock > 1 and mutations and design != "dp":
        raise ValueError(f"a mutant build at pixels_per_clock={cfg.pixels_per_clock} is of "
                         f"design 'dp' (dptbd_dp) only, got {design!r}")
    if cfg.pixels_per_clock > 1:
        from dptbd.hw.wide import check_wide
        check_wide(cfg)
    tools = check_tools()
    start = time.perf_counter()
    mutations = tuple(str(m) for m in mutations)
    if coverage and mutations:
        raise ValueError("a build is a coverage build or a mutant build, not both")
    if state_store is not None and (design != "axi" or mutations):
        raise ValueError("state_store applies to design 'axi' without mutations only")
    if state_store is not None and state_store.frame != cfg:
        raise ValueError("state_store was made for another configuration than cfg")
    if family is not None:
        family_options(cfg, family)           # ValueError naming the families
        if mutations:
            raise ValueError("a mutant build has DPCore's default options: family must be "
                             f"None with mutations, got {family!r}")
    key = _build_key(cfg, design, lut_style, waves, coverage, mutations, state_store, family)
    root = pathlib.Path(root) if root is not None else default_build_root()
    kind = (f"-mut{len(mutations)}" if mutations else "") + ("-waves" if waves else "") \
        + ("-cov" if coverage else "") + ("" if state_store is None else "-store") \
        + ("" if family is None else f"-{family}")
    directory = root.resolve() / f"{config_name(cfg)}-{design}{kind}-{key[:12]}"
    with locked(root.resolve() / ".locks" / (directory.name + ".lock")):
        manifest = _stamp_ok(directory, key)
        cached = manifest is not None
        if not cached:
            manifest = _compile(cfg, design, lut_style, waves, key, directory, tools, verbose,
                                coverage, mutations, state_store, family)
    return VerilatorBuild(cfg, design, directory, directory / EXECUTABLE, manifest, key,
                          time.perf_counter() - start, cached, waves, coverage, state_store,
                          bool(mutations), family)


def _compile(cfg: DPConfig, design: str, lut_style: str, waves: bool, key: str,
             directory: pathlib.Path, tools: dict, verbose: bool, coverage: bool = False,
             mutations: tuple[str, ...] = (), store=None, family: str | None = None) -> dict:
    from dptbd.sim.cell_models import model_sources

    toplevel, define, _ = DESIGNS[design]
    if mutations:
        from dptbd.sim.mutation.netlist import mutant_verilog
        text, manifest = mutant_verilog(cfg, design, mutations)
    else:
        text, manifest = _generate(cfg, design, lut_style, coverage, store, family)
    directory.parent.mkdir(parents=True, exist_ok=True)
    tmp = pathlib.Path(tempfile.mkdtemp(prefix=directory.name + ".", dir=directory.parent))
    try:
        verilog = tmp / f"{toplevel}.v"
        verilog.write_text(text)
        (tmp / f"{toplevel}.json").write_text(json.dumps(manifest, indent=2) + "\n")
        defines = [f"-D{define}"] + (["-DDPTBD_MUTANT"] if mutations else []) \
            + ([] if store is None else toolchain.store_defines(store))
        if design == "core":
            store_bits = cfg.state_bits * cfg.pixels_per_clock     # a beat's P states
            defines += [f"-DDPTBD_STORE_WORDS={cfg.frame_beats}ULL",
                        f"-DDPTBD_STORE_BITS={store_bits}"]
        trace = []
        if waves:
            trace = ["--trace-fst"]
            defines.append("-DDPTBD_TRACE")
        cover = list(COVERAGE_FLAGS) if coverage else []
        cmd = ["verilator", *VERILATOR_FLAGS, *trace, *cover, "--top-module", toplevel,
               "-CFLAGS", " ".join(defines), "-o", EXECUTABLE, "--Mdir", "obj",
               verilog.name, *map(str, model_sources(text)),
               str(HARNESSES.get(design, HARNESS))]
        toolchain.step(cmd, tmp, verbose, f"verilator ({toplevel}, {design})")
        toolchain.compile_executable(
            tmp, EXECUTABLE, toolchain.runtime_dir(directory.parent, tools, waves, coverage),
            verbose, f"C++ build ({toplevel}, {design})")
        stamp = {"key": key, "executable_sha256": _sha256(tmp / EXECUTABLE),
                 "design": design, "toplevel": toplevel, "tools": tools,
                 "command": cmd, "manifest": manifest}
        (tmp / STAMP).write_text(json.dumps(stamp, indent=2) + "\n")
        if directory.exists():                      # stale or foreign: never reused
            shutil.rmtree(directory)
        os.replace(tmp, directory)
    except BaseException:
        shutil.rmtree(tmp, ignore_errors=True)
        raise
    return manifest
