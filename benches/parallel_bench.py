"""Parallel env throughput: env steps and agent-steps per second with 4 and 11 robots.

The museum with several robots (``museum_multi``: the museum's walls, objects and 52 people, a
tour group of four led by robot 1, 56 people in all; eleven robot definitions, the first N are
used). Three settings:

- ``social``: every agent's policy returns its built-in planner's command
  (``info["planner_action"]``, the scenario's social planner, Daza 2021 Algorithm 1, computed for
  every robot every step), so the actions go through the step as a learning policy's would and
  the robots move sensibly;
- ``astar``: the same with plain A*;
- policies only (``planner_actions=False``: the agents' planners do not run): every agent turns
  in place (``[0, 0, 0.5]``), so every robot's lidar and observations change every step and all
  eleven stay live (robots that drive blindly end their episodes in a few seconds, leaving steps
  with few agents: the number would measure collisions, not the env);
- policies only, driving: what an RL rollout pays. Every agent heads for its current target (the
  goal offset of its observation) at full speed, turning towards it, with Gaussian noise on the
  action (seeded); each robot's goal is a long tour (``waypoints``: a seeded shuffle of the
  scenario's robot starts and goals, no dwelling), so a robot that arrives gets a new goal and
  drives on. A robot whose episode ends (a collision: the policy does not avoid anything) is
  re-spawned with all the others by an (untimed) reset as soon as any agent is done, so every
  timed step has all robots live and driving; the row says how many resets the run needed.
  This row is reported beside the turning one (what a rollout pays, contacts included); the
  target is checked on the turning row, as before.

The target (32,000 agent-steps/s with 11 robots: the first wave asked for 30,000 among 40 people
and measured 32,000, which is kept; this scene has 56 people) is checked
on the policies-only setting: what a learning policy pays for the env; with built-in planners
their own cost (in ``core``) comes on top. Only ``env.step`` is timed (the
policies and ``env.reset`` are not), as thread CPU time over several interleaved trials (the
machine is shared and noisy); medians. Agent-steps count the
agents live in each step. Beside each: the bare MuJoCo stepping a control step contains
(``mj_step`` x frame_skip from the same states, on a copy of the data) for the physics model with
the people, contacts on in every period (not matched: the env steps its quiet periods with contacts
off, and those without a person in reach on reduced models, see ``proxemic.sim``; ``env_bench.py``
prints matched denominators, and no target here uses this one), and for the full visual model
(the render model, which is what the physics stepped
before the physics model lost its visual parts); and the step split into the physics (the
callback of ``World.step``: MuJoCo and its Python wrapper), the core (the rest of the
``World.step`` call) and Python (the rest of ``env.step``). With built-in social planners the
core is also split by the robots' social searches (their first plans, triggered re-plans and
refreshes, ``World.social_searches``, counted outside the timers): the mean core of the steps in
which no robot searched (what the core costs without re-planning) and what the steps with
searches add to the mean.

With 11 ``social`` robots the core is held against the physics a plain MuJoCo gym would pay: the
physics model (every body of the scene, people included) stepped bare from the env's states with
contacts on in the share of periods the env stepped with contacts possible and off in the others
(``env_bench.ContactCounter`` counts them). Targets: the core of the steps without a search at most
2x that, the mean core (searches included) at most 3x. The reduced models the env actually steps on
are our optimisation and stay in the numerator's favour; the ratio against them is printed beside.

Run: ``python benches/parallel_bench.py`` (``make bench`` does).
"""

from __future__ import annotations

import copy
import math
import os
import random
import re
import statistics
import sys
import tempfile
import time
from pathlib import Path
from typing import Any

os.environ.setdefault("MUJOCO_GL", "egl")

import mujoco
import numpy as np

import proxemic
from proxemic import _core, scenarios
from proxemic.errors import ScenarioError
from proxemic.sim import timer_off

sys.path.insert(0, str(Path(__file__).resolve().parent))
from env_bench import ContactCounter, physics_model_us

TRIALS = 5
STEPS = 200
TARGET = 32_000  # agent-steps/s with 11 robots driven by policies (the figure the first wave measured)


