"""Scenes from a file, JSON text or a dict: the command's validation and
messages, raised as pleat.SceneError with the file and the JSON path."""

import json

import pytest

import pleat
from conftest import SCENES, write_json


def test_load_from_file_json_and_dict_agree(small_drape, tmp_path):
    path = write_json(tmp_path / "small.json", small_drape)
    from_file = pleat.Scene.load(path)
    from_text = pleat.Scene.from_json(json.dumps(small_drape))
    from_dict = pleat.Scene.from_dict(small_drape)
    assert from_file.file == str(path)
    assert from_file.name == from_text.name == from_dict.name == "small_drape"
    assert from_file.to_dict() == from_text.to_dict() == from_dict.to_dict()
    assert from_file.frames == 30
    assert from_file.frame_dt == pytest.approx(1 / 60)


def test_to_dict_round_trips_with_every_default(small_hanging):
    scene = pleat.Scene.from_dict(small_hanging)
    full = scene.to_dict()
    # Defaults are written out: a sweep's paths point into them.
    assert full["solver"]["substeps"] == 10
    assert "bend_compliance" in full["cloths"][0]["material"]
    assert pleat.Scene.from_dict(full).to_dict() == full


def test_default_scene_is_the_embedded_drape():
    scene = pleat.Scene.default()
    assert scene.name == "drape"
    assert scene.frames == 300


def test_bad_value_names_file_path_and_reason_as_the_command_does(small_drape, tmp_path, run_cli):
    small_drape["cloths"][0]["material"]["bend_compliance"] = -1.0
    path = write_json(tmp_path / "bad.json", small_drape)
    with pytest.raises(pleat.SceneError) as caught:
        pleat.Scene.load(path)
    e = caught.value
    assert isinstance(e, ValueError)
    assert e.file == str(path)
    assert e.path == "cloths[0].material.bend_compliance"
    assert "-1" in e.reason
    assert str(e) == f"{path}: cloths[0].material.bend_compliance: {e.reason}"
    # `pleat check` prints the same message.
    check = run_cli("check", path, check_code=1)
    assert str(e) in check.stdout


def test_every_error_is_listed(small_drape):
    small_drape["cloths"][0]["material"]["density"] = -2.0
    small_drape["solver"]["substeps"] = 0
    with pytest.raises(pleat.SceneError) as caught:
        pleat.Scene.from_dict(small_drape, file="mine")
    paths = {e["path"] for e in caught.value.errors}
    assert paths == {"cloths[0].material.density", "solver.substeps"}
    assert all(e["file"] == "mine" for e in caught.value.errors)
    assert len(str(caught.value).splitlines()) == 2


def test_unknown_field_and_wrong_type_name_the_json_path(small_drape):
    small_drape["cloths"][0]["material"]["densty"] = 1.0
    with pytest.raises(pleat.SceneError) as caught:
        pleat.Scene.from_dict(small_drape)
    assert caught.value.path == "cloths[0].material.densty"
    assert "densty" in caught.value.reason
    with pytest.raises(pleat.SceneError) as caught:
        pleat.Scene.from_json('{"cloths": [{"mesh": 3}]}', file="text")
    assert caught.value.file == "text"
    assert caught.value.path == "cloths[0].mesh"


def test_missing_file_is_a_scene_error(tmp_path):
    with pytest.raises(pleat.SceneError) as caught:
        pleat.Scene.load(tmp_path / "nowhere.json")
    assert "cannot read the file" in str(caught.value)


def test_missing_mesh_is_a_scene_error_when_built(tmp_path):
    scene = json.loads((SCENES / "bunny_drape.json").read_text())
    path = write_json(tmp_path / "bunny.json", scene)  # its meshes/ folder is not here
    with pytest.raises(pleat.SceneError) as caught:
        pleat.Simulation(pleat.Scene.load(path))
    assert caught.value.file == str(path)
    assert caught.value.path
