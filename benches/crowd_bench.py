"""Crowd bench: building and stepping a 100 x 60 m hall with 50, 200 and 1000 people.

Three tenths of the people stand alone, three tenths talk in groups of three (conversations for
the whole episode), the rest walk between two random points of the hall (seeded), and one robot
crosses the hall on the ``social`` planner. For each size the bench reports, as medians over
trials:

- build: the wall time of ``ProxemicEnv(...)`` (scenario validation, the Rust world with every
  person's paths planned, the MuJoCo physics model compiled: with the people up to 1000 of them,
  without them beyond, see ``proxemic.sim.reduced.FULL_MODEL_PEOPLE``) and of the first ``reset``;
- step: thread CPU time of an env step with the robot's ``social`` planner driving, split into
  the physics (the ``frame_skip`` ``mj_step`` calls of the step, with the people's poses and the
  contact hints written), the core (the rest of the one Rust call ``World.step``) and Python (the
  env's observation, outcome and info), all timed in the same steps;
- bare MuJoCo: ``mj_step`` alone, ``frame_skip`` calls per control step of the same model and
  state after the trial (contacts as the last step's hints left them), for the physics floor of
  a step;
- re-plans: the steps in which the robot ran a social search (``World.social_searches``, read
  outside the timers: the planner's A* searches of the whole hall, its triggers and its
  refreshes, which come every 2 s on small maps and about every 10 s in the 1000-person hall),
  and their share of the mean core time.

The growth from 50 to 1000 people is printed as a ratio per person. Target (reliability issue):
1000 people build in at most 2 s; the bench exits non-zero when it is missed.

Ten thousand people: the 1000-person hall and a hall of 10,000 people at the same
density (:func:`hall_size`, 316 x 190 m), each built and stepped in a fresh process (its peak RSS
is the process's): build (``ProxemicEnv`` and the first ``reset``), the median env step over
:data:`BIG_STEPS` steps with plain A* and with ``social`` driving, the peak RSS, and the growth
per person from 1000 to 10,000. Targets: build <= 5 s, env step with ``social`` <= 20 ms; the bench
exits non-zero when one is missed.

Run: ``python benches/crowd_bench.py`` (``make bench`` does). ``--write DIR`` writes the scenario
files (``crowd_<people>.toml``) into ``DIR`` and exits, e.g. for the Rust example
``crowd_world_timing``, which times the core alone on them and prints a digest of its outputs.
"""

from __future__ import annotations

import math
import os
import random
import statistics
import sys
import tempfile
import time
from dataclasses import dataclass
from pathlib import Path

os.environ.setdefault("MUJOCO_GL", "egl")

import mujoco
import numpy as np

from proxemic.env import ProxemicEnv
from proxemic.sim import timer_off

SIZES = (50, 200, 1000)
TRIALS = 3
#: Control steps per trial (60 s): the ``social`` planner refreshes its path of a large hall only
#: every ~10 s (its refresh period grows with the size of its last search), and the mean step must
#: pay for those refreshes as a long run does.
STEPS = 600
BUILD_TARGET_S = 2.0
#: The issue's target for an env step of the largest crowd with the ``social`` planner (microseconds).
STEP_TARGET_US = 2000.0
WIDTH, HEIGHT = 100.0, 60.0
#: The ten-thousand-person rows: sizes, steps per run, targets.
BIG_SIZES = (1000, 10000)
BIG_STEPS = 100
BIG_BUILD_TARGET_S = 5.0
BIG_STEP_TARGET_MS = 20.0
#: Least distance between any two placed points of the crowd (m).
CLEARANCE = 0.8


def hall_size(people: int) -> tuple[float, float]:
    """The hall of `people` people: 100 x 60 m up to 1000 people, larger beyond at the same density
    (6 m² per person) and the same 5:3 shape."""
    if people <= 1000:
        return WIDTH, HEIGHT
    scale = math.sqrt(people / 1000)
    return round(WIDTH * scale), round(HEIGHT * scale)


