"""pleat.Simulation on the CPU backend: arrays, steps, live settings,
dragging, reports equal to the command's report.json, exports."""

import json

import numpy as np
import pytest

import pleat
from conftest import SCENES, write_json

#: report.json's fields that are timings (they differ between any two runs).
TIMINGS = {"ms_per_frame", "stages_ms"}


@pytest.fixture
def sim(small_drape):
    return pleat.Simulation(pleat.Scene.from_dict(small_drape), threads=2)


def test_shapes_and_dtypes(sim):
    n = 16 * 16
    assert len(sim) == sim.particles == n
    for array in (sim.positions, sim.velocities):
        assert array.shape == (n, 3) and array.dtype == np.float32
    triangles = sim.triangles
    assert triangles.shape == (2 * 15 * 15, 3) and triangles.dtype == np.uint32
    assert triangles.max() == n - 1


def test_a_step_moves_the_cloth(sim):
    before = np.array(sim.positions)
    sim.step()
    after = sim.positions
    assert sim.frames == 1 and sim.time == pytest.approx(1 / 60)
    assert np.all(after[:, 1] < before[:, 1])  # falling
    assert np.all(sim.velocities[:, 1] < 0)


def test_cpu_positions_are_a_read_only_view_that_follows_the_steps(sim):
    view = sim.positions
    assert not view.flags.writeable
    assert np.shares_memory(view, sim.positions)  # no copy per read
    with pytest.raises(ValueError):
        view[0, 0] = 1.0
    y = float(view[0, 1])
    sim.step(5)
    assert view[0, 1] < y


def test_set_positions_and_velocities(sim):
    lifted = np.array(sim.positions, dtype=np.float64) + [0.0, 1.0, 0.0]
    sim.set_positions(lifted)  # float64 is converted
    np.testing.assert_allclose(sim.positions, lifted, rtol=0, atol=1e-6)
    sim.set_velocities(np.zeros((len(sim), 3), np.float32))
    assert not sim.velocities.any()
    with pytest.raises(ValueError, match=r"shape \(256, 3\)"):
        sim.set_positions(np.zeros((3, 3)))


def test_live_settings_take_effect_without_a_rebuild(small_drape):
    scene = pleat.Scene.from_dict(small_drape)
    live, control = pleat.Simulation(scene), pleat.Simulation(scene)
    live.step(10)
    control.step(10)
    at = np.array(live.positions)
    live.settings.gravity = (0.0, 9.81, 0.0)
    live.settings.substeps = 20
    # The state is kept: nothing was rebuilt or reset.
    np.testing.assert_array_equal(live.positions, at)
    assert live.frames == 10
    live.step(10)
    control.step(10)
    # Gravity up lifts the cloth above the one still pulled down.
    assert live.positions[:, 1].mean() > control.positions[:, 1].mean() + 0.1
    report = live.report()
    assert report["substeps"] == 20 and report["frames"] == 20
    assert live.settings.gravity == pytest.approx([0.0, 9.81, 0.0])


def test_live_wind_and_compliance(small_hanging):
    scene = pleat.Scene.from_dict(small_hanging)
    windy, still = pleat.Simulation(scene), pleat.Simulation(scene)
    assert windy.settings.wind is None
    windy.settings.wind = (0.0, 0.0, 8.0)
    windy.step(20)
    still.step(20)
    assert windy.positions[:, 2].mean() > still.positions[:, 2].mean() + 0.01
    windy.settings.wind = None
    assert windy.settings.wind is None
    windy.settings.set_compliance("bend", 0.5)
    assert windy.settings.compliance("bend") == 0.5
    with pytest.raises(ValueError, match="unknown compliance"):
        windy.settings.compliance("twist")


def test_settings_refuse_out_of_range_values(sim):
    with pytest.raises(ValueError, match="settings.substeps: must be between 1 and 1000, got 0"):
        sim.settings.substeps = 0
    with pytest.raises(ValueError, match="settings.fold_progress"):
        sim.settings.fold_progress = 1.5
    assert sim.settings.substeps == 10


def test_fold_progress_is_live(tmp_path):
    scene = json.loads((SCENES / "fold_waterbomb.json").read_text())
    sim = pleat.Simulation(pleat.Scene.from_dict(scene, base_dir=SCENES))
    sim.settings.fold_progress = 0.0
    sim.step(30)
    assert thickness(sim.positions) < 1e-3  # the ramp is stopped: still flat
    sim.settings.fold_progress = 0.8
    sim.step(60)
    assert sim.settings.fold_progress == pytest.approx(0.8)
    assert sim.report()["origami"]["fold_progress"] == pytest.approx(0.8)
    assert thickness(sim.positions) > 0.05


