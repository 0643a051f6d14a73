"""A small ``dptbd compare`` specification for the RTL-in-the-loop tests: a mapping
(:func:`small_spec`, what ``build_spec`` takes) and its TOML text (:func:`spec_toml`, what
``dptbd compare --config`` reads)."""

from __future__ import annotations

import copy
import json

#: 4 trials of 16 x 16, 14 frames (3 segments of K = 4), 3 SNRs, one named configuration
#: and a one-point sweep.
SMALL_SPEC = {
    "trials": 4,
    "seed": 3,
    "snr": [1.5, 2.5, 3.5],
    "size": 16,
    "frames": 14,
    "segment_frames": 4,
    "false_alarm_rate": 0.02,
    "chunk": 2,
    "bootstrap": 40,
    "thresholds": [2.0, 3.0, 4.0],
    "config": [{"name": "exact-ish", "input_bits": 10}],
    "sweep": {"input_bits": [4], "energy_headroom": [-1]},
}


def small_spec(**changes) -> dict:
    """A copy of :data:`SMALL_SPEC` with ``changes`` to its top-level keys."""
    return {**copy.deepcopy(SMALL_SPEC), **changes}


def spec_toml(spec: dict) -> str:
    """``spec`` as TOML: scalars and arrays first, then ``[[name]]`` arrays of tables and
    ``[name]`` tables (JSON literals are TOML literals for these values)."""
    lines, tables = [], []
    for key, value in spec.items():
        if isinstance(value, dict):
            tables.append(f"[{key}]")
            tables += [f"{k} = {json.dumps(v)}" for k, v in value.items()]
        elif isinstance(value, list) and value and isinstance(value[0], dict):
            for item in value:
                tables.append(f"[[{key}]]")
                tables += [f"{k} = {json.dumps(v)}" for k, v in item.items()]
        else:
            lines.append(f"{key} = {json.dumps(value)}")
    return "\n".join(lines + tables) + "\n"
