"""Env throughput and rendering bench: the museum with (at least) 40 people.

Steps: env steps per second, the Rust call's share, bare MuJoCo stepping of the same model (and of
the full visual model, which the physics stepped before it lost its visual parts), reset.
Everything is measured in this run, on the same model, interleaved over several trials (the
machine is shared and noisy), as thread CPU time; medians are reported with ratios against the
bare ``mj_step`` cost of the same control steps. The env steps MuJoCo without the timer callback
MuJoCo's Python bindings install (``proxemic.sim.timer_off``: a clock read per timed stage), and
the bare denominators are stepped the same way, like with like. Control periods without a person
in reach are stepped on reduced models (the same robot states and contacts bit for bit): contacts
off on the robots alone (``Simulation.contact_free_model``), contacts on for walls, objects and
robots only on the physics model without the people (``Simulation.robots_model``), and periods
with a few people in reach on a crowd model (the robots with stand-ins for just those people).

The env steps a control period with contacts disabled when the core's hints rule every contact
out (``Sim.step(contacts_possible=False)``). The *matched* denominator is therefore measured on
what the env stepped: every ``REPLAY_EVERY``-th control period of the timed run is kept (the
model it was stepped on, ``Simulation.stepped``, and its integration state at the period's end) and
stepped bare afterwards with the env's contact setting (``ContactCounter.replay_us``); the
keeping's own cost is taken off the env's times. The physics model stepped with contacts on, the
model without the people and the robots alone are printed beside it, and the old-style
denominator (the physics model with contacts off in the periods the env stepped with contacts
off, as the env stepped before the reduced models), for plain A* and ``social``. The targets use
that physics model's denominator: the bare stepping of every body of the scene as a plain MuJoCo
gym would step it, with the env's contact setting in those periods. The reduced models are our
optimisation and stay in the numerator's favour; the matched ratio is printed beside as
information.

Three env settings: the autopilot with plain A* (medians of ``STEPS``-step blocks); the ``social``
planner, whose cost is the **mean** over a ``SOCIAL_STEPS``-step run (throughput pays the periodic
re-plans too), with its median block beside it and its mean over the steps in which the planner
ran no social search (``World.social_searches``, read outside the timer: a step without
re-planning, against the run's matched denominator); and what a learning policy pays: the planner off
(``planner_actions=False``), the policy turning in place. Targets: plain A* at least 3,000 env
steps/s and at most 1.5x the physics model; ``social`` at most 2.0x the physics model (mean); the policy at
least 8,000 env steps/s; reset at most 1 ms; the built-in ``learned`` planner's mean env step at most
1.5x ``astar_orca``'s (both over ``SOCIAL_STEPS``-step runs from the same seeds). A missed target
prints ``MISSED`` and the bench exits with status 1.

Rendering: milliseconds per 640x480 frame from MuJoCo's top camera, its camera following the
robot (offscreen, EGL or OSMesa) and the numpy top-down view (bare and with every overlay), as
wall time (the GL driver renders in its own threads, which thread CPU time would miss), medians
over trials, with the ratio to an env step measured in the same run.

If the museum scenario has fewer than ``--people`` people, copies of its walkers (same routes and
speeds, each starting at its own random point of its route) are added to reach the count; the
bench prints how many were scripted and how many copied.

Run: ``python benches/env_bench.py [--people N]`` (``make bench`` does).
"""

from __future__ import annotations

import argparse
import os
import re
import statistics
import sys
import tempfile
import time
from collections.abc import Callable
from pathlib import Path
from typing import Any

os.environ.setdefault("MUJOCO_GL", "egl")

import mujoco
import numpy as np

from proxemic import scenarios
from proxemic.env import ProxemicEnv
from proxemic.sim import timer_off
from proxemic.viz.topdown import OVERLAYS

