"""Vector env throughput: ``proxemic.vector_env`` and ``gymnasium.make_vec`` of the museum, against one env.

Reports env steps per second (sub-env steps: ``num_envs`` per vector step) as wall time, the
median over interleaved trials (the machine is shared and noisy), for one plain env, for
``make_vec(..., vectorization_mode="sync"|"async")`` and for ``proxemic.vector_env`` (one core
call per vector step; with its default one thread, and with as many threads as cores) with each
``--num-envs``, and the ratio of ``vector_env`` to the sync vector env measured in the same run.
Actions are uniform random from a seeded action space; sub-envs reset themselves when an
episode ends. The async mode runs one subprocess per sub-env, so it only gains with free cores.

Run: ``python benches/vector_bench.py [--num-envs 2 4] [--steps 300]`` (``make bench`` does).
"""

from __future__ import annotations

import argparse
import os
import statistics
import time
from typing import Any

os.environ.setdefault("MUJOCO_GL", "egl")

import gymnasium as gym

import proxemic

ENV_ID = "proxemic/Museum-v3"
TRIALS = 3


def steps_per_second(env: Any, steps: int, num_envs: int) -> float:
    """Sub-env steps per second over `steps` vector (or plain) steps after a reset."""
    env.reset(seed=0)
    env.action_space.seed(0)
    t0 = time.perf_counter()
    for _ in range(steps):
        _, _, terminated, truncated, _ = env.step(env.action_space.sample())
        if num_envs == 0 and (terminated or truncated):
            env.reset()
    return steps * max(num_envs, 1) / (time.perf_counter() - t0)


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--num-envs", type=int, nargs="+", default=[2, 4])
    ap.add_argument("--steps", type=int, default=300, help="vector steps per trial (default: 300)")
    args = ap.parse_args()
    envs: dict[str, tuple[Any, int]] = {"single env": (gym.make(ENV_ID), 0)}
    for n in args.num_envs:
        for mode in ("sync", "async"):
            envs[f"make_vec {mode:5s} x{n}"] = (gym.make_vec(ENV_ID, num_envs=n, vectorization_mode=mode), n)
        envs[f"vector_env x{n}"] = (proxemic.vector_env(ENV_ID, num_envs=n), n)  # one thread
        threads = min(n, os.cpu_count() or 1)
        envs[f"vector_env {threads} threads x{n}"] = (proxemic.vector_env(ENV_ID, num_envs=n, threads=threads), n)
    results: dict[str, list[float]] = {k: [] for k in envs}
    for _ in range(TRIALS):
        for name, (env, n) in envs.items():
            results[name].append(steps_per_second(env, args.steps, n))
    for env, _ in envs.values():
        env.close()
    base = statistics.median(results["single env"])
    load = ", ".join(f"{x:.1f}" for x in os.getloadavg())
    print(f"## vector envs: {ENV_ID}, env steps/s (wall, median of {TRIALS}), {os.cpu_count()} cores, load {load}")
    for name, values in results.items():
        med = statistics.median(values)
        print(f"{name:26s} {med:9.0f} steps/s  {med / base:5.2f}x the single env")
    for n in args.num_envs:
        sync = results[f"make_vec sync  x{n}"]
        for name in [k for k in results if k.startswith("vector_env") and k.endswith(f" x{n}")]:
            ratios = [v / s for v, s in zip(results[name], sync, strict=True)]
            print(f"{name} / make_vec sync x{n}: {statistics.median(ratios):.2f}x (median of per-trial ratios)")


if __name__ == "__main__":
    main()