TURN = np.array([0.0, 0.0, 0.5], np.float32)
#: Standard deviation of the driving policy's action noise (normalised action units).
NOISE = 0.3
#: Tour length of each driving robot (targets before its goal).
TOUR = 12


def driving_scenario(path: Path, seed: int = 7) -> Path:
    """museum_multi with every robot on a long seeded tour of the scenario's robot starts and goals.

    A stop whose leg the scenario check rejects (its path passes the robot's goal) is dropped and
    the check repeated, so the tours are valid by the scenario's own rules.
    """
    src = scenarios.resolve("museum_multi")
    text = src.read_text()
    # the base scene by absolute path, so the copy can live elsewhere
    text = re.sub(
        r'^extends\s*=\s*"([^"]+)"',
        lambda m: f'extends = "{(src.parent / m.group(1)).as_posix()}"',
        text,
        flags=re.M,
    )
    points = [
        (float(x), float(y))
        for x, y in re.findall(r"^(?:start|goal)\s*=\s*\[\s*([-\d.]+)\s*,\s*([-\d.]+)", text, flags=re.M)
    ]
    rng = random.Random(seed)
    robot_block = r"^\[\[robot\]\]\n(?:(?!\[).*\n?)*"
    tours: list[list[tuple[float, float]]] = []
    for block in re.findall(robot_block, text, flags=re.M):
        goal = re.search(r"^goal\s*=\s*\[\s*([-\d.]+)\s*,\s*([-\d.]+)", block, flags=re.M)
        last = (float(goal.group(1)), float(goal.group(2))) if goal else None
        stops: list[tuple[float, float]] = []
        while len(stops) < TOUR:
            p = rng.choice(points)
            if p != (stops[-1] if stops else None) and p != last:
                stops.append(p)
        tours.append(stops)

    def render() -> str:
        it = iter(tours)

        def tour(m: re.Match[str]) -> str:
            block = re.sub(r"^(waypoints|dwell)\s*=.*\n", "", m.group(0), flags=re.M)
            way = ", ".join(f"[{x}, {y}]" for x, y in next(it))
            return block.replace("[[robot]]\n", f"[[robot]]\nwaypoints = [{way}]\n", 1)

        return re.sub(robot_block, tour, text, flags=re.M)

    out = path / "museum_multi_driving.toml"
    for _ in range(20 * TOUR):
        out.write_text(render())
        try:
            _core.World(_core.Scenario.from_file(str(out)))  # the tour checks run on the world
            return out
        except ScenarioError as e:
            bad = re.search(r"robot\[(\d+)\]\.waypoints\[(\d+)\]", str(e))
            if bad is None:
                raise
            del tours[int(bad.group(1))][int(bad.group(2))]
    raise RuntimeError("no valid driving tours")


