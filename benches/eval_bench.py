"""Eval throughput bench: episodes per second per process, for each built-in planner.

Runs what ``proxemic eval`` runs in each worker (``proxemic.evaluation.run_task``: a cached
autopilot env, one seeded episode, its record) on the museum, in this one process. Each trial runs
the same seeds for every planner, planners interleaved (the machine is shared and noisy); time is
this thread's CPU time. Reports, per planner, the median over trials of episodes per CPU second,
control steps per second, and the ratio to plain A* measured in the same run.

Run: ``python benches/eval_bench.py [scenario]`` (``make bench`` does, on the museum).
"""

from __future__ import annotations

import os
import statistics
import sys
import time

os.environ.setdefault("MUJOCO_GL", "egl")

from proxemic import _core
from proxemic.evaluation import cached_env, run_task

TRIALS = 3
EPISODES = 4


def main() -> None:
    scenario = sys.argv[1] if len(sys.argv) > 1 else "museum"
    planners = list(_core.PLANNERS)
    for p in planners:  # build and warm every env once (model compile, first plans) outside the timing
        cached_env(scenario, p)
        run_task((scenario, p, 10_000))
    eps: dict[str, list[float]] = {p: [] for p in planners}
    steps: dict[str, list[float]] = {p: [] for p in planners}
    for trial in range(TRIALS):
        for p in planners:
            t0 = time.thread_time_ns()
            n_steps = 0
            for k in range(EPISODES):
                n_steps += int(run_task((scenario, p, trial * EPISODES + k)).record["steps"])
            cpu = (time.thread_time_ns() - t0) / 1e9
            eps[p].append(EPISODES / cpu)
            steps[p].append(n_steps / cpu)
    base = statistics.median(eps["astar"])
    print(
        f"eval throughput, {scenario}: median of {TRIALS} trials x {EPISODES} seeded episodes, one process (CPU time)"
    )
    print(f"{'planner':16s} {'episodes/s':>11s} {'steps/s':>9s} {'vs astar':>9s}")
    for p in planners:
        e = statistics.median(eps[p])
        print(f"{p:16s} {e:11.2f} {statistics.median(steps[p]):9.0f} {e / base:8.2f}x")


if __name__ == "__main__":
    main()
