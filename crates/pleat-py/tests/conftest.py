"""Shared fixtures: the repository's scenes, the `pleat` command to compare
against, small scenes, and one local Ray for the session."""

import copy
import json
import os
import shutil
import subprocess
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[3]
SCENES = ROOT / "scenes"

#: A 16 x 16 cloth dropped on a sphere: quick to run, with contacts.
SMALL_DRAPE = {
    "name": "small_drape",
    "frames": 30,
    "fps": 60,
    "solver": {"kind": "xpbd", "substeps": 10, "iterations": 1, "damping": 0.1},
    "cloths": [
        {
            "name": "cloth",
            "mesh": {"grid": {"resolution": [16, 16], "size": [1.0, 1.0], "orientation": "horizontal", "center": [0.0, 0.8, 0.0]}},
            "material": {"density": 0.2, "stretch_compliance": 0.0, "shear_compliance": 1e-6, "bend_compliance": 1.0, "thickness": 0.005},
        }
    ],
    "colliders": [{"shape": {"sphere": {"center": [0.0, 0.35, 0.0], "radius": 0.35}}}],
}

#: A 16 x 16 cloth hanging from its two top corners.
SMALL_HANGING = {
    "name": "small_hanging",
    "frames": 30,
    "cloths": [
        {
            "mesh": {"grid": {"resolution": [16, 16], "orientation": "vertical", "center": [0.0, 1.5, 0.0]}},
            "pins": [{"corners": ["top_left", "top_right"]}],
        }
    ],
}


@pytest.fixture
def small_drape():
    return copy.deepcopy(SMALL_DRAPE)


@pytest.fixture
def small_hanging():
    return copy.deepcopy(SMALL_HANGING)


@pytest.fixture(scope="session")
def pleat_bin():
    """The `pleat` command: $PLEAT_BIN (cargo xtask test sets it to the
    workspace's build) or the one on PATH."""
    path = os.environ.get("PLEAT_BIN") or shutil.which("pleat")
    if not path:
        pytest.fail("set PLEAT_BIN to the `pleat` command (cargo xtask test does)")
    return path


@pytest.fixture(scope="session")
def run_cli(pleat_bin):
    """Runs `pleat ARGS...`; returns the completed process."""

    def run(*args, check_code=None):
        done = subprocess.run([pleat_bin, *map(str, args)], capture_output=True, text=True)
        if check_code is not None:
            assert done.returncode == check_code, done.stderr
        return done

    return run


@pytest.fixture(scope="session")
def local_ray():
    """A local Ray with 2 workers (CPUs) for the session."""
    import ray

    ray.init(num_cpus=2, include_dashboard=False)
    yield ray
    ray.shutdown()


def write_json(path, value):
    path.write_text(json.dumps(value))
    return path
