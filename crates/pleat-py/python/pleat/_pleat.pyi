"""Type stubs of pleat._pleat, the native module (Rust, PyO3)."""

import os
from typing import Any, Dict, List, Literal, Mapping, Optional, Sequence, Tuple, Union

import numpy as np
import numpy.typing as npt

__version__: str

_Path = Union[str, "os.PathLike[str]"]
_Vec3 = Union[Tuple[float, float, float], Sequence[float]]
_Backend = Literal["cpu", "gpu"]

class SceneError(ValueError):
    """A scene that cannot be simulated: the message names the file, the
    JSON path and the reason, one error a line, as the ``pleat`` command
    prints them."""

    file: Optional[str]
    """The first error's file (its path, or the name given for text)."""
    path: Optional[str]
    """The first error's JSON path, e.g. ``cloths[0].material.density``;
    empty for the whole file."""
    reason: Optional[str]
    """What is wrong, for the first error."""
    errors: List[Dict[str, str]]
    """Every error, as dicts with ``file``, ``path`` and ``reason``."""

class BackendError(RuntimeError):
    """The GPU backend cannot run: no usable adapter, or a scene feature the
    GPU backend lacks (the message names the scene field)."""

class Scene:
    """A validated scene and where it came from (for messages, and the
    folder its relative paths start from)."""

    @staticmethod
    def load(path: _Path) -> "Scene":
        """Reads and validates a scene file; its relative paths start from
        its folder. Raises SceneError."""
    @staticmethod
    def from_json(text: str, file: str = "<string>", base_dir: Optional[_Path] = None) -> "Scene":
        """Parses and validates scene JSON; ``file`` names it in errors."""
    @staticmethod
    def from_dict(data: Mapping[str, Any], file: str = "<dict>", base_dir: Optional[_Path] = None) -> "Scene":
        """Validates a scene given as a dict (the JSON of a scene file)."""
    @staticmethod
    def default() -> "Scene":
        """The scene ``pleat run`` runs when given none: a cloth draped over
        a sphere onto the ground."""
    @staticmethod
    def hanging_cloth(n: int, substeps: int = 10, tethers: bool = False) -> "Scene":
        """The cloth ``pleat bench`` times: n x n particles, 1 m square,
        hanging from its two top corners."""
    def to_dict(self) -> Dict[str, Any]:
        """The scene as a dict, every default written out."""
    @property
    def name(self) -> str:
        """The scene's name (its file's stem when it has none)."""
    @property
    def frames(self) -> int:
        """Frames a run simulates."""
    @property
    def frame_dt(self) -> float:
        """Seconds per frame."""
    @property
    def file(self) -> str:
        """The scene's name in messages."""
    @property
    def base_dir(self) -> "os.PathLike[str]":
        """The folder the scene's relative paths start from."""

class Settings:
    """The parameters a step reads each time: changing one takes effect at
    the next step, without a rebuild, on either backend."""

    substeps: int
    """Substeps per frame (1 to 1000)."""
    iterations: int
    """Constraint iterations per substep (1 to 1000)."""
    damping: float
    """Velocity damping rate (1/s), zero or positive."""
    gravity: _Vec3
    """Gravitational acceleration (m/s^2)."""
    wind: Optional[_Vec3]
    """Mean wind velocity (m/s), or None for still air."""
    fold_progress: float
    """Fold progress in [0, 1]; setting it stops the scene's fold ramp."""
    def compliance(self, kind: Literal["stretch", "shear", "bend", "crease", "facet"], cloth: int = 0) -> float:
        """Cloth ``cloth``'s compliance of ``kind``."""
    def set_compliance(
        self, kind: Literal["stretch", "shear", "bend", "crease", "facet"], value: float, cloth: int = 0
    ) -> None:
        """Sets cloth ``cloth``'s compliance of ``kind`` from the next step on."""

class Simulation:
    """A scene simulated on the CPU or the GPU backend."""

    def __init__(self, scene: Scene, backend: _Backend = "cpu", threads: Optional[int] = None) -> None:
        """Builds ``scene`` on ``backend`` with ``threads`` CPU threads (all
        cores when None). Raises SceneError (a mesh or pattern file it
        names is bad), BackendError (no usable GPU, or a feature it lacks)
        or ValueError (an unknown backend)."""
    def step(self, frames: int = 1) -> None:
        """Advances ``frames`` frames of the scene's frame time, the GIL
        released; Ctrl-C stops between frames."""
    @property
    def positions(self) -> npt.NDArray[np.float32]:
        """Particle positions (m), shape (n, 3): on the CPU backend a
        read-only view that follows the simulation (no copy), on the GPU a
        new array read back from the device."""
    @property
    def velocities(self) -> npt.NDArray[np.float32]:
        """Particle velocities (m/s), shape (n, 3), as ``positions``."""
    def set_positions(self, positions: npt.ArrayLike) -> None:
        """Moves the particles to ``positions``, shape (n, 3)."""
    def set_velocities(self, velocities: npt.ArrayLike) -> None:
        """Sets the particles' velocities, shape (n, 3)."""
    @property
    def triangles(self) -> npt.NDArray[np.uint32]:
        """The triangles, shape (m, 3), particle indices (read-only view)."""
    @property
    def settings(self) -> Settings:
        """The live settings."""
    def grab(self, particle: int, target: _Vec3, compliance: float = 0.0) -> None:
        """Drags ``particle`` towards ``target`` (m) from the next step on,
        until ``release``; ``compliance`` (m/N) zero puts it there. The
        target moves there at a hand's speed (at most 5 m/s)."""
    def release(self) -> None:
        """Lets go of the grabbed particle, if any."""
    def report(self) -> Dict[str, Any]:
        """The run so far as report.json's fields: what ``pleat run SCENE
        --frames N --out DIR`` writes after the same frames."""
    def export(self, path: _Path) -> None:
        """Writes the current mesh: .obj, .ply (with normals) or .glb."""
    @property
    def particles(self) -> int:
        """Number of particles."""
    @property
    def frames(self) -> int:
        """Frames stepped so far."""
    @property
    def time(self) -> float:
        """Simulated time (s)."""
    @property
    def backend(self) -> str:
        """"cpu" or "gpu"."""
    @property
    def device(self) -> str:
        """The device stepping the simulation."""
    def __len__(self) -> int: ...

def fold(
    pattern: str,
    progress: float = 1.0,
    frames: int = 120,
    backend: _Backend = "cpu",
    threads: Optional[int] = None,
    out: Optional[_Path] = None,
    format: Literal["obj", "ply", "glb"] = "obj",
    every: int = 1,
    fold_out: Optional[_Path] = None,
    thickness: float = 0.0,
) -> Dict[str, Any]:
    """Folds a crease pattern (a .cp, .fold or .svg file, or a built-in such
    as "miura-ori") as ``pleat fold`` does (``thickness``: its
    ``--thickness``); returns report.json's fields."""

def bench(
    sizes: Sequence[int] = (64, 128, 256),
    backend: _Backend = "cpu",
    substeps: int = 10,
    self_collision: bool = False,
    frames: int = 60,
    warmup: int = 30,
    tethers: bool = False,
    threads: Optional[int] = None,
) -> List[Dict[str, Any]]:
    """Times the standard hanging cloth at each size as ``pleat bench
    --json`` does; one dict a size."""
