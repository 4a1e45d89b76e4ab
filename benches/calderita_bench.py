"""The ``calderita`` planner's env step against ``social``'s, on the museum.

Both planners drive the autopilot on the museum scenario; each trial steps each planner
``STEPS`` control steps from the same seed (test split, 1000 + trial), planners interleaved (the
machine is shared and noisy), resetting when an episode ends. A trial's figure is the **mean**
env step over its steps (throughput pays the re-plans and the band's updates too), as thread
CPU time; the bench reports the median over ``TRIALS`` trials per planner and the ratio of
the medians. Target: ``calderita``'s env step at most 3.0x ``social``'s measured in the same run.
A missed target prints ``MISSED`` and the bench exits with status 1.

Run: ``python benches/calderita_bench.py`` (``make bench`` does).
"""

from __future__ import annotations

import os
import statistics
import sys
import time

os.environ.setdefault("MUJOCO_GL", "egl")

import numpy as np

from proxemic.env import ProxemicEnv

TRIALS = 5
STEPS = 300
#: ``calderita``'s env step may cost at most this many times ``social``'s.
TARGET_RATIO = 3.0
PLANNERS = ("social", "calderita")


def mean_step_us(env: ProxemicEnv, seed: int) -> float:
    """The mean env step (us, thread CPU time) over ``STEPS`` autopilot steps from ``seed``."""
    zero = np.zeros(3, np.float32)
    env.reset(seed=seed)
    total = 0
    for _ in range(STEPS):
        t0 = time.thread_time_ns()
        _, _, terminated, truncated, _ = env.step(zero)
        total += time.thread_time_ns() - t0
        if terminated or truncated:
            env.reset()
    return total / STEPS / 1e3


def main() -> int:
    """Runs the bench; returns 1 if the target was missed."""
    envs = {p: ProxemicEnv("museum", autopilot=True, planner=p) for p in PLANNERS}
    for env in envs.values():  # first plans and caches outside the timing
        env.reset(seed=0)
        for _ in range(20):
            env.step(np.zeros(3, np.float32))
    times: dict[str, list[float]] = {p: [] for p in PLANNERS}
    for trial in range(TRIALS):
        for p, env in envs.items():
            times[p].append(mean_step_us(env, 1000 + trial))
    for env in envs.values():
        env.close()
    med = {p: statistics.median(v) for p, v in times.items()}
    ratio = med["calderita"] / med["social"]
    print(f"calderita vs social, museum autopilot: median of {TRIALS} trials x {STEPS}-step means, thread CPU time")
    for p in PLANNERS:
        print(f"  {'env.step (' + p + ')':28s} {med[p]:9.1f} us  {1e6 / med[p]:7.0f} steps/s")
    ok = ratio <= TARGET_RATIO
    print(f"  targets: calderita <= {TARGET_RATIO}x social ({ratio:.2f}x) {'met' if ok else 'MISSED'}")
    return 0 if ok else 1


if __name__ == "__main__":
    sys.exit(main())