def bench(
    robots: int, planners: str | None, planner_actions: bool, scenario: str | Path = "museum_multi"
) -> dict[str, float]:
    driving = scenario != "museum_multi"
    env = proxemic.parallel_env(scenario, robots=robots, planners=planners, planner_actions=planner_actions)
    ws = env.ws
    sim = ws.sim
    m, skip = sim.model, sim.frame_skip
    rm = sim.render_model
    physics_ns, call_ns = [0], [0]
    inner, call = ws._physics, ws.step

    def timed_physics() -> None:
        t0 = time.thread_time_ns()
        inner()
        physics_ns[0] += time.thread_time_ns() - t0

    def timed_call(actions: np.ndarray | None = None) -> None:
        t0 = time.thread_time_ns()
        call(actions)
        call_ns[0] += time.thread_time_ns() - t0

    ws._physics = timed_physics  # type: ignore[method-assign]
    ws.step = timed_call  # type: ignore[method-assign]
    seed = 0
    obs, infos = env.reset(seed=seed)
    state: dict[str, Any] = {"obs": obs, "infos": infos}

    noise = np.random.default_rng(11)
    resets = [0]

    def drive(obs: dict[str, np.ndarray]) -> np.ndarray:
        """Full speed towards the current target, turning to face it, plus noise."""
        gx, gy = float(obs["robot"][0]), float(obs["robot"][1])
        norm = max(np.hypot(gx, gy), 1e-9)
        act = np.array([gx / norm, gy / norm, np.clip(np.arctan2(gy, gx), -1.0, 1.0)])
        return np.clip(act + noise.normal(0.0, NOISE, 3), -1.0, 1.0).astype(np.float32)

    def actions() -> dict[str, np.ndarray]:
        if planner_actions:
            return {a: state["infos"][a]["planner_action"] for a in env.agents}
        if driving:
            return {a: drive(state["obs"][a]) for a in env.agents}
        return dict.fromkeys(env.agents, TURN)

    world = ws.world
    rows = range(world.num_robots)
    #: (core ns, social searches) of each timed step (counted outside the timers).
    split: list[tuple[int, int]] = []

    def searches() -> int:
        return sum(map(world.social_searches, rows))

    def run(n: int) -> tuple[float, int, float, float]:
        """(step us, agent-steps, physics us, World.step us) summed over `n` steps."""
        nonlocal seed
        total, agents = 0, 0
        physics_ns[0] = call_ns[0] = 0
        split.clear()
        for _ in range(n):
            if not env.agents or (driving and len(env.agents) < robots):
                seed += 1
                resets[0] += driving
                state["obs"], state["infos"] = env.reset(seed=seed)
            acts = actions()
            agents += len(acts)
            c0, p0, s0 = call_ns[0], physics_ns[0], searches()
            t0 = time.thread_time_ns()
            out = env.step(acts)
            total += time.thread_time_ns() - t0
            split.append((call_ns[0] - c0 - (physics_ns[0] - p0), searches() - s0))
            state["obs"], state["infos"] = out[0], out[4]
        return total / 1e3, agents, physics_ns[0] / 1e3, call_ns[0] / 1e3

    def bare(model: mujoco.MjModel, n: int, contacts: bool = True) -> float:
        """us per control step of bare stepping of `model` from the env's current state (with
        collision detection off unless `contacts`)."""
        d = copy.copy(sim.data) if model is m else mujoco.MjData(model)
        if model is not m:
            for name in ("qpos", "qvel", "ctrl", "mocap_pos", "mocap_quat", "qacc_warmstart"):
                getattr(d, name)[:] = getattr(sim.data, name)
            mujoco.mj_forward(model, d)
        flags = int(model.opt.disableflags)
        model.opt.disableflags = flags if contacts else flags | int(mujoco.mjtDisableBit.mjDSBL_CONTACT)
        try:
            with timer_off():  # as the env steps
                t0 = time.thread_time_ns()
                for _ in range(n):
                    mujoco.mj_step(model, d, skip)
                return (time.thread_time_ns() - t0) / n / 1e3
        finally:
            model.opt.disableflags = flags

    run(20)  # warm up
    resets[0] = 0
    keys = ("step", "agent", "physics", "core", "bare", "bare_full", "core_quiet", "quiet", "searches", "extra")
    res: dict[str, list[float]] = {k: [] for k in (*keys, "contact share", "physics model")}
    counter = ContactCounter(sim)
    for _ in range(TRIALS):
        with counter:
            total, agents, physics, world_call = run(STEPS)
        # the counting runs inside the physics callback: taken off the step, the call and the physics
        overhead = counter.overhead_ns / 1e3
        total, physics, world_call = total - overhead, physics - overhead, world_call - overhead
        quiet = [core for core, k in split if k == 0]
        res["core_quiet"].append(statistics.fmean(quiet) / 1e3 if quiet else math.nan)
        res["quiet"].append(len(quiet) / STEPS)
        res["searches"].append(sum(k for _, k in split) / STEPS)
        res["extra"].append((world_call - physics) / STEPS - res["core_quiet"][-1])
        res["step"].append(total / STEPS)
        res["agent"].append(total / max(agents, 1))
        res["physics"].append(physics / STEPS)
        res["core"].append((world_call - physics) / STEPS)
        res["bare"].append(bare(m, 50))
        res["bare_full"].append(bare(rm, 50))
        res["contact share"].append(counter.share())
        res["physics model"].append(physics_model_us(counter.share(), res["bare"][-1], bare(m, 50, contacts=False)))
    out = {k: statistics.median(v) for k, v in res.items()}
    out["people"] = ws.world.num_people
    out["resets"] = resets[0]
    env.close()
    return out