TRIALS = 7
STEPS = 400
SOCIAL_STEPS = 600
#: Every how many control periods the counter keeps one to replay bare (see ``ContactCounter``).
REPLAY_EVERY = 4
#: What a kept period's replay starts from: MuJoCo's full integration state.
INTEGRATION = int(mujoco.mjtState.mjSTATE_INTEGRATION)
#: Env steps per second a learning policy's single env keeps (at least the 8k steps/s the
#: first wave measured).
POLICY_TARGET = 8000
FRAMES = 20


def cpu_us(fn: Callable[[], object], n: int) -> float:
    t0 = time.thread_time_ns()
    for _ in range(n):
        fn()
    return (time.thread_time_ns() - t0) / n / 1e3


def bare_us(fn: Callable[[], object], n: int) -> float:
    """:func:`cpu_us` of bare MuJoCo stepping, stepped as the env steps (without the bindings' timer)."""
    with timer_off():
        return cpu_us(fn, n)


def contact_free(sim: Any, people: bool = False, contacts: bool = False) -> Callable[[], None]:
    """Bare stepping of what the env steps while no person is in reach, from the env's state.

    On its own data: ``sim.contact_free_model`` (the robots alone, see ``proxemic.sim``) with
    collision detection off, or with `contacts` ``sim.robots_model`` (the physics model without
    the people); with `people`, the physics model with collision detection off (what the env
    stepped before it had the reduced models).
    """
    model = sim.model if people else (sim.robots_model if contacts else sim.contact_free_model)
    skip = sim.frame_skip
    d = mujoco.MjData(model)
    names = ("qpos", "qvel", "ctrl", "qacc_warmstart") + (("mocap_pos", "mocap_quat") if people else ())
    for name in names:
        getattr(d, name)[:] = getattr(sim.data, name)
    flags = int(model.opt.disableflags)
    off = flags if contacts else flags | int(mujoco.mjtDisableBit.mjDSBL_CONTACT)

    def step() -> None:
        model.opt.disableflags = off
        mujoco.mj_step(model, d, skip)
        model.opt.disableflags = flags

    return step


def physics_model_us(contact_share: float, on_us: float, off_us: float) -> float:
    """The old-style denominator: the physics model stepped with the env's contact setting.

    The physics model with contacts on (`on_us`) in the `contact_share` of periods the env stepped
    with contacts possible, with contacts off (`off_us`) in the others, as the env stepped before
    the reduced models.
    """
    return contact_share * on_us + (1.0 - contact_share) * off_us


def wall_cpu_ms(fn: Callable[[], Any], n: int) -> tuple[float, float]:
    c0, t0 = time.thread_time_ns(), time.perf_counter_ns()
    for _ in range(n):
        fn()
    t1, c1 = time.perf_counter_ns(), time.thread_time_ns()
    return (t1 - t0) / n / 1e6, (c1 - c0) / n / 1e6


def museum_with(people: int, tmp: Path) -> tuple[str | Path, int, int]:
    """The museum scenario with at least `people` people: (scenario, scripted, copied)."""
    text = scenarios.resolve("museum").read_text()
    # each [[person]] table runs to the next table header
    blocks = re.findall(r"^\[\[person\]\]\n(?:(?!\[).*\n?)*", text, flags=re.M)
    walkers = [blk for blk in blocks if re.search(r'^behaviour\s*=\s*"walker"', blk, flags=re.M)]
    missing = people - len(blocks)
    if missing <= 0 or not walkers:
        return "museum", len(blocks), 0
    extra = []
    for k in range(missing):
        blk = walkers[k % len(walkers)]
        extra.append(re.sub(r'^name\s*=\s*"([^"]*)"', rf'name = "\1_bench_copy_{k}"', blk, count=1, flags=re.M))
    out = tmp / "museum_bench.toml"
    out.write_text(text + "\n# copies of walkers added by benches/env_bench.py\n" + "\n".join(extra))
    return out, len(blocks), missing


