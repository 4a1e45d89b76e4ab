"""ORCA cost per agent-step: proxemic's Rust ORCA against navground 0.7.0's ORCA (RVO2), same run.

The world is navground's ``Cross`` scenario (as in navground's
``bench_sim.py``): N agents in a square of side ``2 sqrt(N)`` m (4 m^2 per agent) shuttling between
the mid-points of opposite sides, radius 0.25 m + 0.1 m safety margin, holonomic, max speed 1.5 m/s,
optimal speed 1.0 m/s, neighbours within 5 m, ORCA time horizons 10 s (navground's defaults),
dt = 0.1 s, 20 warm-up steps, then ``AGENT_STEPS / N`` timed steps. Ours runs the same world in the
Rust example ``orca_agents`` (ORCA for every agent, Euler integration and target switching; the
pyo3 layer is not involved). navground's loop also does its own perception (a ``Bounded`` state
estimation) and collision bookkeeping, which is part of what an ORCA world step costs there.

Repetitions alternate between the two implementations (seed by seed) so both see the same machine
load; medians over repetitions of both wall time and thread CPU time per agent-step are printed side
by side with the ratio navground / ours (> 1 means ours is faster).

navground runs in its own virtual env, created on first use:
``python -m venv /tmp/navground-venv && /tmp/navground-venv/bin/pip install "navground[all]==0.7.0"``.

Run: ``python benches/orca_vs_navground.py [N ...] [--reps R] [--agent-steps K]`` (defaults: N = 10
200 1000, R = 5, K = 100000). ``CARGO_TARGET_DIR`` is honoured.
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

VENV = Path(os.environ.get("NAVGROUND_VENV", "/tmp/navground-venv"))
NAVGROUND = "navground[all]==0.7.0"
ROOT = Path(__file__).resolve().parent.parent

# Runs one navground repetition of its `Cross` scenario and prints one JSON line (executed by the
# venv's interpreter). Arguments: N, timed steps, seed, behaviour, side (m), radius (m), optimal
# speed (m/s).
NAVGROUND_WORKER = r'''
import json, math, statistics, sys, time
from navground import sim
n, steps, seed, behavior = int(sys.argv[1]), int(sys.argv[2]), int(sys.argv[3]), sys.argv[4]
side, radius, speed = float(sys.argv[5]), float(sys.argv[6]), float(sys.argv[7])
scenario = sim.load_scenario(f"""
type: Cross
side: {side}
agent_margin: 0.1
target_margin: 0.5
tolerance: 0.5
groups:
  - type: person
    number: {n}
    radius: {radius}
    control_period: 0.0
    kinematics:
      type: Omni
      max_speed: 1.5
      max_angular_speed: 3.0
    behavior:
      type: {behavior}
      optimal_speed: {speed}
      horizon: 5.0
      safety_margin: 0.1
    state_estimation:
      type: Bounded
      range: 5.0
""")
world = scenario.make_world(seed=seed)
world.run(20, 0.1)
c0, t0 = time.thread_time_ns(), time.perf_counter_ns()
world.run(steps, 0.1)
t1, c1 = time.perf_counter_ns(), time.thread_time_ns()
b = world.agents[0].behavior
nn = statistics.mean(len(getattr(a.behavior.environment_state, "neighbors", [])) for a in world.agents)
print(json.dumps(dict(wall=(t1 - t0) / (steps * n) / 1e3, cpu=(c1 - c0) / (steps * n) / 1e3, neighbors=nn,
                      behavior=type(b).__name__, time_horizon=getattr(b, "time_horizon", None),
                      max_neighbors=getattr(b, "max_number_of_neighbors", None))))
'''


def navground_cross(
    py: Path, n: int, steps: int, seed: int, behavior: str, side: float, radius: float, speed: float
) -> dict[str, float]:
    """One repetition of navground's `Cross` (:data:`NAVGROUND_WORKER`) with `behavior`; checks
    that navground ran that behaviour."""
    args = [str(n), str(steps), str(seed), behavior, repr(side), repr(radius), repr(speed)]
    out = subprocess.run([str(py), "-c", NAVGROUND_WORKER, *args], capture_output=True, text=True, check=True)
    row = json.loads(out.stdout.strip().splitlines()[-1])
    expected = f"{behavior}Behavior"
    if row["behavior"] != expected:
        raise RuntimeError(f"navground ran {row['behavior']}, expected {expected}")
    return row


def ensure_navground() -> Path:
    """Creates the navground venv if needed and returns its interpreter."""
    py = VENV / "bin" / "python"
    probe = [str(py), "-c", "import navground.sim, importlib.metadata as m; print(m.version('navground'))"]
    ok = py.exists() and subprocess.run(probe, capture_output=True, text=True).stdout.strip() == "0.7.0"
    if not ok:
        print(f"installing {NAVGROUND} into {VENV} ...", file=sys.stderr, flush=True)
        subprocess.run([sys.executable, "-m", "venv", str(VENV)], check=True)
        subprocess.run([str(py), "-m", "pip", "install", "-q", NAVGROUND], check=True)
    return py


def build_example(name: str) -> Path:
    """Builds the Rust example `name` of proxemic-core (release) and returns the binary's path."""
    subprocess.run(
        ["cargo", "build", "--release", "-q", "-p", "proxemic-core", "--example", name],
        cwd=ROOT,
        check=True,
    )
    target = Path(os.environ.get("CARGO_TARGET_DIR", ROOT / "target"))
    return target / "release" / "examples" / name


