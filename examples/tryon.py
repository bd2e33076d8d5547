#!/usr/bin/env python3
"""Virtual try-on from Python: fit a frame with landmarks supplied from Python, render before/after.

    tools/demo.sh --quick                                   # makes demo-output/model.lnerf
    PYTHONPATH=build/python python3 examples/tryon.py demo-output/model.lnerf -o tryon-output

Writes before.png, after.png, before_after.png (side by side, made with NumPy) and placement.json.
The landmark detector here is the project's dlib adapter called from Python; put your own in
`detect_landmarks` (MediaPipe, a licensed model): it gets an H x W x 3 uint8 sRGB image and
returns 68 (x, y) points in iBUG 300-W order, or None when it finds no face.
"""

import argparse
import os
import sys
import time

import numpy as np

import lorgnette


def detect_landmarks(image, face_px=0.0):
    """68 iBUG points of the face in `image` (H x W x 3 uint8), or None.

    `face_px` is the fit's estimate of the face's width in pixels (0 when unknown); a detector
    may ignore it. dlib's model is for non-commercial use: a shop plugs in its own detector here.
    """
    found = lorgnette.dlib_landmarks(image, face_px=face_px)
    if found is None:
        return None
    return {"points": np.asarray(found["points"]), "box": found["box"]}


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("model", help="trained head (.lnerf), e.g. demo-output/model.lnerf")
    parser.add_argument("--glasses", help="glasses file (glTF/OBJ/PLY); default: a 52-18-140 round frame")
    parser.add_argument("-o", "--out", default="tryon-output", help="output directory")
    parser.add_argument("--size", default="480x360", help="render size WIDTHxHEIGHT")
    parser.add_argument("--views", type=int, default=12, help="views the fit renders")
    args = parser.parse_args()
    width, height = (int(v) for v in args.size.lower().split("x"))
    os.makedirs(args.out, exist_ok=True)

    model = lorgnette.Model.load(args.model)
    if args.glasses:
        glasses = lorgnette.Glasses.load(args.glasses)
    else:
        glasses = lorgnette.Glasses.make(52, 18, 140, "round", path=os.path.join(args.out, "frame.glb"), force=True)
    print(f"{model}\n{glasses}: reference points {glasses.reference_points['source']}")

    t0 = time.perf_counter()
    placement = lorgnette.fit(model, glasses, landmarks=detect_landmarks, views=args.views)
    print(f"fit in {time.perf_counter() - t0:.1f} s: {placement}")
    for warning in placement.warnings:
        print(f"  warning: {warning}")
    placement.save(os.path.join(args.out, "placement.json"), force=True)

    camera = model.orbit(8, size=(width, height))[1]  # 45 degrees off the front
    t0 = time.perf_counter()
    before = model.render(camera)
    after = model.render(camera, glasses, placement)
    print(f"rendered before/after {width}x{height} in {time.perf_counter() - t0:.2f} s")

    before8, after8 = lorgnette.to_srgb8(before), lorgnette.to_srgb8(after)
    gap = np.full((height, 8, 3), 255, np.uint8)
    lorgnette.save_image(os.path.join(args.out, "before.png"), before8)
    lorgnette.save_image(os.path.join(args.out, "after.png"), after8)
    lorgnette.save_image(os.path.join(args.out, "before_after.png"), np.hstack([before8, gap, after8]))
    changed = np.any(before8 != after8, axis=2).mean()
    print(f"wrote {args.out}/before_after.png ({100 * changed:.1f} % of the pixels show the frame)")
    return 0


if __name__ == "__main__":
    sys.exit(main())
