"""Pedestrian update cost per person-step: proxemic's Rust social force against navground 0.7.0's HL
and SocialForce behaviours, measured in the same run.

Ours runs the criterion bench's world in the Rust example ``pedestrian_crowd`` (N walkers on routes
in a walled hall with pillars at the museum's density, 864 m^2 for 29 people, social force with
groups, walls and one robot; the pyo3 layer is not involved). navground runs its ``Cross`` scenario
(navground's own benchmark scenario) at the same density: N agents of radius 0.2 m shuttling across a
square of side ``sqrt(N * 864 / 29)`` m, holonomic, optimal speed 1.2 m/s, neighbours within 5 m
(``Bounded`` state estimation), with its C++ ``HL`` behaviour and its Python ``SocialForce``
behaviour. Both step at dt = 0.1 s after 20 warm-up steps. navground's world step also does its own
perception and collision bookkeeping, which is part of what a pedestrian step costs there.

Repetitions alternate between the implementations (seed by seed) so they see the same machine
load; medians over repetitions of wall time and thread CPU time per person-step are printed side by
side with the ratios navground / ours (> 1 means ours is faster). The issue's target for ours is at
most 2 microseconds per person-step.

navground runs in its own virtual env, created on first use (see ``orca_vs_navground.py``).

Run: ``python benches/pedestrians_vs_navground.py [N ...] [--reps R]`` (defaults: N = 50 200 1000,
R = 3). ``CARGO_TARGET_DIR`` is honoured for ours.
"""

from __future__ import annotations

import argparse
import json
import math
import os
import statistics
import subprocess
import sys
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent))
from orca_vs_navground import build_example, ensure_navground, navground_cross

ROOT = Path(__file__).resolve().parent.parent
#: Timed person-steps per repetition: ours and HL (C++), navground's Python social force.
PERSON_STEPS = {"ours": 100_000, "HL": 40_000, "SocialForce": 2_000}
#: The commit whose pedestrian model is the speed baseline (before the people saw the robot).
BASELINE_REV = "138f713"
#: Crowd sizes at which ours must stay within ``KEPT_RATIO`` of the baseline (CPU time).
KEPT_AT = (50, 1000)
KEPT_RATIO = 1.25


