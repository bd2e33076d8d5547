"""Lorgnette from Python: view-consistent virtual try-on of glasses.

The compiled module (lorgnette._lorgnette, pybind11) runs the same library calls as the
``lorgnette`` command line, so a render or a fit from Python equals the CLI's. Long work
(render, fit, train) releases the GIL. Failures raise ``lorgnette.Error`` (a RuntimeError) with
the CLI's message; missing files raise FileNotFoundError.

    import lorgnette
    model = lorgnette.Model.load("demo-output/model.lnerf")
    glasses = lorgnette.Glasses.load("frame.glb")
    placement = lorgnette.fit(model, glasses, landmarks=my_detector)   # or the built-in dlib
    cam = model.orbit(1, size=(640, 480))[0]
    rgba = model.render(cam, glasses, placement)                     # float32 H x W x 4, linear
    lorgnette.save_image("tryon.png", rgba[..., :3])
"""

import inspect as _inspect

from ._lorgnette import (  # noqa: F401  (the public API)
    Camera,
    Error,
    Glasses,
    LandmarkError,
    Model,
    Placement,
    RangeError,
    __version__,
    device,
    devices,
    dlib_landmarks,
    load_image,
    save_image,
    set_log_level,
    to_srgb8,
    train,
    trs,
    use_device,
)
from . import _lorgnette


def _accepts_face_px(fn):
    """True when `fn` takes a `face_px` keyword (the fit then passes its face-width hint)."""
    if fn is dlib_landmarks:
        return True
    try:
        params = _inspect.signature(fn).parameters.values()
    except (TypeError, ValueError):
        return False
    return any(p.name == "face_px" or p.kind == p.VAR_KEYWORD for p in params)


def fit(model, glasses, landmarks=None, *, views=12, resolution=384, yaw_range=20.0, pitch_range=15.0,
        upsample=0, scale_policy="auto", dataset="", mean_face="", landmark_model="", debug_dir=""):
    """Places `glasses` (a Glasses or a path) on `model` as ``lorgnette fit`` does; returns a Placement.

    `landmarks` finds the 68 iBUG face landmarks in one rendered view. It is called with an
    H x W x 3 uint8 sRGB image (the head over white) and returns None when it sees no face, a
    68 x 2 array of (x, y) pixel coordinates (pixel centres at i + 0.5, iBUG 300-W order), or a
    dict {"points": 68 x 2, "box": (left, top, right, bottom), "score": s}; without a box the
    points' bounding box frames the face. A callable that accepts a ``face_px`` keyword also gets
    the fit's estimate of the face's width in pixels (0 when unknown). None (the default) uses the
    built-in dlib detector; ``lorgnette.dlib_landmarks`` is that detector as a callable, giving the
    same placement. A callable that raises or returns something else raises LandmarkError; a face
    found in too few views raises Error with the CLI's message. The other options are the CLI's.
    """
    return _lorgnette._fit(model, glasses, landmarks, landmarks is not None and _accepts_face_px(landmarks),
                           views, resolution, yaw_range, pitch_range, upsample, scale_policy, dataset,
                           mean_face, landmark_model, debug_dir)


__all__ = [
    "Camera", "Error", "Glasses", "LandmarkError", "Model", "Placement", "device", "devices",
    "dlib_landmarks", "fit", "load_image", "save_image", "set_log_level", "to_srgb8", "train", "trs",
    "use_device",
]
