#!/usr/bin/env python3
"""How far a trained model's surface lies from the true one on synthetic room captures (issue 13).

For each case (a dataset made by `lorgnette synth --room` and one .lnerf per arm), every held-out
view (every 8th frame: the dataset loader's held-out split, which the Python module does not expose,
as `lorgnette eval` uses it) is rendered with depth (the expected termination depth along the unit
ray) and compared with the dataset's true ray distance, over the pixels the subject covers fully
and the render shows opaque (opacity >= 0.99); with true landmarks, only inside the face (the hull
of the 68 points), and separately around the eyes (the eye hulls grown by 4 px), where a frame's
nose pads rest. Signed: positive = the model's surface lies behind the true one.
The fit meets the surface through its density, so a model whose surface sits a few mm behind the
truth lets the frame sink in by that much before the contact search stops it.

Usage (the Python module of a build on PYTHONPATH, or --build):
    benchmarks/nerf/surface_depth_error.py --build BUILD --data WORK --arm NAME=DIR [--arm ...]
        [--mm-per-unit 320] [--csv OUT.csv] CASE [CASE ...]
WORK/CASE is the dataset; DIR/CASE.lnerf the arm's model (room_matrix.sh's layout). Millimetres
come from the dataset's ground_truth.json (mm_per_unit); a mesh subject has none, so
--mm-per-unit gives it (the fit's estimate, e.g. placement.json's mm_per_unit).
"""
import argparse
import csv
import json
import os
import sys

import cv2
import numpy as np


def face_masks(gt, frame, tj, shape):
    """(face, eyes) uint8 masks from the true landmarks; without them, the whole image and none."""
    if not gt.get("ibug68"):
        return np.ones(shape, np.uint8), np.zeros(shape, np.uint8)
    w2c = np.linalg.inv(np.array(frame["transform_matrix"]))
    p = np.array(gt["ibug68"])
    pc = (w2c[:3, :3] @ p.T).T + w2c[:3, 3]
    u = tj["fl_x"] * pc[:, 0] / -pc[:, 2] + tj["cx"]
    v = tj["fl_y"] * pc[:, 1] / pc[:, 2] + tj["cy"]
    uv = np.stack([u, v], 1).astype(np.int32)
    face = np.zeros(shape, np.uint8)
    cv2.fillPoly(face, [cv2.convexHull(uv)], 1)
    eyes = np.zeros(shape, np.uint8)
    for lo, hi in ((36, 42), (42, 48)):
        cv2.fillPoly(eyes, [cv2.convexHull(uv[lo:hi])], 1)
    return face, cv2.dilate(eyes, np.ones((9, 9), np.uint8))


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("cases", nargs="+")
    ap.add_argument("--data", required=True, help="folder holding one dataset per case")
    ap.add_argument("--arm", action="append", required=True, help="NAME=DIR holding CASE.lnerf")
    ap.add_argument("--build", help="build folder (its python/ holds the module)")
    ap.add_argument("--mm-per-unit", type=float, help="for datasets whose ground truth states none")
    ap.add_argument("--csv", help="write the per-case medians here")
    a = ap.parse_args()
    for arm in a.arm:
        if "=" not in arm:
            ap.error(f"--arm '{arm}': give NAME=DIR (DIR holds one CASE.lnerf per case)")
    if a.build:
        sys.path.insert(0, os.path.join(a.build, "python"))
    import lorgnette

    rows = []
    for case in a.cases:
        ds = os.path.join(a.data, case)
        tj = json.load(open(os.path.join(ds, "transforms.json")))
        gt = json.load(open(os.path.join(ds, "ground_truth.json")))
        mm = gt.get("mm_per_unit") or a.mm_per_unit
        if not mm:
            sys.exit(f"{case}: ground_truth.json states no mm_per_unit; pass --mm-per-unit")
        held = [i for i in range(len(tj["frames"])) if i % 8 == 0]
        for arm in a.arm:
            name, folder = arm.split("=", 1)
            model = lorgnette.Model.load(os.path.join(folder, case + ".lnerf"))
            per_view = []
            for i in held:
                frame = tj["frames"][i]
                truth = cv2.imread(os.path.join(ds, frame["depth_path"]), cv2.IMREAD_UNCHANGED)
                truth = truth[..., 0] if truth.ndim == 3 else truth
                matte = cv2.imread(os.path.join(ds, frame["eval_matte_path"]), cv2.IMREAD_UNCHANGED)
                matte = matte[..., 0] if matte.ndim == 3 else matte
                matte = matte / float(np.iinfo(matte.dtype).max)
                cam = lorgnette.Camera.from_transforms(os.path.join(ds, "transforms.json"), i)
                rgba, depth = model.render(cam, depth=True)
                face, eyes = face_masks(gt, frame, tj, truth.shape)
                ok = (face > 0) & np.isfinite(truth) & (matte >= 0.999) & (rgba[..., 3] >= 0.99)
                err = (depth - truth) * mm
                near_eyes = ok & (eyes > 0)
                per_view.append((np.median(err[ok]), np.median(np.abs(err[ok])),
                                 np.median(err[near_eyes]) if near_eyes.any() else np.nan))
            med = np.median(np.array(per_view), 0)
            region = "face (68 true landmarks)" if gt.get("ibug68") else "subject"
            rows.append([case, name, region, f"{med[0]:.2f}", f"{med[1]:.2f}",
                         "" if np.isnan(med[2]) else f"{med[2]:.2f}", len(held)])
            print(f"{case} {name}: {region}: signed {med[0]:+.2f} mm, |error| {med[1]:.2f} mm, "
                  f"eyes {med[2]:+.2f} mm ({len(held)} views)", flush=True)
    if a.csv:
        with open(a.csv, "w", newline="") as f:
            w = csv.writer(f)
            w.writerow(["case", "arm", "region", "signed_mm", "abs_mm", "eyes_signed_mm", "views"])
            w.writerows(rows)


if __name__ == "__main__":
    main()