def run_navground(py: Path, n: int, behavior: str, seed: int) -> dict[str, float]:
    """One navground repetition of `behavior`: radius 0.2 m, optimal speed 1.2 m/s, the museum's
    density (side sqrt(N 864 / 29) m)."""
    steps = max(3, PERSON_STEPS[behavior] // n)
    return navground_cross(py, n, steps, seed, behavior, math.sqrt(n * 864.0 / 29.0), 0.2, 1.2)


def build_baseline(rev: str = BASELINE_REV) -> Path:
    """Builds the example ``pedestrian_crowd`` as it was at ``rev`` and returns the binary's path.

    Raises ``RuntimeError`` naming the commit when this clone's history does not hold it.
    """
    where = ROOT / "target" / "bench-baseline" / rev
    binary = where / "target" / "release" / "examples" / "pedestrian_crowd"
    src = where / "src"
    if not (src / "Cargo.toml").exists():
        got = subprocess.run(["git", "-C", str(ROOT), "archive", rev], capture_output=True)
        if got.returncode != 0:
            raise RuntimeError(
                f"the speed baseline {rev} is not in this clone's git history ({got.stderr.decode().strip()}); "
                "clone with full history to measure the people's speed against it"
            )
        src.mkdir(parents=True, exist_ok=True)
        subprocess.run(["tar", "-x", "-C", str(src)], input=got.stdout, check=True)
    env = {**os.environ, "CARGO_TARGET_DIR": str(where / "target")}
    print(f"building the speed baseline ({rev}) in {where} ...", flush=True)
    subprocess.run(
        ["cargo", "build", "--release", "-q", "-p", "proxemic-core", "--example", "pedestrian_crowd"],
        cwd=src,
        env=env,
        check=True,
    )
    return binary


def run_ours(binary: Path, n: int, seed: int) -> dict[str, float]:
    """One repetition of ours (or of the baseline's build of the same example)."""
    steps = max(5, PERSON_STEPS["ours"] // n)
    out = subprocess.run([str(binary), str(n), str(steps), "1", str(seed)], capture_output=True, text=True, check=True)
    row = json.loads(out.stdout.strip().splitlines()[-1])
    return dict(wall=row["us_per_person_step_median"], cpu=row["cpu_us_per_person_step_median"])


def main() -> int:
    """Runs the bench; returns 1 when the target is missed."""
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("ns", nargs="*", type=int, default=[50, 200, 1000])
    p.add_argument("--reps", type=int, default=3)
    a = p.parse_args()
    py = ensure_navground()
    binary = build_example("pedestrian_crowd")
    try:
        baseline = build_baseline()
    except RuntimeError as e:
        print(f"pedestrians_vs_navground: {e}", file=sys.stderr)
        return 1
    rows = []
    for n in a.ns:
        res: dict[str, list[dict[str, float]]] = {"ours": [], "baseline": [], "HL": [], "SocialForce": []}
        for seed in range(a.reps):
            res["ours"].append(run_ours(binary, n, seed))
            res["baseline"].append(run_ours(baseline, n, seed))
            res["HL"].append(run_navground(py, n, "HL", seed))
            res["SocialForce"].append(run_navground(py, n, "SocialForce", seed))
        row: dict[str, float] = {"n": n, "reps": a.reps}
        for k, rs in res.items():
            row[f"{k}_wall_us"] = statistics.median(r["wall"] for r in rs)
            row[f"{k}_cpu_us"] = statistics.median(r["cpu"] for r in rs)
        row["navground_neighbors"] = statistics.mean(r["neighbors"] for r in res["HL"])
        rows.append(row)
        print(json.dumps(row), flush=True)

    print()
    print("Pedestrian update per person-step (microseconds, medians; ratio = navground / ours)")
    print(
        "scenes: ours = the example pedestrian_crowd (walkers on routes in a walled hall with pillars); "
        "navground = its Cross scenario, same density"
    )
    head = f"{'N':>5} | {'clock':>5} | {'ours':>7} | {'navground HL (C++)':>18} | {'ratio':>6} | "
    head += f"{'navground SocialForce (Python behaviour)':>40} | {'ratio':>7}"
    print(head)
    print("-" * len(head))
    for r in rows:
        for clock in ("cpu", "wall"):
            ours = r[f"ours_{clock}_us"]
            hl, sf = r[f"HL_{clock}_us"], r[f"SocialForce_{clock}_us"]
            print(
                f"{int(r['n']):>5} | {clock:>5} | {ours:>7.2f} | {hl:>18.2f} | {hl / ours:>6.1f} | "
                f"{sf:>40.1f} | {sf / ours:>7.0f}"
            )
    over = [int(r["n"]) for r in rows if r["ours_cpu_us"] > 2.0]
    print("target (ours at most 2 us per person-step, CPU time):", f"MISSED at N = {over}" if over else "met")

    print()
    print(f"The people's speed kept: ours against the same example at {BASELINE_REV} (same run, same seeds)")
    head = f"{'N':>5} | {'clock':>5} | {'ours':>7} | {BASELINE_REV:>9} | {'ours / ' + BASELINE_REV:>15}"
    print(head)
    print("-" * len(head))
    for r in rows:
        for clock in ("cpu", "wall"):
            ours, base = r[f"ours_{clock}_us"], r[f"baseline_{clock}_us"]
            print(f"{int(r['n']):>5} | {clock:>5} | {ours:>7.3f} | {base:>9.3f} | {ours / base:>15.2f}")
    measured = {int(r["n"]): r["ours_cpu_us"] / r["baseline_cpu_us"] for r in rows}
    missing = [n for n in KEPT_AT if n not in measured]
    slow = [n for n in KEPT_AT if n in measured and measured[n] > KEPT_RATIO]
    verdict = "met" if not (slow or missing) else f"MISSED at N = {slow}" if slow else f"NOT MEASURED at N = {missing}"
    print(f"target (ours at most {KEPT_RATIO} x {BASELINE_REV} at N = {list(KEPT_AT)}, CPU time):", verdict)
    return 1 if over or slow or missing else 0


if __name__ == "__main__":
    sys.exit(main())