def bench_steps(env: ProxemicEnv) -> dict[str, float]:
    env.reset(seed=0)
    skip = env.sim.frame_skip
    world, sim = env.world, env.sim
    zero = np.zeros(3, np.float32)
    autopilot = np.full(3 * world.num_robots, np.nan)
    models = {"bare mj_step x frame_skip": sim.model, "bare mj_step x frame_skip (full model)": sim.render_model}
    scratch = {k: mujoco.MjData(model) for k, model in models.items()}

    def env_step() -> None:
        _, _, te, tr, _ = env.step(zero)
        if te or tr:
            env.reset()

    def rust_step() -> None:
        # The core's share of the one call: World.step with a physics that does nothing.
        world.step(autopilot, lambda: None, sim.state, sim.contacts, env._out, env._people)

    def bare_from_env(key: str) -> Callable[[], None]:
        model, d = models[key], scratch[key]

        def sync() -> None:  # the env's current state, on a scratch copy
            for name in ("qpos", "qvel", "ctrl", "mocap_pos", "mocap_quat", "qacc_warmstart"):
                getattr(d, name)[:] = getattr(sim.data, name)

        def step() -> None:
            mujoco.mj_step(model, d, skip)

        step.sync = sync  # type: ignore[attr-defined]
        return step

    resets: list[float] = []
    # the full metric set of one finished episode (World.episode_metrics: the post-hoc evaluator)
    metrics_us: list[float] = []
    episode_steps: list[int] = []
    res: dict[str, list[float]] = {
        "env.step": [],
        "Rust World.step": [],
        "contact share": [],
        "robots-only share": [],
        "crowd share": [],
        "matched": [],
        "bare robots only, contacts on": [],
        "bare contacts off": [],
        "bare contacts off, with the people": [],
        **{k: [] for k in models},
    }
    counter = ContactCounter(sim)
    seed = 0
    for _ in range(TRIALS):
        with counter:
            res["env.step"].append(cpu_us(env_step, STEPS) - counter.overhead_ns / 1e3 / STEPS)
        res["contact share"].append(counter.share())
        res["robots-only share"].append(counter.robots_only_share())
        res["crowd share"].append(counter.crowd_share())
        res["matched"].append(counter.replay_us())
        res["bare robots only, contacts on"].append(bare_us(contact_free(sim, contacts=True), STEPS))
        for key in models:
            bare = bare_from_env(key)
            bare.sync()  # type: ignore[attr-defined]
            res[key].append(bare_us(bare, STEPS))
        res["bare contacts off"].append(bare_us(contact_free(sim), STEPS))
        res["bare contacts off, with the people"].append(bare_us(contact_free(sim, people=True), STEPS))
        # the Rust call alone, on the state the env is in (advances the people; harmless here)
        res["Rust World.step"].append(cpu_us(rust_step, STEPS))
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
    med["env.reset"] = statistics.median(resets)
    med["episode_metrics"] = statistics.median(metrics_us)
    med["episode steps"] = statistics.median(episode_steps)
    return med


