"""JSON paths into a scene dict, as scene errors name them:
``cloths[0].material.bend_compliance``, ``solver.substeps``."""

from __future__ import annotations

import re
from typing import Any, List, Union

_NAME = r"[A-Za-z_][A-Za-z0-9_]*"
_PATH = re.compile(rf"{_NAME}(\[\d+\])*(\.{_NAME}(\[\d+\])*)*")
_STEP = re.compile(rf"({_NAME})|\[(\d+)\]")

Step = Union[str, int]


def parse(path: str) -> List[Step]:
    """The steps of ``path``: field names and list indices.

    Raises ValueError for a path that is not of the form ``a.b[0].c``.
    """
    if not isinstance(path, str) or not _PATH.fullmatch(path):
        raise ValueError(f"{path!r} is not a JSON path such as 'cloths[0].material.density'")
    return [name if name else int(index) for name, index in _STEP.findall(path)]


def set_value(data: Any, path: str, value: Any) -> None:
    """Sets the value at ``path`` in ``data`` (dicts and lists).

    The last field may be new (an optional field the scene left out); every
    step before it must exist. Raises KeyError naming the path otherwise.
    """
    steps = parse(path)
    node = data
    for i, step in enumerate(steps):
        last = i == len(steps) - 1
        where = _render(steps[: i + 1])
        if isinstance(step, int):
            if not isinstance(node, list) or step >= len(node):
                raise KeyError(f"{where}: the scene has no such element")
        elif not isinstance(node, dict) or (not last and step not in node):
            raise KeyError(f"{where}: the scene has no such field")
        if last:
            node[step] = value
        else:
            node = node[step]


def _render(steps: List[Step]) -> str:
    out = ""
    for s in steps:
        out += f"[{s}]" if isinstance(s, int) else (f".{s}" if out else s)
    return out
