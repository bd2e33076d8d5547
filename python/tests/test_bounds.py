"""Out-of-range numbers raise lorgnette.RangeError (a lorgnette.Error and a ValueError) with the
CLI's own message, wrong types a TypeError naming the argument (never pybind's "Unable to cast"),
and nothing hangs or allocates without bound (host/util/bounds.h holds the one table of ranges)."""

import math
import time

import pytest

import lorgnette
from conftest import cli_error


def range_error(call):
    with pytest.raises(lorgnette.RangeError) as info:
        call()
    assert isinstance(info.value, lorgnette.Error) and isinstance(info.value, ValueError)
    return str(info.value)


def test_train_numbers_have_the_cli_message(tmp_path):
    data, out = str(tmp_path), str(tmp_path / "m.lnerf")
    cases = [({"steps": 0}, ["--steps", 0]),
             ({"seconds": math.nan}, ["--seconds", "nan"]),
             ({"downscale": 1000}, ["--downscale", 1000]),
             ({"hair_mm": 5000}, ["--hair", 5000]),
             ({"batch_log2": 40}, ["--batch-log2", 40])]
    for kwargs, flags in cases:
        msg = range_error(lambda: lorgnette.train(data, out, **kwargs))
        assert msg == cli_error("train", tmp_path, "-o", out, *flags), kwargs
    with pytest.raises(TypeError, match="steps"):
        lorgnette.train(data, out, steps="many")
    with pytest.raises(TypeError, match="steps"):
        lorgnette.train(data, out, steps=True)
    assert "whole number" in range_error(lambda: lorgnette.train(data, out, steps=1.5))
    assert "--steps" in range_error(lambda: lorgnette.train(data, out, steps=10**30))
    assert not (tmp_path / "m.lnerf").exists()


def test_render_numbers_have_the_cli_message(tmp_path, model, model_path):
    camera = model.orbit(1, size=(32, 24))[0]
    pose = tmp_path / "pose.json"
    pose.write_text('{"transform_matrix": [[1,0,0,0],[0,1,0,0],[0,0,1,3],[0,0,0,1]]}')
    base = ["render", model_path, "--pose", pose, "-o", tmp_path / "out"]
    t0 = time.monotonic()
    msg = range_error(lambda: model.render(camera, step_scale=1e-9))
    assert time.monotonic() - t0 < 5.0  # refused, not marched
    assert msg == cli_error(*base, "--step-scale", "1e-9")
    msg = range_error(lambda: model.render(camera, background=(math.nan, 1, 1)))
    assert msg == cli_error(*base, "--background", "nan", 1, 1)
    assert range_error(lambda: model.render(camera, spp=0)) == cli_error(*base, "--spp", 0)
    with pytest.raises(TypeError, match="background"):
        model.render(camera, background="white")
    with pytest.raises(TypeError, match="glasses must be a lorgnette.Glasses or a path"):
        model.render(camera, glasses=42)


def test_orbit_of_a_billion_views_is_refused_at_once(tmp_path, model, model_path):
    t0 = time.monotonic()
    msg = range_error(lambda: model.orbit(10**9))
    assert time.monotonic() - t0 < 5.0
    assert msg == cli_error("render", model_path, "--orbit", 10**9, "-o", tmp_path / "out")
    assert "--fov" in range_error(lambda: model.orbit(4, fov_y_deg=500))
    assert "--size" in range_error(lambda: model.orbit(4, size=(0, 10)))
    with pytest.raises(TypeError, match="size"):
        model.orbit(4, size="big")


def test_glasses_without_a_placement_are_refused_like_the_cli(tmp_path, model, model_path, frame_path):
    camera = model.orbit(1, size=(32, 24))[0]
    glasses = lorgnette.Glasses.load(str(frame_path))
    with pytest.raises(lorgnette.Error, match="glasses were given but no placement"):
        model.render(camera, glasses)
    with pytest.raises(lorgnette.Error, match="glasses were given but no placement"):
        model.render(camera, glasses=str(frame_path))  # a path works as the CLI's --glasses
    pose = tmp_path / "pose.json"
    pose.write_text('{"transform_matrix": [[1,0,0,0],[0,1,0,0],[0,0,1,3],[0,0,0,1]]}')
    assert "glasses were given but no placement" in cli_error(
        "render", model_path, "--glasses", frame_path, "--pose", pose, "--size", "32x24", "-o", tmp_path / "o")


def test_hand_placements_are_finite(tmp_path, model, frame_path):
    assert "--translate (Python: translate)" in range_error(lambda: lorgnette.trs(translate=(math.nan, 0, 0)))
    assert "--scale (Python: scale)" in range_error(lambda: lorgnette.trs(scale=-1))
    camera = model.orbit(1, size=(32, 24))[0]
    glasses = lorgnette.Glasses.load(str(frame_path))
    bad = lorgnette.trs(scale=0.001)
    bad[0, 3] = math.nan
    with pytest.raises(lorgnette.Error, match="non-finite"):
        model.render(camera, glasses, bad)


def test_glasses_units_have_the_cli_message(frame_path):
    for bad in (-1, math.nan, 1e300):
        msg = range_error(lambda: lorgnette.Glasses.load(str(frame_path), mm_per_unit=bad))
        assert "--mm-per-unit (Python: mm_per_unit) must be within 0.001..100000" in msg


def test_frame_numbers_have_the_cli_message(tmp_path):
    out = tmp_path / "tiny.glb"
    for kwargs, flags in [({"lens": 5}, ["--lens", 5]), ({"bridge": math.nan}, ["--bridge", "nan"]),
                          ({"temple": 1e9}, ["--temple", 1e9])]:
        args = {"lens": 52, "bridge": 18, "temple": 140, **kwargs}
        msg = range_error(lambda: lorgnette.Glasses.make(args["lens"], args["bridge"], args["temple"],
                                                         path=str(out)))
        assert msg == cli_error("glasses", "make", "-o", out, *flags), kwargs
    assert not out.exists()


def test_fit_numbers_have_the_cli_message(tmp_path, model, model_path, frame_path):
    placement = tmp_path / "p.json"
    for kwargs, flags in [({"views": 1}, ["--views", 1]), ({"yaw_range": math.nan}, ["--yaw-range", "nan"]),
                          ({"resolution": 10}, ["--resolution", 10]), ({"upsample": 9}, ["--upsample", 9])]:
        msg = range_error(lambda: lorgnette.fit(model, str(frame_path), **kwargs))
        assert msg == cli_error("fit", model_path, "--glasses", frame_path, "-o", placement, *flags), kwargs
    assert not placement.exists()