def crowd_scenario(people: int, seed: int = 1) -> str:
    """The TOML text of the hall (:func:`hall_size`) with `people` people (seeded).

    Three tenths of them stand alone, three tenths talk in groups of three (a conversation around
    an o-space centre for the whole episode; a group of two or one more standing person takes the
    remainder) and the rest walk between two random points of the hall.
    """
    rng = random.Random(seed)
    width, height = hall_size(people)
    corners = [(0, 0), (width, 0), (width, height), (0, height)]
    lines = [
        "[scene]",
        f'name = "crowd_{people}"',
        f"bounds = [0, 0, {width}, {height}]",
    ]
    for (x0, y0), (x1, y1) in zip(corners, corners[1:] + corners[:1], strict=True):
        lines += ["[[wall]]", f"from = [{x0}, {y0}]", f"to = [{x1}, {y1}]"]
    lines += ["[[robot]]", f"start = [2, {height / 2:g}, 0]", f"goal = [{width - 2:g}, {height / 2:g}]"]
    lines += ['planner = "social"']
    lines += ["[episode]", "max_time = 300"]
    # Every placed point (standing poses, route ends, conversation places) at least CLEARANCE
    # from the others: the scenario check rejects people placed overlapping. A coarse grid of
    # cells finds neighbours.
    cells: dict[tuple[int, int], list[tuple[float, float]]] = {}

    def is_free(x: float, y: float, clear: float) -> bool:
        cx, cy, k = int(x // CLEARANCE), int(y // CLEARANCE), int(clear // CLEARANCE) + 1
        near = (q for i in range(-k, k + 1) for j in range(-k, k + 1) for q in cells.get((cx + i, cy + j), ()))
        return all((x - qx) ** 2 + (y - qy) ** 2 >= clear**2 for qx, qy in near)

    def place(x: float, y: float) -> None:
        cells.setdefault((int(x // CLEARANCE), int(y // CLEARANCE)), []).append((x, y))

    def free_point(clear: float = CLEARANCE) -> tuple[float, float]:
        while True:
            x, y = round(rng.uniform(5, width - 5), 2), round(rng.uniform(3, height - 3), 2)
            if is_free(x, y, clear):
                return x, y

    standing = round(0.3 * people)
    talking = round(0.3 * people)
    sizes = [3] * (talking // 3) + ([talking % 3] if talking % 3 == 2 else [])
    standing += talking - sum(sizes)  # a remainder of one talker stands alone
    walking = people - standing - sum(sizes)
    for _ in range(standing):
        x, y = free_point()
        place(x, y)
        lines += ["[[person]]", 'behaviour = "standing"', f"pose = [{x:.2f}, {y:.2f}, {rng.uniform(-3, 3):.2f}]"]
    for group, n in enumerate(sizes, start=1):
        # The members stand on a circle of radius 0.4 + 0.1 n around the spot (the core's
        # conversation layout), the first member's home setting the circle's first angle; the
        # homes are the places themselves, pushed out by CLEARANCE.
        r = 0.4 + 0.1 * n
        while True:
            sx, sy = free_point(r + CLEARANCE)
            a0 = rng.uniform(-math.pi, math.pi)
            angles = [a0 + math.tau * k / n for k in range(n)]
            homes = [(sx + (r + CLEARANCE) * math.cos(a), sy + (r + CLEARANCE) * math.sin(a)) for a in angles]
            if all(is_free(hx, hy, CLEARANCE) for hx, hy in homes):
                break
        for a in angles:
            place(sx + r * math.cos(a), sy + r * math.sin(a))
        for hx, hy in homes:
            place(hx, hy)
            lines += [
                "[[person]]",
                'behaviour = "conversation"',
                f"group = {group}",
                f"home = [{hx:.3f}, {hy:.3f}]",
                f"spot = [{sx:.2f}, {sy:.2f}]",
                "start = -10.0",
                "end = 100000.0",
            ]
    for _ in range(walking):
        x, y = free_point()
        place(x, y)
        x2, y2 = free_point()
        place(x2, y2)
        lines += ["[[person]]", f"route = [[{x:.2f}, {y:.2f}], [{x2:.2f}, {y2:.2f}]]"]
    return "\n".join(lines) + "\n"


@dataclass
class Trial:
    """One trial's figures (seconds for the build, microseconds per control step otherwise)."""

    build: float
    step: float
    physics: float
    core: float
    python: float
    bare: float
    replan_steps: int
    replan: float


def measure(path: Path) -> Trial:
    """One trial: build, then STEPS env steps timed and split, then bare MuJoCo stepping."""
    t0 = time.perf_counter()
    env = ProxemicEnv(path, autopilot=True)
    env.reset(seed=0)
    build = time.perf_counter() - t0
    # The env's World.step call and the physics it calls back between its two halves, timed by
    # wrappers set on this env's WorldSim (instance attributes, removed after the steps).
    ws = env.ws
    world_step, physics = ws.step, ws._physics
    last = [0, 0]  # World.step, physics (ns) of the last env step

    def timed_physics() -> None:
        t = time.thread_time_ns()
        physics()
        last[1] = time.thread_time_ns() - t

    def timed_world_step(actions: np.ndarray | None = None) -> None:
        t = time.thread_time_ns()
        world_step(actions)
        last[0] = time.thread_time_ns() - t

    ws._physics, ws.step = timed_physics, timed_world_step  # type: ignore[method-assign]
    calls: list[tuple[int, int, int]] = []  # per env step: env.step, World.step, physics (ns)
    searched: list[bool] = []  # per env step: whether the robot ran a social search in it
    for _ in range(STEPS):
        before = env.world.social_searches(0)
        c0 = time.thread_time_ns()
        _, _, terminated, truncated, _ = env.step(env.action_space.sample() * 0)
        calls.append((time.thread_time_ns() - c0, last[0], last[1]))
        searched.append(env.world.social_searches(0) > before)
        if terminated or truncated:
            env.reset()
    del ws._physics, ws.step
    sim = env.sim
    with timer_off():  # as the env steps
        c0 = time.thread_time_ns()
        for _ in range(STEPS):
            mujoco.mj_step(sim.model, sim.data, sim.frame_skip)
        bare = (time.thread_time_ns() - c0) / STEPS / 1e3
    env.close()
    core = [(rust - phys) / 1e3 for _, rust, phys in calls]
    search_steps = [c for c, s in zip(core, searched, strict=True) if s]
    return Trial(
        build=build,
        step=sum(c[0] for c in calls) / STEPS / 1e3,
        physics=sum(c[2] for c in calls) / STEPS / 1e3,
        core=sum(core) / STEPS,
        python=sum(c[0] - c[1] for c in calls) / STEPS / 1e3,
        bare=bare,
        replan_steps=len(search_steps),
        replan=sum(search_steps) / STEPS,
    )


def one_run(path: Path, planner: str, steps: int) -> dict[str, float]:
    """Builds `path` with `planner` driving, steps it `steps` times: build (s), median step (ms)."""
    import resource

    t0 = time.perf_counter()
    env = ProxemicEnv(path, autopilot=True, planner=planner)
    env.reset(seed=0)
    build = time.perf_counter() - t0
    times = []
    for _ in range(steps):
        t = time.perf_counter()
        _, _, terminated, truncated, _ = env.step(env.action_space.sample() * 0)
        times.append(time.perf_counter() - t)
        if terminated or truncated:
            env.reset()
    env.close()
    rss = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024
    return {"build": build, "step": 1e3 * statistics.median(times), "rss": rss}


def big_rows(tmp: Path) -> bool:
    """The 1000 and 10,000-person rows (each run in a fresh process); returns whether the targets were met."""
    import json
    import subprocess

    rows = {}
    for n in BIG_SIZES:
        path = tmp / f"crowd_{n}.toml"
        path.write_text(crowd_scenario(n))
        for planner in ("astar", "social"):
            out = subprocess.run(
                [sys.executable, __file__, "--one", str(path), planner, str(BIG_STEPS)],
                capture_output=True,
                text=True,
                check=True,
            ).stdout
            rows[n, planner] = json.loads(out.splitlines()[-1])
    print(
        f"{'people':>7} {'hall [m]':>10} {'build [s]':>10} {'step astar [ms]':>16} {'step social [ms]':>17}"
        f" {'RSS [MB]':>9}"
    )
    for n in BIG_SIZES:
        a, b = rows[n, "astar"], rows[n, "social"]
        w, h = hall_size(n)
        print(
            f"{n:>7} {f'{w:g} x {h:g}':>10} {statistics.median([a['build'], b['build']]):>10.2f}"
            f" {a['step']:>16.2f} {b['step']:>17.2f} {max(a['rss'], b['rss']):>9.0f}"
        )
    n0, n1 = BIG_SIZES
    for planner in ("astar", "social"):
        g = rows[n1, planner]["step"] / rows[n0, planner]["step"]
        print(f"growth {n0} -> {n1} people, {planner}: step x{g:.1f} for x{n1 / n0:.0f} people")
    build = statistics.median([rows[n1, "astar"]["build"], rows[n1, "social"]["build"]])
    step = rows[n1, "social"]["step"]
    ok_build, ok_step = build <= BIG_BUILD_TARGET_S, step <= BIG_STEP_TARGET_MS
    print(f"build of {n1} people: {build:.2f} s, target <= {BIG_BUILD_TARGET_S} s: {'met' if ok_build else 'MISSED'}")
    print(
        f"env step with {n1} people (social): {step:.2f} ms, target <= {BIG_STEP_TARGET_MS} ms: "
        f"{'met' if ok_step else 'MISSED'}"
    )
    return ok_build and ok_step


def main() -> int:
    """Runs the bench; returns the exit code (1 when a target is missed)."""
    if len(sys.argv) == 5 and sys.argv[1] == "--one":
        import json

        print(json.dumps(one_run(Path(sys.argv[2]), sys.argv[3], int(sys.argv[4]))))
        return 0
    if len(sys.argv) == 3 and sys.argv[1] == "--write":
        out = Path(sys.argv[2])
        out.mkdir(parents=True, exist_ok=True)
        for n in SIZES:
            (out / f"crowd_{n}.toml").write_text(crowd_scenario(n))
        print(f"wrote {', '.join(f'crowd_{n}.toml' for n in SIZES)} to {out}")
        return 0
    if len(sys.argv) == 2 and sys.argv[1] == "--big":
        with tempfile.TemporaryDirectory() as tmp:
            return 0 if big_rows(Path(tmp)) else 1
    rows = []
    with tempfile.TemporaryDirectory() as tmp:
        for n in SIZES:
            path = Path(tmp) / f"crowd_{n}.toml"
            path.write_text(crowd_scenario(n))
            trials = [measure(path) for _ in range(TRIALS)]
            med = {f: statistics.median(getattr(t, f) for t in trials) for f in Trial.__dataclass_fields__}
            rows.append((n, med))
    print(
        f"{'people':>7} {'build [s]':>10} {'env step, social [us]':>22} {'step per person [us]':>21}"
        f" {'physics':>8} {'core':>8} {'python':>7} {'bare mj_step':>13} {'re-plans (core us)':>19}"
    )
    for n, m in rows:
        print(
            f"{n:>7} {m['build']:>10.3f} {m['step']:>22.1f} {m['step'] / n:>21.2f} {m['physics']:>8.0f}"
            f" {m['core']:>8.0f} {m['python']:>7.0f} {m['bare']:>13.0f}"
            f" {m['replan_steps']:>8.0f} ({m['replan']:>6.0f})"
        )
    (n0, m0), (n1, m1) = rows[0], rows[-1]
    s0, s1, b1 = m0["step"], m1["step"], m1["build"]
    print(f"growth {n0} -> {n1} people: step x{s1 / s0:.1f} for x{n1 / n0:.0f} people")
    with tempfile.TemporaryDirectory() as tmp:
        ok_big = big_rows(Path(tmp))
    ok_build = b1 <= BUILD_TARGET_S
    ok_step = s1 <= STEP_TARGET_US
    print(f"build of {n1} people: {b1:.3f} s, target <= {BUILD_TARGET_S} s: {'met' if ok_build else 'MISSED'}")
    print(
        f"env step with {n1} people (social): {s1 / 1e3:.2f} ms, target <= {STEP_TARGET_US / 1e3:.1f} ms: "
        f"{'met' if ok_step else 'MISSED'}"
    )
    return 0 if ok_build and ok_step and ok_big else 1


if __name__ == "__main__":
    sys.exit(main())
