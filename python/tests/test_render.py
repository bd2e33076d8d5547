"""Model.render against `lorgnette render`: the same camera gives the same pixels, bit for bit.

The CLI writes 8-bit sRGB PNGs (lossy against the float render) and float32 depth EXRs (lossless),
so the colour is compared after lorgnette.to_srgb8 (the CLI's own conversion) with the PNG's stored
bytes, and the depth as float32 with the EXR.
"""

import numpy as np
import pytest

import lorgnette
from conftest import count_during, run_cli, write_pose

SIZE = (96, 72)


def cli_render(work, model_path, camera, name, *extra):
    pose = write_pose(work / f"{name}.pose.json", camera)
    out = work / name
    run_cli("render", model_path, "--pose", pose, "--size", f"{SIZE[0]}x{SIZE[1]}", "-o", out, "--no-video", *extra)
    colour = lorgnette.load_image(str(out / "frame_0000.png"), raw=True)
    depth = lorgnette.load_image(str(out / "depth_0000.exr"), raw=True)
    return pose, colour, depth


def test_render_equals_cli_bitwise(work, model, model_path):
    camera = model.orbit(3, size=SIZE)[1]
    pose, colour, depth = cli_render(work, model_path, camera, "head")
    cam = lorgnette.Camera.from_pose(str(pose), size=SIZE)
    rgba, py_depth = model.render(cam, depth=True)
    assert rgba.shape == (SIZE[1], SIZE[0], 4) and rgba.dtype == np.float32
    assert colour.dtype == np.uint8 and colour.shape == (SIZE[1], SIZE[0], 3)
    np.testing.assert_array_equal(lorgnette.to_srgb8(rgba), colour)
    assert depth.dtype == np.float32
    np.testing.assert_array_equal(py_depth, depth[..., 0])
    assert (py_depth > 0).mean() > 0.05  # the head is in view


def test_render_with_glasses_equals_cli_bitwise(work, model, model_path, frame_path, cli_placement):
    camera = model.orbit(1, size=SIZE)[0]
    _, colour, depth = cli_render(work, model_path, camera, "tryon", "--glasses", frame_path,
                                  "--placement", cli_placement)
    glasses = lorgnette.Glasses.load(str(frame_path))
    placement = lorgnette.Placement.load(str(cli_placement))
    rgba, py_depth = model.render(camera, glasses, placement, depth=True)
    np.testing.assert_array_equal(lorgnette.to_srgb8(rgba), colour)
    np.testing.assert_array_equal(py_depth, depth[..., 0])
    bare = model.render(camera)
    assert np.abs(bare - rgba).max() > 0.1  # the frame is there


def test_render_alpha_and_size(model):
    camera = lorgnette.Camera.look_at(eye=(0.0, 0.0, 3.0), target=(0.0, 0.0, 0.0), size=(64, 48))
    rgba = model.render(camera, size=(32, 24), alpha=True)
    assert rgba.shape == (24, 32, 4)
    assert lorgnette.to_srgb8(rgba, alpha=True).shape == (24, 32, 4)
    assert 0.0 <= rgba.min() and rgba.max() <= 1.0 + 1e-6


def test_render_releases_the_gil(model):
    camera = model.orbit(1, size=(256, 192))[0]
    _, counted, seconds = count_during(lambda: model.render(camera, spp=2))
    assert seconds > 0.05, "render too short to tell"
    assert counted >= max(3, 0.1 * seconds / 0.001), (counted, seconds)  # held GIL: ~0


def yaw_of(camera, captured):
    """Yaw (degrees) of a camera's position about the range's centre, in its front/up frame."""
    d = np.asarray(camera.c2w)[:3, 3] - np.asarray(captured["center"])
    f, u = np.asarray(captured["front"]), np.asarray(captured["up"])
    return float(np.degrees(np.arctan2(d @ np.cross(u, f), d @ f)))


def test_orbit_and_captured_range(model, dataset):
    cams = model.orbit(4, size=(80, 60))
    assert len(cams) == 4 and cams[0].size == [80, 60]
    captured = model.captured_range()
    assert captured["cameras"] == 28  # the training frames (32 less every 8th, held out)
    lo, hi = captured["yaw_deg"]
    assert lo < 0 < hi  # the synthetic capture sweeps across the front
    margin = captured["margin_deg"]
    full = model.orbit(36, size=(80, 60), beyond_capture=True)
    for cams_, inside in ((model.orbit(36, size=(80, 60)), True), (full, False)):
        yaws = [yaw_of(c, captured) for c in cams_]
        assert (min(yaws) >= lo - margin - 0.01 and max(yaws) <= hi + margin + 0.01) == inside
    frame = lorgnette.Camera.from_transforms(str(dataset / "transforms.json"), 0)
    assert frame.size == [64, 64]
    assert model.capture_cameras()[0].fx == pytest.approx(frame.fx)
