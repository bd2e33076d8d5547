#!/usr/bin/env python3
"""benchmarks/service/capacity_model.py against queueing theory's exact results.

- Erlang C with one server is M/M/1's mean wait, rho * s / (1 - rho).
- The simulated M/D/1 mean wait matches Pollaczek-Khinchine's exact rho * s / (2 (1 - rho)) within
  5 % (fixed seed, 400 simulated hours: about 23,000 arrivals at rho = 0.8).
- Slots that are never all busy make no one wait; more slots never make the wait longer.
"""
import importlib.util
import pathlib
import sys

path = pathlib.Path(__file__).resolve().parents[2] / "benchmarks" / "service" / "capacity_model.py"
spec = importlib.util.spec_from_file_location("capacity_model", path)
cm = importlib.util.module_from_spec(spec)
spec.loader.exec_module(cm)

failures = []


def check(name, ok, detail):
    print(("ok   " if ok else "FAIL ") + name + ": " + detail)
    if not ok:
        failures.append(name)


s, lam = 50.0, 0.8 / 50.0  # rho = 0.8
mm1 = 0.8 * s / (1 - 0.8)
check("erlang_c_one_server", abs(cm.mmc_wait(lam, s, 1) - mm1) < 1e-9 * mm1,
      f"{cm.mmc_wait(lam, s, 1):.6f} vs M/M/1 {mm1:.6f}")
check("erlang_c_overloaded", cm.mmc_wait(lam, s, 1) < float("inf") and
      cm.mmc_wait(2 * lam, s, 1) == float("inf"), "rho >= 1 has no steady wait")
pk = 0.8 * s / (2 * (1 - 0.8))
sim = cm.simulate(lam, s, 1, 400.0, 7)
check("md1_mean_wait", abs(sim["mean"] - pk) < 0.05 * pk, f"simulated {sim['mean']:.2f} s vs exact {pk:.2f} s")
idle = cm.simulate(1.0 / 3600.0, 10.0, 50, 50.0, 3)
check("no_wait_with_spare_slots", idle["max"] == 0.0, f"max wait {idle['max']}")
w = [cm.simulate(0.03, 60.0, c, 100.0, 5)["mean"] for c in (2, 3, 4)]
check("more_slots_wait_less", w[0] > w[1] > w[2], " > ".join(f"{x:.1f}" for x in w))
sys.exit(1 if failures else 0)