class ContactCounter:
    """Counts, while active (``with``), the env's control periods by kind, and keeps some to replay.

    Kinds: contacts on or off, and contacts on without a person in reach (the physics model
    without the people) or with a few people in reach (a crowd model, see ``proxemic.sim``).
    Every ``REPLAY_EVERY``-th period, the model the env stepped it on and its integration state at
    the period's end are kept: :meth:`replay_us` steps each of them bare, as the env would step
    the next period on that model, for the like-with-like denominator. What the counting costs
    is summed in ``overhead_ns`` for the benches to take off the env's times.
    """

    def __init__(self, sim: Any) -> None:
        self.sim = sim
        self.on = 0
        self.robots_only_on = 0
        self.crowd_on = 0
        self.total = 0
        self.kept: list[tuple[mujoco.MjModel, np.ndarray, int]] = []
        #: Thread CPU time the counting and keeping took in the env's steps (ns), for the
        #: benches to take off their env step times.
        self.overhead_ns = 0

    def __enter__(self) -> ContactCounter:
        self.on = self.robots_only_on = self.crowd_on = self.total = self.overhead_ns = 0
        self.kept = []
        sim = self.sim
        step = sim.step
        crowd_models = {id(c.model) for c in sim._crowds.values()}
        no_contact = int(mujoco.mjtDisableBit.mjDSBL_CONTACT)

        def counted(command: np.ndarray, contacts_possible: bool = True) -> None:
            step(command, contacts_possible)
            t0 = time.thread_time_ns()
            m, d = sim.stepped
            self.on += bool(contacts_possible)
            # contacts on without a person in reach: stepped on the physics model without the people
            self.robots_only_on += bool(contacts_possible) and m is sim.robots_model
            self.crowd_on += bool(contacts_possible) and id(m) in crowd_models
            if self.total % REPLAY_EVERY == 0:
                flags = int(m.opt.disableflags) | (0 if contacts_possible else no_contact)
                # the integration state only (a few kB; a copy of the data would be its 13 MB arena)
                state = np.empty(mujoco.mj_stateSize(m, INTEGRATION))
                mujoco.mj_getState(m, d, state, INTEGRATION)
                self.kept.append((m, state, flags))
            self.total += 1
            self.overhead_ns += time.thread_time_ns() - t0

        self.sim.step = counted
        return self

    def __exit__(self, *exc: object) -> None:
        del self.sim.step  # the instance attribute: the class's method is back

    def share(self) -> float:
        """The share of the counted control periods that had contacts on (1.0 when none ran)."""
        return self.on / self.total if self.total else 1.0

    def robots_only_share(self) -> float:
        """The share of the counted control periods with contacts on but no person in reach."""
        return self.robots_only_on / self.total if self.total else 0.0

    def crowd_share(self) -> float:
        """The share of the counted control periods stepped on a crowd model."""
        return self.crowd_on / self.total if self.total else 0.0

    def replay_us(self) -> float:
        """Bare MuJoCo per control period, like with like: the mean over the kept periods of one
        period's ``mj_step`` calls on the model the env stepped, from its state then, with the
        env's contact setting (each the median of 3 from the kept state; the bindings' timer off)."""
        skip = self.sim.frame_skip
        per: list[float] = []
        scratch: dict[int, mujoco.MjData] = {}  # one per model, reused: warm, as the env's data is
        with timer_off():
            for m, kept, flags in self.kept:
                d = scratch.setdefault(id(m), mujoco.MjData(m))
                saved = int(m.opt.disableflags)
                times = []
                for _ in range(3):
                    mujoco.mj_setState(m, d, kept, INTEGRATION)
                    m.opt.disableflags = flags
                    t0 = time.thread_time_ns()
                    mujoco.mj_step(m, d, skip)
                    times.append((time.thread_time_ns() - t0) / 1e3)
                    m.opt.disableflags = saved
                per.append(statistics.median(times))
        return statistics.fmean(per) if per else float("nan")


def bench_policy(env: ProxemicEnv) -> dict[str, float]:
    """A learning policy's env step: the robot's planner off, the policy turning in place.

    Turning in place keeps the robot's lidar and observation changing every step and the episode
    live (a robot driving blindly ends its episode in a few seconds); the same policy as
    ``benches/parallel_bench.py``'s policies-only row. Bare MuJoCo from the env's states, contacts
    matched as for the autopilot row.
    """
    sim = env.sim
    turn = np.array([0.0, 0.0, 0.5], np.float32)
    counter = ContactCounter(sim)

    def env_step() -> None:
        _, _, te, tr, _ = env.step(turn)
        if te or tr:
            env.reset()

    res: dict[str, list[float]] = {"env.step": [], "contact share": [], "matched": []}
    env.reset(seed=0)
    for _ in range(TRIALS):
        with counter:
            res["env.step"].append(cpu_us(env_step, STEPS) - counter.overhead_ns / 1e3 / STEPS)
        res["contact share"].append(counter.share())
        res["matched"].append(counter.replay_us())
    return {k: statistics.median(v) for k, v in res.items()}


