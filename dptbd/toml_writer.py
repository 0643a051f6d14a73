"""A small TOML writer: the standard library's ``tomllib`` reads TOML only.

:func:`dump_toml` writes a two-level document — scalars, tables, and arrays of tables one
level down — which is what a scenario file is (``dptbd.evaluation.run.scenario``,
``Scenario.to_toml``, also written into every ``dptbd run`` output folder). ``tomllib``
reads back exactly the values written.
"""

from __future__ import annotations

import math
from typing import Any, Mapping

__all__ = ["dump_toml"]


def _toml_value(v: Any) -> str:
    if isinstance(v, bool):
        return "true" if v else "false"
    if isinstance(v, int):
        return str(v)
    if isinstance(v, float):
        return repr(v) if math.isfinite(v) else ("nan" if math.isnan(v) else
                                                  ("inf" if v > 0 else "-inf"))
    if isinstance(v, str):
        return '"' + v.replace("\\", "\\\\").replace('"', '\\"') + '"'
    if isinstance(v, (list, tuple)):
        return "[" + ", ".join(_toml_value(x) for x in v) + "]"
    if isinstance(v, Mapping):
        return "{" + ", ".join(f"{k} = {_toml_value(x)}" for k, x in v.items()) + "}"
    raise TypeError(f"cannot write {type(v).__name__} to TOML; allowed: bool, int, float, str, "
                    f"list, tuple, mapping")


def dump_toml(data: Mapping[str, Any]) -> str:
    """TOML text of a two-level document (scalars, tables, arrays of tables one level down)."""
    lines = [f"{k} = {_toml_value(v)}" for k, v in data.items() if not isinstance(v, Mapping)]
    for name, table in data.items():
        if not isinstance(table, Mapping):
            continue
        lines += ["", f"[{name}]"]
        arrays = {k: v for k, v in table.items()
                  if isinstance(v, list) and v and all(isinstance(x, Mapping) for x in v)}
        lines += [f"{k} = {_toml_value(v)}" for k, v in table.items() if k not in arrays]
        for key, items in arrays.items():
            for item in items:
                lines += ["", f"[[{name}.{key}]]"]
                lines += [f"{k} = {_toml_value(v)}" for k, v in item.items()]
    return "\n".join(lines) + "\n"
