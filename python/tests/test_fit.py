"""lorgnette.fit against `lorgnette fit`, landmark callables, and Placement (placement.json)."""

import json

import numpy as np
import pytest

import lorgnette


def comparable(placement_json):
    """placement.json without the per-stage seconds (wall-clock timings differ between runs)."""
    data = dict(placement_json)
    data.pop("seconds", None)
    return data


def test_fit_with_python_dlib_landmarks_equals_cli(model, frame_path, cli_placement):
    calls = []

    def detector(image, face_px=0.0):  # landmarks supplied from Python: the project's dlib adapter
        assert image.dtype == np.uint8 and image.ndim == 3 and image.shape[2] == 3
        calls.append(image.shape)
        return lorgnette.dlib_landmarks(image, face_px=face_px)

    placement = lorgnette.fit(model, str(frame_path), landmarks=detector, views=6)
    assert calls, "the callable was never called"
    cli = json.loads(cli_placement.read_text())
    assert comparable(placement.data) == comparable(cli)
    assert placement.ok and 50.0 < placement.pd_mm < 80.0
    # The scale's source and the fit advice (#44), as placement.json has them.
    assert placement.scale_source in ("card", "iris", "mean-face")
    assert placement.scale_source == cli["scale_source"]
    assert 0.0 < placement.pd_uncertainty_mm < placement.pd_mm
    assert placement.advice == cli["advice"]
    assert [r["name"] for r in placement.advice["rules"]] == [
        "frame_width", "bridge", "temple_length", "lens_height"]


def test_landmark_callable_without_face_raises(model, frame_path):
    with pytest.raises(lorgnette.Error, match="face"):
        lorgnette.fit(model, str(frame_path), landmarks=lambda image: None, views=3, resolution=96)


def test_landmark_callable_that_raises(model, frame_path):
    def broken(image):
        raise ValueError("detector exploded")

    with pytest.raises(lorgnette.LandmarkError, match="detector exploded") as info:
        lorgnette.fit(model, str(frame_path), landmarks=broken, views=3, resolution=96)
    assert isinstance(info.value.__cause__, ValueError)
    assert isinstance(info.value, lorgnette.Error)


def test_landmark_callable_with_bad_result(model, frame_path):
    with pytest.raises(lorgnette.LandmarkError, match="68"):
        lorgnette.fit(model, str(frame_path), landmarks=lambda image: np.zeros((5, 2)), views=3, resolution=96)
    with pytest.raises(TypeError):
        lorgnette.fit(model, str(frame_path), landmarks="not callable")


def test_placement_round_trip(tmp_path, cli_placement):
    placement = lorgnette.Placement.load(str(cli_placement))
    out = tmp_path / "copy.json"
    placement.save(str(out))
    saved, original = json.loads(out.read_text()), json.loads(cli_placement.read_text())
    assert comparable(saved) == comparable(original)
    # seconds are written rounded (fit/placement_json.cpp), so a re-write may move the last digit
    assert saved["seconds"] == pytest.approx(original["seconds"], abs=1e-8)
    with pytest.raises(lorgnette.Error, match="exists"):
        placement.save(str(out))
    moved = placement.adjusted(translate_mm=(0.0, -2.0, 0.0))
    delta = moved.transform[:3, 3] - placement.transform[:3, 3]
    # 2 mm down the frame's own y axis, in scene units (the transform's y column)
    np.testing.assert_allclose(delta, -2.0 * placement.transform[:3, 1], atol=1e-6)
    moved.transform = placement.transform
    np.testing.assert_array_equal(moved.transform, placement.transform)
    again = lorgnette.Placement.from_json(placement.to_json())
    assert again.data == placement.data


def test_glasses_make_and_reference_points(tmp_path):
    glasses = lorgnette.Glasses.make(52, 18, 140, "round", path=str(tmp_path / "f.glb"))
    size = glasses.size_mm
    assert size["lens_width"] == pytest.approx(52, abs=1.0) and size["bridge"] == pytest.approx(18, abs=1.0)
    ref = glasses.reference_points
    assert np.allclose(ref["g_c"], 0.0) and ref["g_l"][0] > 0 > ref["g_r"][0]
    verts = glasses.vertices()
    moved = glasses.vertices(lorgnette.trs(translate=(1.0, 2.0, 3.0)))
    np.testing.assert_allclose(moved - verts, np.broadcast_to([1.0, 2.0, 3.0], verts.shape), atol=1e-5)
    with pytest.raises(lorgnette.Error, match="exists"):
        lorgnette.Glasses.make(52, 18, 140, "round", path=str(tmp_path / "f.glb"))


def test_placement_refuses_broken_transforms_and_warns_for_another_frame(tmp_path, model, cli_placement):
    """The placement module's checks reach Python: broken transforms raise, another frame warns."""
    for bad in (np.zeros((4, 4)), np.diag([1e300, 1e300, 1e300, 1.0]), np.full((4, 4), np.nan)):
        with pytest.raises(ValueError, match="transform"):
            lorgnette.Placement.from_transform(bad)
    data = json.loads(cli_placement.read_text())
    data["transform"] = [[0, 0, 0, 0]] * 3 + [[0, 0, 0, 1]]
    broken = tmp_path / "broken.json"
    broken.write_text(json.dumps(data))
    with pytest.raises(lorgnette.Error, match="transform"):
        lorgnette.Placement.load(str(broken))
    placement = lorgnette.Placement.load(str(cli_placement))
    with pytest.raises(ValueError, match="transform"):
        placement.transform = np.zeros((4, 4))
    other = lorgnette.Glasses.make(48, 20, 135, "round", path=str(tmp_path / "other.glb"))
    camera = model.orbit(1, size=(32, 24))[0]
    with pytest.warns(UserWarning, match="another glasses file"):
        model.render(camera, other, placement)
