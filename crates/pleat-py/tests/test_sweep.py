"""pleat.sweep: variants as Ray tasks (2 local workers) or serially, the
same figures either way; failures as rows; the out folder and resuming."""

import json
import math

import pytest

import pleat
from pleat import _variant

#: Columns that are timings (they differ between any two runs).
TIMINGS = {"ms_per_frame"}

GRID = {
    "cloths[0].material.bend_compliance": [1e-4, 1e-2, 1.0, 100.0],
    "solver.substeps": [5, 10],
}


def rows(table):
    """The table as a list of dicts, whether pandas made it or not."""
    if isinstance(table, list):
        return table
    return [{k: (None if isinstance(v, float) and math.isnan(v) else v) for k, v in r.items()} for r in table.to_dict("records")]


def figures(table):
    return [{k: v for k, v in r.items() if k not in TIMINGS} for r in rows(table)]


def test_ray_sweep_matches_serial_figure_for_figure(small_drape, local_ray, tmp_path):
    scene = pleat.Scene.from_dict(small_drape)
    on_ray = pleat.sweep(scene, GRID, frames=20, out=tmp_path / "ray")
    serial = pleat.sweep(scene, GRID, frames=20, out=tmp_path / "serial", serial=True)
    assert len(rows(on_ray)) == 8
    assert figures(on_ray) == figures(serial)
    table = rows(on_ray)
    assert [r["variant"] for r in table] == list(range(8))
    assert [(r["cloths[0].material.bend_compliance"], r["solver.substeps"]) for r in table][:3] == [
        (1e-4, 5),
        (1e-4, 10),
        (1e-2, 5),
    ]
    assert all(r["exit_code"] == 0 and r["error"] is None for r in table)
    assert [r["substeps"] for r in table] == [5, 10] * 4
    # The variants differ: bending stiffness changes how the cloth drapes.
    assert len({r["kinetic_energy"] for r in table}) == 8
    # The Ray tasks ran on one thread each, the serial runs on all cores:
    # the figures do not depend on it.
    report = json.loads((tmp_path / "ray" / "variant_0003" / "report.json").read_text())
    assert report["threads"] == 1 and report["max_stretch"] == table[3]["max_stretch"]


def test_out_folder_and_manifest(small_drape, tmp_path):
    pleat.sweep(small_drape, {"solver.substeps": [4, 8]}, frames=5, out=tmp_path, serial=True)
    manifest = json.loads((tmp_path / "manifest.json").read_text())
    assert manifest["total"] == manifest["done"] == 2
    assert manifest["grid"] == {"solver.substeps": [4, 8]}
    assert [v["row"]["solver.substeps"] for v in manifest["variants"]] == [4, 8]
    folder = tmp_path / "variant_0001"
    assert json.loads((folder / "scene.json").read_text())["solver"]["substeps"] == 8
    assert json.loads((folder / "report.json").read_text())["substeps"] == 8
    assert (folder / "final.obj").read_text().startswith(("#", "v", "o"))


def test_an_interrupted_sweep_reruns_only_what_is_missing(small_drape, tmp_path, monkeypatch):
    grid = {"solver.substeps": [3, 4, 5]}
    first = rows(pleat.sweep(small_drape, grid, frames=5, out=tmp_path, serial=True))
    (tmp_path / "variant_0001" / "result.json").unlink()
    ran = []
    real = _variant.run

    def counting(job):
        ran.append(job["file"])
        return real(job)

    monkeypatch.setattr(_variant, "run", counting)
    again = rows(pleat.sweep(small_drape, grid, frames=5, out=tmp_path, serial=True))
    assert ran == ["<dict> (variant 1)"]
    assert figures(again) == figures(first)
    # Other frames are another sweep: nothing is reused.
    ran.clear()
    pleat.sweep(small_drape, grid, frames=6, out=tmp_path, serial=True)
    assert len(ran) == 3


def test_failed_variants_are_rows_and_the_sweep_goes_on(small_drape, tmp_path):
    grid = {"cloths[0].material.bend_compliance": [-1.0, 1.0]}
    table = rows(pleat.sweep(small_drape, grid, frames=5, out=tmp_path, serial=True))
    bad, good = table
    assert bad["exit_code"] == 2
    assert "(variant 0): cloths[0].material.bend_compliance: must be zero or positive" in bad["error"]
    assert bad["max_stretch"] is None
    assert good["exit_code"] == 0 and good["max_stretch"] > 0
    # A path the scene lacks fails the same way.
    table = rows(pleat.sweep(small_drape, {"cloths[3].material.density": [1.0]}, frames=5, serial=True))
    assert table[0]["exit_code"] == 2 and "cloths[3]: the scene has no such element" in table[0]["error"]


def test_an_unstable_variant_exits_1_with_when_and_where(tmp_path):
    stiff = {
        "name": "stiff_springs",
        "solver": {"kind": "mass_spring", "substeps": 1},
        "cloths": [
            {
                "mesh": {"grid": {"resolution": [32, 32], "orientation": "vertical", "center": [0, 1.5, 0]}},
                "material": {"spring_stiffness": {"structural": 50000, "shear": 50000, "bend": 100}},
                "pins": [{"corners": ["top_left", "top_right"]}],
            }
        ],
    }
    table = rows(pleat.sweep(stiff, {"solver.substeps": [1]}, frames=30, out=tmp_path, serial=True))
    assert table[0]["exit_code"] == 1
    assert table[0]["unstable"] and table[0]["error"].startswith("unstable (runaway) from 0.")
    assert json.loads((tmp_path / "variant_0000" / "report.json").read_text())["unstable"]


def test_bad_grids_are_refused(small_drape):
    with pytest.raises(ValueError, match="not a JSON path"):
        pleat.sweep(small_drape, {"solver..substeps": [1]}, serial=True)
    with pytest.raises(ValueError, match="non-empty list"):
        pleat.sweep(small_drape, {"solver.substeps": []}, serial=True)
    with pytest.raises(ValueError, match="unknown backend"):
        pleat.sweep(small_drape, {"solver.substeps": [1]}, backend="tpu", serial=True)