def bench_social(env: ProxemicEnv) -> dict[str, float]:
    """The ``social`` planner's env step: the mean over ``SOCIAL_STEPS``-step runs, and bare MuJoCo."""
    sim = env.sim
    zero = np.zeros(3, np.float32)
    skip = sim.frame_skip
    d = mujoco.MjData(sim.model)
    counter = ContactCounter(sim)
    res: dict[str, list[float]] = {
        "mean": [],
        "median block": [],
        "contact share": [],
        "crowd share": [],
        "matched": [],
        "bare mj_step x frame_skip": [],
        "bare contacts off, with the people": [],
        "quiet mean": [],
        "quiet share": [],
    }
    for trial in range(TRIALS):
        env.reset(seed=1000 + trial)
        times: list[float] = []
        quiet: list[float] = []  # the steps in which the robot ran no social search
        with counter:
            for _ in range(SOCIAL_STEPS):
                before, searches = counter.overhead_ns, env.world.social_searches(0)
                t0 = time.thread_time_ns()
                _, _, te, tr, _ = env.step(zero)
                times.append((time.thread_time_ns() - t0 - (counter.overhead_ns - before)) / 1e3)
                if env.world.social_searches(0) == searches:
                    quiet.append(times[-1])
                if te or tr:
                    env.reset()
        res["quiet mean"].append(statistics.fmean(quiet) if quiet else float("nan"))
        res["quiet share"].append(len(quiet) / SOCIAL_STEPS)
        res["contact share"].append(counter.share())
        res["crowd share"].append(counter.crowd_share())
        res["matched"].append(counter.replay_us())
        res["mean"].append(statistics.fmean(times))
        res["median block"].append(
            statistics.median(statistics.fmean(times[k : k + 50]) for k in range(0, len(times), 50))
        )
        for name in ("qpos", "qvel", "ctrl", "mocap_pos", "mocap_quat", "qacc_warmstart"):
            getattr(d, name)[:] = getattr(sim.data, name)

        def on() -> None:
            mujoco.mj_step(sim.model, d, skip)

        res["bare mj_step x frame_skip"].append(bare_us(on, STEPS))
        res["bare contacts off, with the people"].append(bare_us(contact_free(sim, people=True), STEPS))
    return {k: statistics.median(v) for k, v in res.items()}


def mean_step_us(env: ProxemicEnv) -> float:
    """The median over ``TRIALS`` of the mean ``env.step`` CPU time over ``SOCIAL_STEPS`` steps (resets untimed)."""
    zero = np.zeros(3, np.float32)
    means = []
    for trial in range(TRIALS):
        env.reset(seed=1000 + trial)
        total = 0.0
        for _ in range(SOCIAL_STEPS):
            t0 = time.thread_time_ns()
            _, _, te, tr, _ = env.step(zero)
            total += (time.thread_time_ns() - t0) / 1e3
            if te or tr:
                env.reset()
        means.append(total / SOCIAL_STEPS)
    return statistics.median(means)


def bench_render(env: ProxemicEnv) -> dict[str, tuple[float, float]]:
    env.reset(seed=0)
    zero = np.zeros(3, np.float32)
    for _ in range(20):  # people moving, a path planned
        env.step(zero)
    views: dict[str, Callable[[], Any]] = {
        "MuJoCo top camera": lambda: env.sim.render(640, 480, "top"),
        "MuJoCo follow camera": lambda: env.sim.render(640, 480, "robot_0/follow"),
        "top-down (path)": lambda: env.render_topdown(("path",)),
        "top-down (every overlay)": lambda: env.render_topdown(OVERLAYS),
    }
    for fn in views.values():  # contexts, renderers, caches
        fn()
    views["env.step"] = lambda: env.step(zero)
    res: dict[str, list[tuple[float, float]]] = {k: [] for k in views}
    for _ in range(TRIALS):
        for k, fn in views.items():
            res[k].append(wall_cpu_ms(fn, FRAMES))
    return {k: (statistics.median(w for w, _ in v), statistics.median(c for _, c in v)) for k, v in res.items()}