def run_navground(py: Path, n: int, steps: int, seed: int) -> dict[str, float]:
    """One navground repetition: ORCA, radius 0.25 m, optimal speed 1.0 m/s, side 2 sqrt(N) m."""
    return navground_cross(py, n, steps, seed, "ORCA", 2.0 * math.sqrt(n), 0.25, 1.0)


def run_ours(binary: Path, n: int, steps: int, seed: int) -> dict[str, float]:
    """One repetition of ours."""
    out = subprocess.run([str(binary), str(n), str(steps), "1", str(seed)], capture_output=True, text=True, check=True)
    row = json.loads(out.stdout.strip().splitlines()[-1])
    return dict(
        wall=row["us_per_agent_step_median"],
        cpu=row["cpu_us_per_agent_step_median"],
        neighbors=row["mean_neighbors"],
    )


def main() -> int:
    """Runs the bench; returns 1 when the target is missed."""
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("ns", nargs="*", type=int, default=[10, 200, 1000])
    p.add_argument("--reps", type=int, default=5)
    p.add_argument("--agent-steps", type=int, default=100_000)
    a = p.parse_args()
    py = ensure_navground()
    binary = build_example("orca_agents")
    rows = []
    for n in a.ns:
        steps = max(5, a.agent_steps // n)
        ng: list[dict[str, float]] = []
        us: list[dict[str, float]] = []
        for seed in range(a.reps):
            ng.append(run_navground(py, n, steps, seed))
            us.append(run_ours(binary, n, steps, seed))

        def med(rs: list[dict[str, float]], k: str) -> float:
            return statistics.median(r[k] for r in rs)

        row = dict(
            n=n,
            steps=steps,
            reps=a.reps,
            navground_wall_us=med(ng, "wall"),
            ours_wall_us=med(us, "wall"),
            navground_cpu_us=med(ng, "cpu"),
            ours_cpu_us=med(us, "cpu"),
            navground_neighbors=statistics.mean(r["neighbors"] for r in ng),
            ours_neighbors=statistics.mean(r["neighbors"] for r in us),
        )
        rows.append(row)
        print(json.dumps(row), flush=True)

    print()
    print("ORCA cost per agent-step (microseconds, medians over repetitions; ratio = navground / ours)")
    print("scene: navground's Cross scenario on both sides (ours: the same world in the Rust example orca_agents)")
    head = f"{'N':>5} | {'navground wall':>14} | {'ours wall':>9} | {'ratio':>6} | "
    head += f"{'navground CPU':>13} | {'ours CPU':>8} | {'ratio':>6} | {'neighbours ng/ours':>18}"
    print(head)
    print("-" * len(head))
    for r in rows:
        print(
            f"{r['n']:>5} | {r['navground_wall_us']:>14.2f} | {r['ours_wall_us']:>9.2f} | "
            f"{r['navground_wall_us'] / r['ours_wall_us']:>6.2f} | {r['navground_cpu_us']:>13.2f} | "
            f"{r['ours_cpu_us']:>8.2f} | {r['navground_cpu_us'] / r['ours_cpu_us']:>6.2f} | "
            f"{r['navground_neighbors']:>8.1f} / {r['ours_neighbors']:<7.1f}"
        )
    slower = [r["n"] for r in rows if r["ours_cpu_us"] > r["navground_cpu_us"]]
    print("target (no slower than navground at any N, CPU time):", "MISSED at N = " + str(slower) if slower else "met")
    return 1 if slower else 0


if __name__ == "__main__":
    sys.exit(main())
