"""Parallel env throughput: env steps and agent-steps per second with 4 and 11 robots.

The museum with several robots (``museum_multi``: the museum's walls, objects and visitors,
eleven robot definitions; the first N are used). Every robot is an agent whose policy returns
its built-in planner's command (``info["planner_action"]``), so the actions go through
``World.command`` as a learning policy's would and the robots move sensibly. Two planner
settings: the scenario's ``social`` planner (Daza 2021 Algorithm 1, computed for every robot
every step to fill ``planner_action``), plain ``astar``, and policies only (``planner_actions=False``:
the agents' planners do not run; the policy sends zero commands).

Measured in this run, on the same model, interleaved over several trials (the machine is shared
and noisy), as thread CPU time; medians. Agent-steps count the agents actually live in each
step. The ratio is to the bare MuJoCo stepping a control step contains (``mj_step`` x frame_skip
on the same model), and the Rust share is one ``World.step`` call (all robots) of the step.

Run: ``python benches/parallel_bench.py`` (``make bench`` does).
"""

from __future__ import annotations

import os
import statistics
import time
from collections.abc import Callable

os.environ.setdefault("MUJOCO_GL", "egl")

import mujoco
import numpy as np

import proxemic

TRIALS = 5
STEPS = 200
TARGET = 30_000  # agent-steps/s with 11 robots (issue 6)
ZERO = np.zeros(3, np.float32)


def bench(robots: int, planners: str | None, planner_actions: bool = True) -> dict[str, float]:
    env = proxemic.parallel_env("museum_multi", robots=robots, planners=planners, planner_actions=planner_actions)
    _, infos = env.reset(seed=0)
    ws = env.ws
    m, d, skip = ws.sim.model, ws.sim.data, ws.sim.frame_skip
    seed = 0
    state = {"infos": infos}

    def run(n: int) -> tuple[float, int]:
        nonlocal seed
        agent_steps = 0
        t0 = time.thread_time_ns()
        for _ in range(n):
            if not env.agents:
                seed += 1
                _, state["infos"] = env.reset(seed=seed)
            infos = state["infos"]
            actions = {a: infos[a].get("planner_action", ZERO) for a in env.agents}
            agent_steps += len(actions)
            _, _, _, _, state["infos"] = env.step(actions)
        return (time.thread_time_ns() - t0) / 1e3, agent_steps

    def cpu_us(fn: Callable[[], None], n: int) -> float:
        t0 = time.thread_time_ns()
        for _ in range(n):
            fn()
        return (time.thread_time_ns() - t0) / n / 1e3

    def rust() -> None:
        ws.world.step(ws.sim.state, ws.sim.contacts, ws.out, ws.people)

    def bare() -> None:
        mujoco.mj_step(m, d, skip)

    run(20)  # warm up
    step_us, agent_us, rust_us, bare_us = [], [], [], []
    for _ in range(TRIALS):
        total, agents = run(STEPS)
        step_us.append(total / STEPS)
        agent_us.append(total / agents)
        rust_us.append(cpu_us(rust, STEPS))  # advances the people; harmless for timing
        bare_us.append(cpu_us(bare, STEPS))
        _, state["infos"] = env.reset(seed=seed)
    people = ws.world.num_people
    env.close()
    return {
        "people": people,
        "step": statistics.median(step_us),
        "agent": statistics.median(agent_us),
        "rust": statistics.median(rust_us),
        "bare": statistics.median(bare_us),
    }


def main() -> None:
    print(f"parallel env, museum_multi, {TRIALS} trials x {STEPS} steps, thread CPU time, medians")
    settings = (
        ("social", None, True, "planner social"),
        ("astar", "astar", True, "planner astar"),
        ("none", None, False, "policies only (planner_actions=False)"),
    )
    for _, planners, planner_actions, label in settings:
        for robots in (4, 11):
            r = bench(robots, planners, planner_actions)
            what = f"{robots:2d} robots, {int(r['people'])} people, {label}"
            print(
                f"  {what:58s} {r['step']:8.1f} us/step {1e6 / r['step']:7.0f} steps/s "
                f"{1e6 / r['agent']:7.0f} agent-steps/s  ratio to bare MuJoCo {r['step'] / r['bare']:5.2f}x  "
                f"(bare {r['bare']:.0f} us, Rust call {r['rust']:.0f} us = {100 * r['rust'] / r['step']:.0f}%)"
            )
            if robots == 11:
                print(
                    f"  {'':58s} target {TARGET} agent-steps/s with 11 robots: "
                    f"{'met' if 1e6 / r['agent'] >= TARGET else 'NOT met'}; the bare MuJoCo stepping alone "
                    f"allows {robots * 1e6 / r['bare']:.0f}"
                )


if __name__ == "__main__":
    main()
