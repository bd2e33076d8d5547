#!/usr/bin/env python3
"""Checks a `lorgnette demo --quick` output folder: the fit succeeded, the held-out PSNR is above a
floor, the files a shopper's page links exist, and the report's stage timings are consistent.
Usage: quick_report_check.py OUTPUT_FOLDER. Exits non-zero, naming every failed check."""
import json
import os
import sys

out = sys.argv[1]
try:
    report = json.load(open(os.path.join(out, "report.json")))
except (OSError, ValueError) as e:
    sys.exit(f"quick demo report: FAILED: no readable report.json in {out}: {e}")
failures = []


def check(ok, what):
    if not ok:
        failures.append(what)


fit = report.get("fit", {})
check(report.get("ok") is True, f"report not ok: {report.get('message')!r}")
check(fit.get("ok") is True, "the fit is not ok")
# Floor: the quick demo measures 31-33 dB on held-out views of the procedural head (128 px, 600
# steps of 2^15 samples); 26 dB leaves room for seeds and devices.
check(report.get("psnr", 0) > 26.0, f"held-out PSNR {report.get('psnr')} dB <= 26")
# The anatomical range of adult PDs, with the head's true 64 mm inside it.
check(50.0 < fit.get("pd_mm", 0) < 76.0, f"PD {fit.get('pd_mm')} mm outside 50-76")
for f in ("report.html", "placement.json", "head.lnerf", "orbit/orbit.mp4", "orbit/contact_sheet.png",
          "dataset/transforms.json", "frame.glb"):
    check(os.path.isfile(os.path.join(out, f)), f"missing {f}")
# Five stages and their total; each stage's CPU time is the process's own: at most its wall time on
# every logical CPU (10 ms for the clocks' reads), and some for the training.
seconds, cpu = report.get("seconds", {}), report.get("cpu_seconds", {})
stages = sorted(k for k in seconds if k != "total")
check(stages == ["evaluate", "fit", "render", "synthesize", "train"], f"stages {stages}")
cpus = os.cpu_count() or 1
for s in stages:
    check(s in cpu and cpu[s] <= seconds[s] * cpus + 0.01, f"stage {s}: CPU {cpu.get(s)} s > wall x {cpus}")
check(cpu.get("train", 0) > 0, "no CPU time for the training")
check(" CPUs, " in report.get("machine", ""), f"machine {report.get('machine')!r}")
# The scale's source and the fit advice reach the report and its page.
check(isinstance(fit.get("scale_source"), str), "no scale source")
check(len(fit.get("advice", {}).get("rules", [])) == 4, "fit advice does not have 4 rules")
page = open(os.path.join(out, "report.html"), encoding="utf-8").read()
check("Size and fit" in page, "the page has no size-and-fit section")

for f in failures:
    print(f"quick demo report: FAILED: {f}")
sys.exit(1 if failures else 0)
