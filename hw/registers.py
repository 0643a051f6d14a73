"""The register map of ``dptbd_axi`` in SystemRDL (``hw/registers.rdl``), compiled per build.

``hw/registers.rdl`` is the one source of the register map: every register, field, access,
reset value, range and description. :func:`compile_map` compiles it with
``systemrdl-compiler`` for a :class:`~dptbd.config.DPConfig` (and, with ``--state-store
axi``, its :class:`~dptbd.config.AxiStoreConfig`) and returns the elaborated ``addrmap``
node; everything else is read from that node:

- :func:`dptbd.hw.register_map.register_map` (the :class:`~dptbd.hw.register_map.RegisterMap`
  the Amaranth register file decodes, and the testbenches' constants),
- the PeakRDL outputs ``dptbd verilog --top axi`` writes (:mod:`dptbd.hw.flow.register_docs`):
  C header, HTML, Markdown and IP-XACT.

How the one ``.rdl`` elaborates to each build's map:

- the build's numbers (frame size, widths, K_max, the settings' limits, the store's port)
  are parameters of the ``addrmap`` (:func:`rdl_parameters`), given to the compiler's
  elaboration as overrides; ``DPConfig`` derives them, the ``.rdl`` only places them;
- the registers of the state store in external memory are inside ```ifdef STATE_STORE``
  (the SystemRDL preprocessor's), which :func:`compile_map` defines for that build only.

A malformed ``.rdl`` (a field overlapping another, a reset value wider than its field, …) is
refused by the compiler's own error, with the file and line (:class:`RegisterMapError`).
"""

from __future__ import annotations

import functools
import pathlib

from dptbd.config import DPConfig
from dptbd.errors import DptbdError

__all__ = ["RDL_PATH", "TOP_NAME", "RegisterMapError", "rdl_parameters", "compile_map"]

#: The SystemRDL source (package data of ``dptbd.hw``).
RDL_PATH = pathlib.Path(__file__).with_name("registers.rdl")
#: The ``addrmap`` of :data:`RDL_PATH` that is the register map of ``dptbd_axi``.
TOP_NAME = "dptbd_axi"


class RegisterMapError(DptbdError):
    """A register map refused: the SystemRDL compiler's errors, or a register whose access
    the register file cannot implement."""


def _bits(hi: int) -> int:
    return max(1, int(hi).bit_length())


def rdl_parameters(cfg: DPConfig, store=None) -> dict[str, int]:
    """The parameter overrides of the ``addrmap`` for ``cfg`` (and ``store``)."""
    params = {
        "WIDTH": cfg.width, "HEIGHT": cfg.height, "INPUT_BITS": cfg.input_bits,
        "ENERGY_BITS": cfg.energy_bits, "WEIGHT_FRAC_BITS": cfg.weight_frac_bits,
        "RADIUS": cfg.radius, "K_MAX": cfg.k_max, "SEGMENT_FRAMES": cfg.segment_frames,
        "RECORD_CAPACITY": cfg.record_capacity, "HISTOGRAM_BITS": cfg.histogram_bits,
        "CANDIDATE_COUNT": cfg.n_candidates, "HISTOGRAM_SHIFT": cfg.bin_shift,
        "LUT_ENTRIES": cfg.lut_entries, "WEIGHT_BITS": cfg.weight_bits,
        "CANDIDATE_COUNT_BITS": _bits(cfg.record_capacity),
        "HISTOGRAM_SHIFT_BITS": _bits(cfg.energy_bits - 1),
        "HISTOGRAM_SHIFT_MAX": cfg.energy_bits - 1,
        "WEIGHT_UNITY": 1 << cfg.weight_frac_bits,
    }
    if store is not None:
        top = (1 << store.address_bits) - store.frame_bytes
        params.update({
            "STORE_DATA_BITS": store.data_bits, "STORE_ADDRESS_BITS": store.address_bits,
            "STORE_ID_BITS": store.id_bits, "STORE_OUTSTANDING": store.outstanding,
            "STORE_BURST_BEATS": store.burst_beats, "STORE_SLOT_BITS": store.slot_bits,
            "STORE_FRAME_BYTES": store.frame_bytes, "STORE_BASE_ADDRESS": store.base_address,
            "STORE_BASE_MAX": top - top % store.burst_bytes,
            "STORE_BURST_BYTES": store.burst_bytes,
        })
    return params


def compile_map(cfg: DPConfig, store=None, *, source=None):
    """The register map of ``dptbd_axi`` built for ``cfg`` (with the state store in external
    memory ``store``, an :class:`~dptbd.config.AxiStoreConfig`, if given), compiled from
    ``source`` (default :data:`RDL_PATH`): the elaborated ``addrmap``
    (:class:`systemrdl.node.AddrmapNode`). Compiled once per argument set (cached): treat
    the node as read-only.

    Raises
    ------
    RegisterMapError
        The compiler's errors, one per line, each ``{file}:{line}:{column}: error: {text}``.
    """
    return _compile(cfg, store, str(RDL_PATH if source is None else source))


@functools.lru_cache(maxsize=32)
def _compile(cfg, store, path):
    # systemrdl is imported here, not with this module: the gateware imports the register
    # map's constants, and the compiler takes a while to import
    from systemrdl import RDLCompileError, RDLCompiler
    from systemrdl.messages import (DetailedFileSourceRef, FileSourceRef, MessagePrinter,
                                    Severity)

    errors = []

    class Collect(MessagePrinter):
        """Keeps the compiler's errors as ``file:line:column: error: text``; drops warnings
        and the closing "aborted due to previous errors"."""

        def print_message(self, severity, text, src_ref):
            if severity < Severity.ERROR or (severity == Severity.FATAL and errors):
                return
            if isinstance(src_ref, DetailedFileSourceRef):
                where = f"{src_ref.path}:{src_ref.line}:{src_ref.line_selection[0] + 1}: "
            elif isinstance(src_ref, FileSourceRef):
                where = f"{src_ref.path}: "
            else:
                where = ""
            errors.append(f"{where}error: {text}")

    compiler = RDLCompiler(message_printer=Collect())
    try:
        compiler.compile_file(path, defines={} if store is None else {"STATE_STORE": ""})
        root = compiler.elaborate(TOP_NAME, parameters=rdl_parameters(cfg, store))
    except RDLCompileError:
        raise RegisterMapError("\n".join(errors)) from None
    return root.top