def test_a_patterns_importer_warning_is_a_python_warning(tmp_path):
    # A unit square folded flat along its diagonal, with neither a mountain
    # or valley label nor faceOrders to say which way: not driven, and said.
    fold = {
        "frame_classes": ["foldedForm"],
        "vertices_coords": [[0, 0, 0], [1, 0, 0], [0, 0, 0], [0, 1, 0]],
        "faces_vertices": [[0, 1, 3], [1, 2, 3]],
    }
    (tmp_path / "flat.fold").write_text(json.dumps(fold))
    scene = {"name": "undirected", "cloths": [{"mesh": {"pattern": {"path": "flat.fold"}}}]}
    with pytest.warns(UserWarning, match=r"cloths\[0\]\.mesh\.pattern: .*flat\.fold: 1 crease is folded flat"):
        pleat.Simulation(pleat.Scene.from_dict(scene, base_dir=tmp_path))


def thickness(points):
    """The spread of `points` across their best-fitting plane (m)."""
    centred = points - points.mean(axis=0)
    return np.linalg.svd(centred, compute_uv=False)[-1] / np.sqrt(len(points))


def test_grab_drags_a_particle_to_the_target_until_released(sim):
    target = (0.3, 1.2, -0.1)
    start = sim.positions[0].copy()
    sim.grab(0, target)
    sim.step(1)
    # At a hand's speed: at most 5 m/s over the frame of 1/60 s.
    assert np.linalg.norm(sim.positions[0] - start) <= 5.0 / 60.0 + 1e-4
    sim.step(60)
    np.testing.assert_allclose(sim.positions[0], target, atol=1e-4)
    sim.release()
    sim.step(10)
    assert np.linalg.norm(sim.positions[0] - target) > 0.05
    with pytest.raises(IndexError):
        sim.grab(len(sim), target)


@pytest.mark.parametrize("scene_file", ["hanging.json", "drape.json"])
def test_report_equals_the_commands_report_json(scene_file, tmp_path, run_cli):
    path = SCENES / scene_file
    frames = 12
    run_cli("run", path, "--frames", frames, "--out", tmp_path, check_code=0)
    cli = json.loads((tmp_path / "report.json").read_text())
    sim = pleat.Simulation(pleat.Scene.load(path))
    sim.step(frames)
    report = sim.report()
    assert set(report) == set(cli)
    assert {k: v for k, v in report.items() if k not in TIMINGS} == {
        k: v for k, v in cli.items() if k not in TIMINGS
    }
    assert set(report["stages_ms"]) == set(cli["stages_ms"])


def test_export_obj_ply_glb(sim, tmp_path):
    sim.step(2)
    for ext in ("obj", "ply", "glb"):
        sim.export(tmp_path / f"mesh.{ext}")
        assert (tmp_path / f"mesh.{ext}").stat().st_size > 1000
    lines = (tmp_path / "mesh.obj").read_text().splitlines()
    vertices = [l for l in lines if l.startswith("v ")]
    assert len(vertices) == len(sim)
    first = [float(c) for c in vertices[0].split()[1:4]]
    np.testing.assert_allclose(first, sim.positions[0], atol=1e-5)
    assert (tmp_path / "mesh.glb").read_bytes()[:4] == b"glTF"
    with pytest.raises(ValueError, match="unknown mesh format"):
        sim.export(tmp_path / "mesh.stl")
    with pytest.raises(OSError, match="nowhere"):
        sim.export(tmp_path / "nowhere" / "mesh.obj")


def test_unknown_backend_and_threads():
    with pytest.raises(ValueError, match="unknown backend 'tpu'"):
        pleat.Simulation(pleat.Scene.default(), backend="tpu")
    with pytest.raises(ValueError, match="threads"):
        pleat.Simulation(pleat.Scene.default(), threads=0)


def test_same_figures_for_any_thread_count(small_drape):
    scene = pleat.Scene.from_dict(small_drape)
    runs = []
    for threads in (1, 2):
        sim = pleat.Simulation(scene, threads=threads)
        sim.step(20)
        runs.append(np.array(sim.positions))
    np.testing.assert_array_equal(runs[0], runs[1])
