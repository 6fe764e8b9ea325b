"""``pleat.sweep``: a scene run over a grid of parameter values, each
variant a Ray task (local Ray by default, a cluster with ``address=``) or,
with ``serial=True``, one after the other in this process.

Keys of the grid are JSON paths into the scene, as scene errors name them
(``cloths[0].material.bend_compliance``, ``solver.substeps``); the
variants are the cartesian product of the values, in the grid's order. A
variant's figures depend only on its scene, frames and backend (pleat's
solvers give the same result for any thread count), so the same variant
gives the same figures wherever it runs.
"""

from __future__ import annotations

import copy
import itertools
import json
import os
from typing import Any, Callable, Dict, List, Mapping, Optional, Sequence, Tuple, Union

from . import _paths, _store, _variant
from ._pleat import Scene
from ._progress import Progress

#: report.json's figures each row of the table carries (plus ms_per_frame,
#: the mean time per frame).
FIGURES = (
    "frames",
    "substeps",
    "particles",
    "max_stretch",
    "mean_stretch",
    "nan",
    "unstable",
    "unstable_at",
    "unstable_kind",
    "self_intersections",
    "collider_penetrations",
    "kinetic_energy",
)

SceneLike = Union[Scene, Mapping[str, Any], str, "os.PathLike[str]"]
Job = Dict[str, Any]


def sweep(
    scene: SceneLike,
    grid: Mapping[str, Sequence[Any]],
    *,
    frames: Optional[int] = None,
    backend: str = "cpu",
    out: Union[str, "os.PathLike[str]", None] = None,
    threads: Optional[int] = None,
    serial: bool = False,
    address: Optional[str] = None,
    workers: Optional[int] = None,
    mesh: str = "obj",
    progress: Optional[bool] = None,
) -> Any:
    """Runs every variant of ``scene`` in ``grid`` and tabulates them.

    Args:
        scene: a :class:`pleat.Scene`, a scene file's path or a scene dict.
        grid: JSON path to the values it takes, e.g.
            ``{"cloths[0].material.bend_compliance": [1e-3, 1.0],
            "solver.substeps": [5, 10, 20]}``.
        frames: frames each variant runs (default: the scene's).
        backend: "cpu" or "gpu".
        out: a folder for each variant's scene.json, report.json, final mesh
            and result.json, and manifest.json. Run again with the same
            ``out``, a sweep reruns only the variants not finished before.
        threads: CPU threads a variant steps on; default all cores when
            serial, 1 per Ray task (Ray runs tasks side by side).
        serial: run in this process, one variant after another, without Ray.
        address: the Ray cluster to run on (default: a local Ray, started for
            the sweep and stopped after, unless one is running already).
        workers: CPUs of a local Ray started for the sweep (default: all).
        mesh: the final mesh's format: "obj", "ply" or "glb".
        progress: draw a progress bar on stderr (default: on a terminal).

    Returns:
        One row a variant, in grid order: ``variant`` (its number), the
        grid's keys with their values, ``exit_code`` (what ``pleat run`` would
        exit with: 0, 1 for a run gone NaN or unstable, 2 for a bad scene;
        None if its task died), ``error`` (None on success), report.json's
        :data:`FIGURES` and ``ms_per_frame``. A pandas DataFrame if pandas
        is installed, else a list of dicts.
    """
    base = _scene(scene)
    keys = _check_grid(grid)
    if backend not in ("cpu", "gpu"):
        raise ValueError(f"unknown backend '{backend}': use cpu or gpu")
    if mesh not in ("obj", "ply", "glb"):
        raise ValueError(f"unknown mesh format '{mesh}': use obj, ply or glb")
    if frames is not None and frames < 1:
        raise ValueError(f"frames must be at least 1, got {frames}")
    task_threads = threads if threads is not None or serial else 1
    variants = [dict(zip(keys, values)) for values in itertools.product(*grid.values())]
    jobs = [_job(base, i, params, frames, backend, task_threads, mesh) for i, params in enumerate(variants)]

    store = _store.Store(out) if out is not None else None
    header = {
        "scene": base.file,
        "base_dir": os.fspath(base.base_dir),
        "frames": frames if frames is not None else base.frames,
        "backend": backend,
        "grid": {k: list(v) for k, v in grid.items()},
    }
    rows: List[Optional[Dict[str, Any]]] = [None] * len(jobs)
    bar = Progress(len(jobs), progress)
    todo: List[Tuple[int, Job]] = []
    for i, job in enumerate(jobs):
        earlier = store.done(i, _store.key(job)) if store and "scene_json" in job else None
        if earlier is not None:
            rows[i] = earlier
            bar.advance(failed=earlier["exit_code"] != 0, reused=True)
        elif "scene_json" not in job:
            # The grid named a path the scene lacks: the variant fails as
            # bad input, as a scene file with that mistake would.
            rows[i] = _row(i, variants[i], _variant_failure(job["error"]))
            bar.advance(failed=True)
        else:
            todo.append((i, job))
    if store:
        store.manifest(header, rows)

    def finished(i: int, outcome: Dict[str, Any]) -> None:
        row = _row(i, variants[i], outcome)
        rows[i] = row
        if store and outcome["exit_code"] is not None:
            files = dict(outcome["files"], **{"scene.json": jobs[i]["scene_json"].encode()})
            store.save(i, _store.key(jobs[i]), row, files)
            store.manifest(header, rows)
        bar.advance(failed=row["exit_code"] != 0)

    try:
        if serial:
            for i, job in todo:
                finished(i, _variant.run(job))
        else:
            _on_ray(todo, finished, address, workers)
    finally:
        bar.close()
    return _table([r for r in rows if r is not None])


