"""pleat.fold and pleat.bench: the commands' work, as dicts."""

import json

import pytest

import pleat

TIMINGS = {"ms_per_frame", "stages_ms"}


def test_fold_returns_the_commands_report(tmp_path, run_cli):
    cli_out, py_out = tmp_path / "cli", tmp_path / "py"
    run_cli("fold", "waterbomb-base", "--frames", 20, "--out", cli_out, "--every", 100, check_code=0)
    cli = json.loads((cli_out / "report.json").read_text())
    report = pleat.fold("waterbomb-base", frames=20, out=py_out, every=100, fold_out=py_out / "folded.fold")
    assert {k: v for k, v in report.items() if k not in TIMINGS} == {
        k: v for k, v in cli.items() if k not in TIMINGS
    }
    assert report["origami"]["fold_progress"] == pytest.approx(1.0)
    assert json.loads((py_out / "report.json").read_text())["frames"] == 80
    folded = json.loads((py_out / "folded.fold").read_text())
    assert folded["frame_classes"] == ["foldedForm"] and folded["edges_foldAngle"]


def test_fold_with_a_thickness_keeps_the_layers_apart_and_folds_flat():
    def worst(report):
        errors = report["origami"]["max_fold_angle_error_deg"]
        return max(errors["mountain"], errors["valley"])

    without = pleat.fold("waterbomb-base", frames=60)
    report = pleat.fold("waterbomb-base", frames=60, thickness=0.0005)
    assert without["self_contacts_per_frame"] == 0 and report["self_contacts_per_frame"] > 0
    assert report["self_intersections"] == 0
    # Creases go to 180 degrees with a thickness, to 178 without.
    assert worst(report) < 1.0 < worst(without)


def test_fold_refuses_bad_input():
    with pytest.raises(ValueError, match="--progress must be between 0 and 1"):
        pleat.fold("waterbomb-base", progress=2.0)
    with pytest.raises(ValueError, match="neither a crease-pattern file nor a built-in"):
        pleat.fold("no-such-pattern")
    with pytest.raises(ValueError, match="unknown format"):
        pleat.fold("waterbomb-base", format="stl")
    with pytest.raises(ValueError, match="--thickness must be at least 0"):
        pleat.fold("waterbomb-base", thickness=-0.001)


def test_bench_lines():
    lines = pleat.bench(sizes=[8, 12], frames=3, warmup=1, threads=1)
    assert [l["n"] for l in lines] == [8, 12]
    assert [l["particles"] for l in lines] == [64, 144]
    assert all(l["backend"] == "cpu" and l["ms_per_frame"] > 0 and l["threads"] == 1 for l in lines)
    with pytest.raises(ValueError, match="sizes are 2 to 4096"):
        pleat.bench(sizes=[1])
