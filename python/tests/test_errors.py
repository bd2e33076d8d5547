"""Bad paths and corrupt files raise Python exceptions with the CLI's messages, never crash."""

import pytest

import lorgnette
from conftest import cli_error


def test_missing_files_raise_file_not_found(tmp_path):
    missing = str(tmp_path / "missing")
    for call in (lambda: lorgnette.Model.load(missing + ".lnerf"),
                 lambda: lorgnette.Glasses.load(missing + ".glb"),
                 lambda: lorgnette.Placement.load(missing + ".json"),
                 lambda: lorgnette.Camera.from_pose(missing + ".json"),
                 lambda: lorgnette.Camera.from_transforms(missing),
                 lambda: lorgnette.load_image(missing + ".png")):
        with pytest.raises(FileNotFoundError, match="does not exist"):
            call()


def test_corrupt_model_has_the_cli_message(tmp_path, model_path):
    bad = tmp_path / "bad.lnerf"
    bad.write_bytes(b"not a model at all" * 10)
    truncated = tmp_path / "truncated.lnerf"
    truncated.write_bytes(model_path.read_bytes()[:5000])
    pose = tmp_path / "pose.json"
    pose.write_text('{"transform_matrix": [[1,0,0,0],[0,1,0,0],[0,0,1,3],[0,0,0,1]]}')
    for path in (bad, truncated):
        with pytest.raises(lorgnette.Error) as info:
            lorgnette.Model.load(str(path))
        assert str(info.value) == cli_error("render", path, "--pose", pose, "-o", tmp_path / "out")


def test_corrupt_glasses_placement_and_pose(tmp_path, model):
    junk = tmp_path / "junk.glb"
    junk.write_bytes(b"\x00\x01garbage" * 50)
    with pytest.raises(lorgnette.Error) as info:
        lorgnette.Glasses.load(str(junk))
    assert str(info.value) == cli_error("glasses", "inspect", junk)
    placement = tmp_path / "placement.json"
    placement.write_text('{"version": 1, "transform": [[1, 2], "x"]}')
    with pytest.raises(lorgnette.Error, match="placement.json"):  # the fit's reader names the field
        lorgnette.Placement.load(str(placement))
    placement.write_text("{ not json")
    with pytest.raises(lorgnette.Error):
        lorgnette.Placement.load(str(placement))
    pose = tmp_path / "pose.json"
    pose.write_text('{"no_matrix": 1}')
    with pytest.raises(lorgnette.Error, match="transform_matrix"):
        lorgnette.Camera.from_pose(str(pose))
    image = tmp_path / "image.png"
    image.write_bytes(b"\x89PNG\r\n\x1a\n" + b"\x00" * 40)
    with pytest.raises(lorgnette.Error):
        lorgnette.load_image(str(image))


def test_bad_arguments(model, tmp_path):
    camera = model.orbit(1, size=(32, 24))[0]
    with pytest.raises(ValueError):
        model.render(camera, spp=0)
    with pytest.raises(lorgnette.Error, match="no glasses"):
        model.render(camera, placement=lorgnette.trs())
    with pytest.raises(lorgnette.Error):
        lorgnette.Glasses.make(5, 18, 140, "rect", path=str(tmp_path / "tiny.glb"))
    with pytest.raises(lorgnette.Error):
        lorgnette.Glasses.make(52, 18, 140, "hexagon", path=str(tmp_path / "hex.glb"))
    with pytest.raises(lorgnette.Error):
        lorgnette.use_device("no-such-device-anywhere")
    with pytest.raises(lorgnette.Error):
        lorgnette.Camera.look_at(eye=(0, 0, 0), target=(0, 0, 0))
    with pytest.raises(ValueError, match="hair_mm"):
        lorgnette.train(str(tmp_path), str(tmp_path / "m.lnerf"), steps=1, hair_mm=-5)


def test_devices():
    devices = lorgnette.devices()
    assert devices and sum(d["selected"] for d in devices) == 1
    assert lorgnette.device()["index"] == next(d["index"] for d in devices if d["selected"])


def test_train_never_writes_the_model_over_the_dataset(dataset):
    target = dataset / "transforms.json"
    before = target.read_bytes()
    with pytest.raises(lorgnette.Error, match="is the input"):
        lorgnette.train(str(dataset), str(target), steps=1, force=True)
    assert target.read_bytes() == before