def main() -> int:
    """Runs the bench; returns 1 when a target is missed."""
    checks: dict[str, bool] = {}
    print(
        f"parallel env, museum_multi, {TRIALS} trials x {STEPS} steps, env.step thread CPU time, medians "
        "(bare: mj_step x frame_skip from the env's states, the physics model with the people and contacts on, "
        "not matched to the env's quiet periods; full: the visual model)"
    )
    tmp = tempfile.TemporaryDirectory()
    driving = driving_scenario(Path(tmp.name))
    settings: tuple[tuple[str | None, bool, str, str | Path], ...] = (
        ("astar", True, "planner astar", "museum_multi"),
        (None, True, "planner social", "museum_multi"),
        (None, False, "policies only (turning in place)", "museum_multi"),
        (None, False, "policies only (driving, noise)", driving),
    )
    for planners, planner_actions, label, scenario in settings:
        for robots in (4, 11):
            r = bench(robots, planners, planner_actions, scenario)
            what = f"{robots:2d} robots, {int(r['people'])} people, {label}"
            print(
                f"  {what:46s} {r['step']:7.1f} us/step {1e6 / r['step']:6.0f} steps/s "
                f"{1e6 / r['agent']:6.0f} agent-steps/s  {r['step'] / r['bare']:5.2f}x bare MuJoCo "
                f"(bare {r['bare']:.0f} us, full model {r['bare_full']:.0f} us; physics {r['physics']:.0f} us, "
                f"core {r['core']:.0f} us, Python {r['step'] - r['physics'] - r['core']:.0f} us)"
            )
            if scenario != "museum_multi":
                print(
                    f"  {'':46s} every timed step with all {robots} robots live and driving; "
                    f"{int(r['resets'])} resets (a robot's episode ended) in {TRIALS * STEPS} steps"
                )
            if robots == 11 and not planner_actions and scenario == "museum_multi":
                rate = 1e6 / r["agent"]
                checks[f"{TARGET} agent-steps/s with 11 robots, policies only"] = rate >= TARGET
                print(
                    f"  {'':46s} target {TARGET} agent-steps/s with 11 robots: {'met' if rate >= TARGET else 'MISSED'}"
                    f"; the bare MuJoCo stepping alone allows {robots * 1e6 / r['bare']:.0f}"
                )
            if planners is None and planner_actions:
                # The core without its searches: the steps in which no robot ran a social search.
                print(
                    f"  {'':46s} {r['searches']:.2f} social searches per step; in the {100 * r['quiet']:.0f}% of "
                    f"steps without one the core takes {r['core_quiet']:.0f} us "
                    f"({r['core_quiet'] / r['physics']:.2f}x physics); the steps with searches add "
                    f"{r['extra']:.0f} us to the mean core"
                )
            if robots == 11 and planners is None and planner_actions:
                # The denominator: the physics model (every body of the scene) stepped bare as a
                # plain MuJoCo gym would, with the env's contact setting in those periods; the
                # reduced models the env steps on are our optimisation, their ratio is information.
                phys = r["physics model"]
                quiet_ok, mean_ok = r["core_quiet"] <= 2.0 * phys, r["core"] <= 3.0 * phys
                checks["11 social robots: core without searches <= 2x the physics model"] = quiet_ok
                checks["11 social robots: mean core <= 3x the physics model"] = mean_ok
                print(
                    f"  {'':46s} physics model {phys:.0f} us (bare, contacts on in the "
                    f"{100 * r['contact share']:.0f}% of periods the env stepped with contacts possible); "
                    f"core without searches {r['core_quiet']:.0f} us = {r['core_quiet'] / phys:.2f}x "
                    f"(target <= 2x: {'met' if quiet_ok else 'MISSED'}), mean core {r['core']:.0f} us = "
                    f"{r['core'] / phys:.2f}x (target <= 3x: {'met' if mean_ok else 'MISSED'}); against the "
                    f"reduced models the env stepped ({r['physics']:.0f} us): {r['core'] / r['physics']:.2f}x"
                )
    tmp.cleanup()
    missed = [k for k, ok in checks.items() if not ok]
    print("targets: " + ("all met" if not missed else "MISSED: " + "; ".join(missed)))
    return 1 if missed else 0


if __name__ == "__main__":
    sys.exit(main())
