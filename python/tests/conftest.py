"""Shared fixtures of the Python tests: the built CLI and one small trained head for the session.

The head is the procedural one (`lorgnette synth --procedural`, 32 views of 64 px) trained by the
CLI at the viewer tests' fixture's budget (400 steps of 2^14 samples, a 2^14 hash table): enough for
dlib to find the face in the fit's views, and about 15 s on 2 CPU cores with the synthesis. ctest sets PYTHONPATH to the build's python/ folder and
LORGNETTE_CLI to the built `lorgnette`.
"""

import json
import os
import pathlib
import subprocess
import threading
import time

import pytest

import lorgnette

REPO = pathlib.Path(__file__).resolve().parents[2]


def cli_path():
    path = os.environ.get("LORGNETTE_CLI", str(REPO / "build" / "tools" / "lorgnette"))
    if not os.path.exists(path):
        pytest.skip(f"the lorgnette CLI is not built ({path}); build the `lorgnette` target")
    return path


def run_cli(*args, check=True):
    """Runs `lorgnette -q ARGS`; returns the CompletedProcess (stderr holds the error message)."""
    proc = subprocess.run([cli_path(), "-q", *map(str, args)], capture_output=True, text=True)
    if check and proc.returncode != 0:
        raise AssertionError(f"lorgnette {' '.join(map(str, args))} failed:\n{proc.stderr}")
    return proc


def cli_error(*args):
    """The message the CLI prints after 'error: ' when ARGS fail."""
    proc = run_cli(*args, check=False)
    assert proc.returncode != 0, f"lorgnette {args} should have failed"
    lines = [l for l in proc.stderr.splitlines() if l.startswith("error: ")]
    assert lines, proc.stderr
    return lines[-1][len("error: "):]


def count_during(fn):
    """Runs fn() while a Python thread counts; returns (fn's result, counts during fn, seconds).

    A call that holds the GIL for its whole duration leaves the counter (nearly) still."""
    stop = threading.Event()
    ticks = []

    def spin():
        while not stop.is_set():
            ticks.append(time.perf_counter())
            time.sleep(0.001)

    thread = threading.Thread(target=spin)
    thread.start()
    time.sleep(0.02)
    t0 = time.perf_counter()
    result = fn()
    t1 = time.perf_counter()
    stop.set()
    thread.join()
    return result, sum(t0 < t < t1 for t in ticks), t1 - t0


@pytest.fixture(scope="session")
def work(tmp_path_factory):
    return tmp_path_factory.mktemp("lorgnette")


@pytest.fixture(scope="session")
def dataset(work):
    out = work / "head"
    run_cli("synth", "--procedural", "-o", out, "--views", 32, "--size", "64x64", "--seed", 1)
    return out


@pytest.fixture(scope="session")
def model_path(work, dataset):
    out = work / "head.lnerf"
    run_cli("train", dataset, "-o", out, "--steps", 400, "--batch-log2", 14, "--log2-table", 14, "--seed", 1)
    return out


@pytest.fixture(scope="session")
def model(model_path):
    return lorgnette.Model.load(str(model_path))


@pytest.fixture(scope="session")
def frame_path(work):
    out = work / "frame.glb"
    run_cli("glasses", "make", "--lens", 52, "--bridge", 18, "--temple", 140, "--shape", "rect", "-o", out)
    return out


@pytest.fixture(scope="session")
def cli_placement(work, model_path, frame_path):
    """`lorgnette fit` on the session's head (6 views, to keep the suite short)."""
    out = work / "placement_cli.json"
    run_cli("fit", model_path, "--glasses", frame_path, "-o", out, "--views", 6)
    return out


def write_pose(path, camera):
    """A pose JSON for `render --pose` holding exactly `camera` (transforms.json conventions)."""
    pose = {"transform_matrix": camera.c2w.tolist(), "fl_x": camera.fx, "fl_y": camera.fy,
            "cx": camera.cx, "cy": camera.cy, "w": camera.width, "h": camera.height}
    path.write_text(json.dumps(pose))
    return path