def _scene(scene: SceneLike) -> Scene:
    if isinstance(scene, Scene):
        return scene
    if isinstance(scene, Mapping):
        return Scene.from_dict(dict(scene))
    return Scene.load(os.fspath(scene))


def _check_grid(grid: Mapping[str, Sequence[Any]]) -> List[str]:
    if not isinstance(grid, Mapping) or not grid:
        raise ValueError("grid must be a non-empty dict of JSON path to values")
    for key, values in grid.items():
        _paths.parse(key)
        if isinstance(values, (str, bytes)) or not isinstance(values, Sequence) or not values:
            raise ValueError(f"grid[{key!r}] must be a non-empty list of values")
    return list(grid)


def _job(base: Scene, index: int, params: Dict[str, Any], frames: Optional[int], backend: str, threads: Optional[int], mesh: str) -> Job:
    job: Job = {"frames": frames, "backend": backend, "threads": threads, "mesh": mesh}
    data = base.to_dict()
    try:
        for key, value in params.items():
            _paths.set_value(data, key, copy.deepcopy(value))
    except KeyError as e:
        job["error"] = f"{base.file}: {e.args[0]}"
        return job
    job.update(
        scene_json=json.dumps(data),
        file=f"{base.file} (variant {index})",
        base_dir=os.fspath(base.base_dir),
    )
    return job


def _variant_failure(error: str) -> Dict[str, Any]:
    return {"exit_code": _variant.BAD_INPUT, "error": error, "report": None, "files": {}}


def _row(index: int, params: Dict[str, Any], outcome: Dict[str, Any]) -> Dict[str, Any]:
    row: Dict[str, Any] = {"variant": index}
    row.update(params)
    row["exit_code"] = outcome["exit_code"]
    row["error"] = outcome["error"]
    report = outcome["report"] or {}
    for name in FIGURES:
        row[name] = report.get(name)
    row["ms_per_frame"] = report["ms_per_frame"]["mean"] if report else None
    return row


def _on_ray(
    todo: List[Tuple[int, Job]],
    finished: Callable[[int, Dict[str, Any]], None],
    address: Optional[str],
    workers: Optional[int],
) -> None:
    """Runs the jobs as Ray tasks, handing each outcome to ``finished`` as
    it arrives."""
    if not todo:
        return
    import ray

    started = not ray.is_initialized()
    if started:
        if address is not None:
            ray.init(address=address)
        else:
            ray.init(num_cpus=workers, include_dashboard=False)
    try:
        # Every job asks for the same threads: one remote function for all.
        task = ray.remote(num_cpus=todo[0][1]["threads"] or 1)(_variant.run)
        pending = {task.remote(job): i for i, job in todo}
        while pending:
            ready, _ = ray.wait(list(pending), num_returns=1)
            for ref in ready:
                i = pending.pop(ref)
                try:
                    outcome = ray.get(ref)
                except ray.exceptions.RayError as e:
                    outcome = {"exit_code": None, "error": f"the Ray task failed: {e}", "report": None, "files": {}}
                finished(i, outcome)
    finally:
        if started:
            ray.shutdown()


def _table(rows: List[Dict[str, Any]]) -> Any:
    try:
        import pandas
    except ImportError:
        return rows
    return pandas.DataFrame(rows)