def main() -> int:
    """Runs the bench; returns 1 if a target was missed."""
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("--people", type=int, default=40, help="people in the museum (default: 40)")
    a = p.parse_args()
    with tempfile.TemporaryDirectory() as tmp:
        scenario, scripted, copied = museum_with(a.people, Path(tmp))
        env = ProxemicEnv(scenario, autopilot=True, width=640, height=480)
        social_env = ProxemicEnv(scenario, autopilot=True, planner="social")
        policy_env = ProxemicEnv(scenario, planner_actions=False)
    n = env.world.num_people
    skip = env.sim.frame_skip
    med = bench_steps(env)
    base = med["matched"]
    on = med["bare mj_step x frame_skip"]
    how = f"{scripted} scripted + {copied} copied walkers" if copied else "as scripted"
    print(
        f"museum: {n} people ({how}), {skip} physics steps per control step, "
        f"{TRIALS} trials x {STEPS} steps, thread CPU time, medians"
    )
    rate, ratio = 1e6 / med["env.step"], med["env.step"] / base
    print(
        f"  {'env.step (autopilot: plain A*)':40s} {med['env.step']:8.1f} us  "
        f"{rate:8.0f} steps/s  ratio to bare MuJoCo {ratio:5.2f}x matched "
        f"({med['env.step'] / on:4.2f}x contacts on)"
    )
    print(
        f"  {'Rust World.step (one call)':40s} {med['Rust World.step']:8.1f} us  "
        f"{100 * med['Rust World.step'] / med['env.step']:5.1f}% of the env step"
    )
    print(
        f"  {'bare mj_step x frame_skip, matched':40s} {base:8.1f} us  (the models the env stepped, replayed "
        f"from every {REPLAY_EVERY}th period; contacts on in {100 * med['contact share']:.0f}% of the env's "
        f"steps: {100 * med['robots-only share']:.0f}% without a person in reach, "
        f"{100 * med['crowd share']:.0f}% on a crowd model; the physics model with contacts on {on:.1f} us, "
        f"without the people {med['bare robots only, contacts on']:.1f} us, "
        f"the robots alone with contacts off {med['bare contacts off']:.1f} us)"
    )
    share = med["contact share"]
    with_people = physics_model_us(share, on, med["bare contacts off, with the people"])
    print(
        f"  {'bare, contacts off with the people':40s} {with_people:8.1f} us  matched (off "
        f"{med['bare contacts off, with the people']:.1f} us: the physics model, as stepped before the "
        f"reduced models; {med['env.step'] / with_people:4.2f}x)"
    )
    full = med["bare mj_step x frame_skip (full model)"]
    ratio_full = med["env.step"] / full
    print(f"  {'bare mj_step x frame_skip, full model':40s} {full:8.1f} us  (visual parts; {ratio_full:4.2f}x)")
    print(f"  {'env.reset':40s} {med['env.reset'] / 1e3:8.2f} ms")
    soc = bench_social(social_env)
    social_env.close()
    soc_ratio = soc["mean"] / soc["matched"]
    print(
        f"  {'env.step (autopilot: social)':40s} {soc['mean']:8.1f} us  mean over {SOCIAL_STEPS} steps, "
        f"{soc_ratio:5.2f}x bare MuJoCo matched ({soc['mean'] / soc['bare mj_step x frame_skip']:4.2f}x contacts on); "
        f"median 50-step block {soc['median block']:.1f} us ({soc['median block'] / soc['matched']:4.2f}x); "
        f"bare matched {soc['matched']:.1f} us (contacts on in {100 * soc['contact share']:.0f}%, "
        f"{100 * soc['crowd share']:.0f}% on a crowd model)"
    )
    soc_people = physics_model_us(
        soc["contact share"], soc["bare mj_step x frame_skip"], soc["bare contacts off, with the people"]
    )
    print(
        f"  {'':40s} the physics model as stepped before the reduced models (contacts on in the same "
        f"periods): {soc_people:.1f} us, {soc['mean'] / soc_people:4.2f}x"
    )
    print(
        f"  {'':40s} without its searches: {soc['quiet mean']:.1f} us mean over the "
        f"{100 * soc['quiet share']:.0f}% of steps in which the planner ran no social search "
        f"({soc['quiet mean'] / soc['matched']:4.2f}x the run's bare matched)"
    )
    pol = bench_policy(policy_env)
    policy_env.close()
    pol_rate = 1e6 / pol["env.step"]
    print(
        f"  {'env.step (policy turning, planner off)':40s} {pol['env.step']:8.1f} us  {pol_rate:8.0f} steps/s  "
        f"{pol['env.step'] / pol['matched']:5.2f}x bare MuJoCo matched "
        f"(bare matched {pol['matched']:.1f} us, contacts on in {100 * pol['contact share']:.0f}%)"
    )
    learned_env = ProxemicEnv(scenario, autopilot=True, planner="learned")
    orca_env = ProxemicEnv(scenario, autopilot=True, planner="astar_orca")
    learned_us, orca_us = mean_step_us(learned_env), mean_step_us(orca_env)
    learned_env.close()
    orca_env.close()
    print(
        f"  {'env.step (autopilot: learned)':40s} {learned_us:8.1f} us  mean over {SOCIAL_STEPS} steps, "
        f"{learned_us / orca_us:4.2f}x astar_orca's {orca_us:.1f} us (same seeds, same run)"
    )
    reset_ms = med["env.reset"] / 1e3
    checks = {
        ">= 3000 steps/s (plain A*)": rate >= 3000,
        f">= {POLICY_TARGET} steps/s (policy)": pol_rate >= POLICY_TARGET,
        "<= 1.5x the physics model (plain A*)": med["env.step"] / with_people <= 1.5,
        "<= 2.0x the physics model (social, mean)": soc["mean"] / soc_people <= 2.0,
        "reset <= 1 ms": reset_ms <= 1.0,
        "<= 1.5x astar_orca (learned, mean)": learned_us / orca_us <= 1.5,
    }
    print("  targets: " + ", ".join(f"{k} {'met' if ok else 'MISSED'}" for k, ok in checks.items()))
    mu, steps = med["episode_metrics"], med["episode steps"]
    print(
        f"  {'episode_metrics (full set, one episode)':40s} {mu / 1e3:8.2f} ms  "
        f"{mu / steps:6.1f} us per recorded step ({steps:.0f} steps), "
        f"{100 * mu / steps / med['env.step']:4.1f}% of an env step"
    )
    ren = bench_render(env)
    step_wall, step_cpu = ren.pop("env.step")
    print()
    print(
        f"rendering 640x480, museum with {n} people, {TRIALS} trials x {FRAMES} frames, medians "
        f"(wall time; thread CPU time misses the GL driver's threads)"
    )
    for k, (w, c) in ren.items():
        print(f"  {k:40s} {w:8.2f} ms/frame wall  {w / step_wall:6.1f}x an env step   {c:7.2f} ms thread CPU")
    pad = " " * 25
    print(f"  {'env.step (the baseline)':40s} {step_wall:8.2f} ms wall{pad}{step_cpu:7.2f} ms thread CPU")
    env.close()
    return 0 if all(checks.values()) else 1


if __name__ == "__main__":
    sys.exit(main())
