#!/usr/bin/env python3
"""Shoppers per GPU-hour and GPUs for a day's shoppers, from per-stage seconds.

The model (docs/bench/service-capacity.md):
- One local worker slot per GPU (`serve --workers N`, docs/service.md). A slot holds its job through
  all its stages, so a shopper occupies a GPU's slot for
      S = capture + train + F * (fit + try-on pictures)
  seconds, F the catalogue's frames (each fitted and rendered once per shopper).
- Shoppers arrive at random (Poisson) and are served first come, first served by c slots with the
  fixed service time S: an M/D/c queue.
- The peak hour holds a share of the day's shoppers; its arrival rate is held for the whole
  simulated time, so the waits are those of a peak that lasts (an upper bound on a one-hour peak).
- The wait is from `start` to a slot taking the job (the job's `queued` time).

The queue is simulated (fixed seed) and the mean wait checked against the M/M/c formula halved
(the usual M/D/c approximation). Every input is a flag, so the figures measured on another
machine go in unchanged.
"""
import argparse
import heapq
import json
import math
import random


def mmc_wait(lam, s, c):
    """Mean queue wait of M/M/c with arrival rate lam and mean service s (Erlang C)."""
    a = lam * s
    if a >= c:
        return math.inf
    term, total = 1.0, 1.0
    for k in range(1, c):
        term *= a / k
        total += term
    last = term * a / c / (1 - a / c)
    return last / (total + last) * s / (c - a)


def simulate(lam, s, c, hours, seed):
    """Waits of Poisson arrivals (rate lam per second) at c slots of fixed service time s."""
    rng = random.Random(seed)
    free = [0.0] * c  # the time each slot is next free
    heapq.heapify(free)
    t, waits = 0.0, []
    while t < hours * 3600.0:
        t += rng.expovariate(lam)
        start = max(t, heapq.heappop(free))
        waits.append(start - t)
        heapq.heappush(free, start + s)
    waits.sort()
    return {"mean": sum(waits) / len(waits), "p95": waits[int(0.95 * (len(waits) - 1))],
            "max": waits[-1], "jobs": len(waits)}


def main():
    p = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("--capture-s", type=float, required=True, help="capture stage, seconds on the GPU host")
    p.add_argument("--train-s", type=float, required=True, help="train stage, seconds on the GPU")
    p.add_argument("--fit-s", type=float, required=True, help="fit of one frame, seconds")
    p.add_argument("--tryon-s", type=float, required=True, help="try-on pictures of one frame, seconds")
    p.add_argument("--frames", type=int, nargs="+", default=[1, 10, 50], help="catalogue sizes")
    p.add_argument("--per-day", type=float, default=1000.0, help="shoppers a day")
    p.add_argument("--peak-share", type=float, default=0.15, help="share of the day in the peak hour")
    p.add_argument("--wait-limit-s", type=float, default=300.0, help="the p95 queue wait allowed at peak")
    p.add_argument("--hours", type=float, default=200.0, help="simulated hours at the peak rate")
    p.add_argument("--seed", type=int, default=1)
    a = p.parse_args()
    lam = a.per_day * a.peak_share / 3600.0
    rows = []
    for f in a.frames:
        s = a.capture_s + a.train_s + f * (a.fit_s + a.tryon_s)
        c = max(1, math.ceil(lam * s))
        while True:
            sim = simulate(lam, s, c, a.hours, a.seed)
            if lam * s < c and sim["p95"] <= a.wait_limit_s:
                break
            c += 1
        rows.append({"frames": f, "seconds_per_shopper": round(s, 1),
                     "shoppers_per_gpu_hour": round(3600.0 / s, 1), "gpus": c,
                     "peak_utilisation": round(lam * s / c, 2),
                     "wait_s": {k: round(v, 1) if k != "jobs" else v for k, v in sim.items()},
                     "wait_mean_mdc_approx_s": round(mmc_wait(lam, s, c) / 2, 1)})
    print(json.dumps({"peak_arrivals_per_hour": a.per_day * a.peak_share, "rows": rows}, indent=1))


if __name__ == "__main__":
    main()
