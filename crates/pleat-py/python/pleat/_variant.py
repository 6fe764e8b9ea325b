"""One variant of a sweep: its scene, its run, and its outcome as the
``pleat run`` command would give it (report, exit status, error).

This is what a Ray task runs: plain data in (the variant's scene as JSON
text), plain data out (the report and the files to write), so a task runs
the same anywhere pleat is installed and the driver alone writes ``out/``.
"""

from __future__ import annotations

import json
import os
import tempfile
from typing import Any, Dict, Optional

from ._pleat import BackendError, Scene, SceneError, Simulation

#: The exit status of ``pleat run``: success, unstable run, bad input.
OK, UNSTABLE, BAD_INPUT = 0, 1, 2


def run(job: Dict[str, Any]) -> Dict[str, Any]:
    """Runs the variant ``job`` describes and returns its outcome.

    ``job`` holds ``scene_json``, ``file`` and ``base_dir`` (the variant's
    scene and where its relative paths start), ``frames`` (None: the
    scene's), ``backend``, ``threads`` and ``mesh`` (the extension of the
    final mesh: "obj", "ply" or "glb"). The outcome holds ``exit_code``,
    ``error`` (None on success), ``report`` (report.json's fields, None when
    the scene could not be built) and ``files`` (name to bytes).
    """
    outcome: Dict[str, Any] = {"exit_code": OK, "error": None, "report": None, "files": {}}
    try:
        scene = Scene.from_json(job["scene_json"], job["file"], job["base_dir"])
        sim = Simulation(scene, job["backend"], job["threads"])
    except (SceneError, BackendError, ValueError) as e:
        outcome.update(exit_code=BAD_INPUT, error=str(e))
        return outcome
    frames = job["frames"] if job["frames"] is not None else scene.frames
    sim.step(frames)
    report = sim.report()
    outcome["report"] = report
    outcome["files"]["report.json"] = (json.dumps(report, indent=2) + "\n").encode()
    problem = instability(report)
    if problem:
        outcome.update(exit_code=UNSTABLE, error=problem)
        return outcome
    name = "final." + job["mesh"]
    with tempfile.TemporaryDirectory() as tmp:
        path = os.path.join(tmp, name)
        sim.export(path)
        with open(path, "rb") as f:
            outcome["files"][name] = f.read()
    return outcome


def instability(report: Dict[str, Any]) -> Optional[str]:
    """What went wrong in a run, from its report, as the command says it;
    None for a stable run."""
    if not (report["nan"] or report["unstable"]):
        return None
    kind = report.get("unstable_kind") or ("non_finite" if report["nan"] else "unstable")
    at = report.get("unstable_at")
    particle = report.get("unstable_particle")
    when = f" from {at:.3f} s" if at is not None else ""
    where = f" (particle {particle})" if particle is not None else ""
    return f"unstable ({kind}){when}{where}"
