"""pleat: cloth and origami simulation from Python.

Scenes are read from a file, JSON text or a dict and checked as the ``pleat``
command checks them; a :class:`Simulation` steps one on the CPU or the GPU
with the GIL released and shows its state as numpy arrays; :func:`fold` and
:func:`bench` are ``pleat fold`` and ``pleat bench``; :func:`sweep` runs a
grid of scene variations as Ray tasks (or serially) and tabulates their
reports.

>>> import pleat
>>> sim = pleat.Simulation(pleat.Scene.default())
>>> sim.step(10)
>>> sim.positions.shape
(4096, 3)
"""

from ._pleat import (
    BackendError,
    Scene,
    SceneError,
    Settings,
    Simulation,
    __version__,
    bench,
    fold,
)
from .sweep import sweep

__all__ = [
    "BackendError",
    "Scene",
    "SceneError",
    "Settings",
    "Simulation",
    "__version__",
    "bench",
    "fold",
    "sweep",
]
