"""Env throughput bench: env steps per second, the Rust call's share, bare MuJoCo stepping, reset.

Everything is measured in this run, on the same model, interleaved over several trials (the
machine is shared and noisy), as thread CPU time; medians are reported with ratios against the
bare ``mj_step`` cost of the same control steps.

Run: ``python benches/env_bench.py`` (``make bench`` does).
"""

from __future__ import annotations

import os
import statistics
import time
from collections.abc import Callable

os.environ.setdefault("MUJOCO_GL", "egl")

import mujoco
import numpy as np

from proxemic.env import ProxemicEnv

TRIALS = 7
STEPS = 400


def cpu_us(fn: Callable[[], None], n: int) -> float:
    t0 = time.thread_time_ns()
    for _ in range(n):
        fn()
    return (time.thread_time_ns() - t0) / n / 1e3


def main() -> None:
    env = ProxemicEnv("museum", autopilot=True)
    env.reset(seed=0)
    m, d = env.sim.model, env.sim.data
    skip = env.sim.frame_skip
    world, sim = env.world, env.sim
    zero = np.zeros(3, np.float32)

    def env_step() -> None:
        _, _, te, tr, _ = env.step(zero)
        if te or tr:
            env.reset()

    def rust_step() -> None:
        world.step(sim.state, sim.contacts, env._out, env._people)

    def bare() -> None:
        mujoco.mj_step(m, d, skip)

    resets: list[float] = []
    # the full metric set of one finished episode (World.episode_metrics: the post-hoc evaluator)
    metrics_us: list[float] = []
    episode_steps: list[int] = []
    res: dict[str, list[float]] = {"env.step": [], "Rust World.step": [], "bare mj_step x frame_skip": []}
    seed = 0
    for _ in range(TRIALS):
        res["env.step"].append(cpu_us(env_step, STEPS))
        # the Rust call alone, on the state the env is in (advances the people; harmless here)
        res["Rust World.step"].append(cpu_us(rust_step, STEPS))
        res["bare mj_step x frame_skip"].append(cpu_us(bare, STEPS))
        t0 = time.thread_time_ns()
        for _ in range(20):
            seed += 1
            env.reset(seed=seed)
        resets.append((time.thread_time_ns() - t0) / 20 / 1e3)
        env.reset(seed=seed)
        done, n = False, 0
        while not done:
            _, _, te, tr, _ = env.step(zero)
            done, n = te or tr, n + 1
        episode_steps.append(n)
        metrics_us.append(cpu_us(world.episode_metrics, 5))
        env.reset(seed=seed)
    med = {k: statistics.median(v) for k, v in res.items()}
    base = med["bare mj_step x frame_skip"]
    print(
        f"museum: {env.world.num_people} people, {skip} physics steps per control step, "
        f"{TRIALS} trials x {STEPS} steps, thread CPU time, medians"
    )
    print(
        f"  {'env.step (autopilot: plain A*)':40s} {med['env.step']:8.1f} us  "
        f"{1e6 / med['env.step']:8.0f} steps/s  ratio to bare MuJoCo {med['env.step'] / base:5.2f}x"
    )
    print(
        f"  {'Rust World.step (one call)':40s} {med['Rust World.step']:8.1f} us  "
        f"{100 * med['Rust World.step'] / med['env.step']:5.1f}% of the env step"
    )
    print(f"  {'bare mj_step x frame_skip':40s} {base:8.1f} us")
    print(f"  {'env.reset':40s} {statistics.median(resets) / 1e3:8.2f} ms")
    mu, steps = statistics.median(metrics_us), statistics.median(episode_steps)
    print(
        f"  {'episode_metrics (full set, one episode)':40s} {mu / 1e3:8.2f} ms  "
        f"{mu / steps:6.1f} us per recorded step ({steps:.0f} steps), "
        f"{100 * mu / steps / med['env.step']:4.1f}% of an env step"
    )
    env.close()


if __name__ == "__main__":
    main()
