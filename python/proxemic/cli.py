"""The ``proxemic`` command line."""

from __future__ import annotations

import argparse
import json
import math
import os
import sys
import textwrap
import time
from collections.abc import Sequence
from pathlib import Path
from typing import Any, NoReturn

import numpy as np

from proxemic import scenarios, splits
from proxemic.errors import ProxemicError
from proxemic.evaluation import BASELINE_PLANNERS, EvalResult
from proxemic.viz.topdown import FRAME_SIZE

#: The social-map pictures of the demo: (scenario, time of day or None for the scene's start).
DEMO_SOCIAL_MAPS: tuple[tuple[str, str | None], ...] = (("sousa2022_fig16", None), ("calderita_exp1", None))


#: The demo's planners: the non-social baselines (plain A* blind to people, plain A* with ORCA, plain
#: A* that stops for whoever is in its way), the social global planner alone, and proxemic's own social
#: planner (social A* with Daza 2021's mode switch: Social Momentum near people and ORCA among robots).
DEMO_PLANNERS = ("astar", "astar_orca", "astar_stop", "social_astar", "social")
#: The demo's first episode seed: the test split's first (``proxemic.splits.TEST_EPISODE_SEEDS``).
DEMO_FIRST_SEED = splits.TEST_EPISODE_SEEDS[0]


def seeds_split(seeds: Sequence[int]) -> str:
    """Which split of :mod:`proxemic.splits` the episode seeds belong to, in words."""
    from proxemic import splits

    if set(seeds) <= set(splits.TEST_EPISODE_SEEDS):
        return "the test split (no constant or scene was tuned on these seeds; proxemic.splits)"
    if set(seeds) <= set(splits.TUNING_EPISODE_SEEDS):
        return "the tuning split (constants and scenes were tuned on these seeds; proxemic.splits)"
    return "seeds of both the tuning and the test split (proxemic.splits)"


#: How the demo's headline figures are averaged and measured, beside the registry's definitions.
DEMO_FIGURE_NOTES: dict[str, str] = {
    "success": "rate over the episodes, 95% Wilson interval",
    "collision": "rate over the episodes, 95% Wilson interval",
    "time_to_goal": "mean over the episodes that reached the goal, 95% Student t interval",
    "path_length_ratio": "mean over the successful episodes (a collision or the time limit cuts the path short)",
    "psi_intimate": "a person's centre to the robot's centre, against the scene's Hall radii (bodies of 0.3 m "
    "and 0.22 m radius reach 0.45 m between centres only by overlapping)",
    "psi_personal": "a person's centre to the robot's centre, against the scene's Hall radii",
    "intimate_gap_time": "body edge to body edge, the reading of the claims",
    "intimate_gap_entries_robot_caused": "body gaps; the robot moving toward the person above 0.05 m/s, the "
    "rule of robot-at-fault contacts",
    "intimate_gap_entries_person_caused": "body gaps; the person came to a robot stopped or moving away",
    "personal_gap_time_robot_caused": "body gaps, seconds of visits the robot made (or joined by moving toward "
    "the person)",
    "personal_gap_time_person_caused": "body gaps, seconds of visits the person made to a robot stopped or moving away",
    "interaction_crossings": "mean per episode",
    "psi_objects_active": "the robot's centre inside the space",
    "snqi": "robot-sf's composite score (higher is better), normalised on the plain astar episodes",
}


def demo_legend(split: str, episodes: int) -> str:
    """What each headline figure of the demo means: its unit, how it is measured and averaged, the split."""
    from proxemic import _core
    from proxemic.evaluation import HEADLINE, METRICS

    registry = {m["key"]: m for m in _core.metric_registry()}
    lines = [textwrap.fill(f"What the figures mean: {episodes} episodes per planner, seeds of {split}.", 100)]
    for key in HEADLINE:
        info = METRICS[key]
        definition = str(registry[key]["definition"]).split(". ")[0].rstrip(".") if key in registry else ""
        unit = f" ({info.unit})" if info.unit else ""
        text = "; ".join(x for x in (definition, DEMO_FIGURE_NOTES.get(key, "")) if x)
        lines.append(textwrap.fill(f"- {info.label}{unit}: {text}.", 100, subsequent_indent="  "))
    lines.append(
        textwrap.fill(
            'A verdict ("social vs astar") compares the means over the seeds where both planners reached the '
            "goal, with a 95% paired bootstrap interval; personal-zone time there is the share of instants above. "
            "These few episodes illustrate; the claims are asserted by tests/test_social_vs_astar.py (make test) "
            "on 20 test-split seeds per scene and 50 generated scenes, personal-zone time in seconds.",
            100,
        )
    )
    return "\n".join(lines)


def _print_results(result: EvalResult, note: str = "") -> None:
    """An evaluation's results in the terminal: the headline table, `note` if any, SNQI, verdicts."""
    from proxemic.evaluation import headline_text

    print(headline_text(result.summary))
    if note:
        print()
        print(textwrap.fill(note, 100))
    print()
    print(textwrap.fill(result.snqi_line, 100))
    for v in result.verdicts:
        print()
        print(v)


def cmd_demo(args: argparse.Namespace) -> int:
    """The main job: planners compared on test-split seeds, metrics tables, trajectory and social-map plots."""
    from proxemic.evaluation import EvalConfig, run_evaluation
    from proxemic.social import SocialMap

    out = Path(args.out)
    planners = args.planner or list(DEMO_PLANNERS)
    seeds = range(args.seed, args.seed + args.episodes)
    split = seeds_split(seeds)
    written: list[Path] = []
    for scenario in args.scenario or ["museum", "care_center"]:
        scene_out = out / Path(scenario).stem
        cfg = EvalConfig(
            scenario=scenario,
            planners=planners,
            episodes=args.episodes,
            seed=args.seed,
            out=scene_out,
            workers=args.workers,
            keep_trajectories=args.episodes,  # every episode reported is drawn
        )
        t0 = time.perf_counter()
        result = run_evaluation(cfg)
        print()
        print(
            f"## {scenario}: {', '.join(planners)}, {args.episodes} episodes each, seeds {seeds[0]}-{seeds[-1]} "
            f"({time.perf_counter() - t0:.1f} s; all metrics in {scene_out}/summary.md)"
        )
        print()
        _print_results(result)
        print()
        print(
            textwrap.fill(
                f"Drawn: every episode (seeds {seeds[0]}-{seeds[-1]}) of each planner in trajectories_<planner>.png; "
                f"seed {seeds[0]} of every planner in trajectories_social_map.png.",
                100,
            )
        )
        written += [scene_out / "summary.md", scene_out / "metrics.png"]
        written += [scene_out / f"trajectories_{p}.png" for p in planners] + [scene_out / "trajectories_social_map.png"]
    print()
    print(demo_legend(split, args.episodes))
    print()
    print("## social maps: plain A* vs social A* paths")
    print()
    for scenario, tod in DEMO_SOCIAL_MAPS:
        sm = SocialMap(scenario, time_of_day=tod)
        plain, social = sm.plan(social=False), sm.plan(social=True)
        png = sm.plot(out / f"social_map_{scenario}.png", paths={"plain A*": plain, "social A*": social})
        length = lambda p: float(np.sum(np.linalg.norm(np.diff(p, axis=0), axis=1))) if p is not None else math.nan  # noqa: E731
        crosses = bool(plain is not None and np.isinf(sm.factor_along(plain)).any())
        print(
            f"- {scenario}: {sm.summary()['groups']} groups, plain A* {length(plain):.1f} m"
            f"{' (crosses an intimate zone)' if crosses else ''}, social A* {length(social):.1f} m"
        )
        written.append(png)
    print()
    print("wrote:")
    for w in written:
        print(f"  {w}")
    return 0


def _fresh_out(parent: Path) -> Path:
    """A new folder under ``parent`` named for the date and time (``-2``, ... if taken): a run's default output."""
    stamp = time.strftime("%Y%m%d-%H%M%S")
    out, k = parent / stamp, 1
    while out.exists():
        k += 1
        out = parent / f"{stamp}-{k}"
    return out


def _clear_old_videos(out: Path) -> None:
    """Removes the videos an earlier run wrote into ``out/videos`` (``<planner>_seed<N>.mp4``)."""
    for old in (out / "videos").glob("*_seed*.mp4"):
        old.unlink()


def _eval_suite(args: argparse.Namespace) -> int:
    """``eval --suite francis2023``: every archetype with every planner, a table per archetype."""
    from proxemic import francis2023

    if args.policy or args.video:
        print("proxemic: error: --suite runs built-in planners only (no --policy, no --video)", file=sys.stderr)
        return 2
    if args.scenario is not None:
        print(
            f"proxemic: error: --scenario: a --suite run makes its own scenes (got --scenario {args.scenario} with "
            f"--suite {args.suite}; drop one, or pick archetypes with --archetype)",
            file=sys.stderr,
        )
        return 2
    t0 = time.perf_counter()
    result = francis2023.run_suite(
        args.planner or ["astar"],
        args.episodes,
        seed=args.seed,
        out=Path(args.out),
        workers=args.workers,
        max_time=args.max_time,
        archetypes=args.archetype,
        drive=args.drive or "holonomic",
    )
    print()
    print(francis2023.headline_text(result.summary))
    print()
    episodes = sum(1 for r in result.records if r.get("robot", 0) == 0)
    print(
        f"{episodes} episodes in {time.perf_counter() - t0:.1f} s; wrote {args.out}/episodes.csv (with an archetype "
        "column), episodes.parquet, archetypes.csv (every metric per archetype) and summary.md"
    )
    return 0


def _policy_refs(args: argparse.Namespace) -> list[Any] | None:
    """The ``--policy`` of `args` as a labelled :class:`proxemic.policy.PolicyRef` list (empty without one).

    None (after printing the error) for a ``--policy-name`` without ``--policy``.
    """
    from proxemic.policy import PolicyRef

    if args.policy:
        module = args.policy.partition(":")[0]
        stem = Path(module).stem if module.endswith(".py") else module.rpartition(".")[2]
        name = args.policy_name or stem
        return [PolicyRef(name.rpartition("/")[2], args.policy, os.getcwd())]
    if args.policy_name:
        print("proxemic: error: --policy-name labels a --policy; no --policy given", file=sys.stderr)
        return None
    return []


def _eval_crowdnav(args: argparse.Namespace) -> int:
    """``eval --suite crowdnav``: the four settings of CrowdNav's protocol, both robots, beside CrowdNav's own run.

    Every built-in planner by default; ``--planner`` picks some, ``--policy`` adds a user's policy.
    """
    from proxemic import crowdnav

    if args.video or args.scenario is not None or args.archetype or args.max_time is not None:
        print(
            "proxemic: error: --suite crowdnav runs its own scenes and episodes (CrowdNav's 25 s): "
            "no --video, --scenario, --archetype or --max-time",
            file=sys.stderr,
        )
        return 2
    policies = _policy_refs(args)
    if policies is None:
        return 2
    for planner in args.planner or []:
        if planner not in crowdnav.PLANNERS:
            print(
                f"proxemic: error: --planner {planner!r}: not a built-in planner of the CrowdNav protocol "
                f"(one of {', '.join(crowdnav.PLANNERS)})",
                file=sys.stderr,
            )
            return 2
    t0 = time.perf_counter()
    drives = (args.drive,) if args.drive else crowdnav.DRIVES
    rows = crowdnav.run_suite(args.planner, args.episodes, seed=args.seed, policies=policies, drives=drives)
    print(crowdnav.table_text(rows))
    print()
    print(f"{len(rows) * args.episodes} episodes in {time.perf_counter() - t0:.1f} s")
    return 0


def cmd_eval(args: argparse.Namespace) -> int:
    """Seeded comparison of planners and user policies: records, summary with confidence intervals, plots."""
    from proxemic.evaluation import EvalConfig, policy_robot_note, robots_note, run_evaluation

    crowd = args.suite == "crowdnav"
    if args.episodes is None:
        args.episodes = 500 if crowd else 20
    if args.seed is None:
        args.seed = 10_000 if crowd else 0
    if crowd:
        return _eval_crowdnav(args)
    args.out = str(_fresh_out(Path("out/eval")) if args.out is None else Path(args.out))
    _clear_old_videos(Path(args.out))
    if args.suite:
        return _eval_suite(args)
    if args.max_time is not None:
        print("proxemic: error: --max-time applies to a --suite run", file=sys.stderr)
        return 2
    if args.archetype:
        print(
            f"proxemic: error: --archetype applies to a --suite run (got --archetype {' '.join(args.archetype)} "
            "without --suite; add --suite francis2023, or use --scenario francis2023/<archetype>)",
            file=sys.stderr,
        )
        return 2
    policies = _policy_refs(args)
    if policies is None:
        return 2
    cfg = EvalConfig(
        scenario=args.scenario or "museum",
        planners=args.planner or ([] if policies else list(BASELINE_PLANNERS)),
        episodes=args.episodes,
        seed=args.seed,
        out=Path(args.out),
        workers=args.workers,
        backend=args.backend,
        ray_address=args.ray_address,
        policies=policies,
        drive=args.drive,
    )
    t0 = time.perf_counter()
    result = run_evaluation(cfg)
    print()
    _print_results(result, robots_note(result.summary) or policy_robot_note(cfg))
    print()
    print(
        f"{len(cfg.tasks())} episodes in {time.perf_counter() - t0:.1f} s; wrote {cfg.out}/episodes.csv, "
        f"episodes.parquet, summary.md (all metrics) and plots"
    )
    if args.video:
        from proxemic.viz.video import record_episode

        # The same (planner, seed) episodes again, deterministic: the videos show what was measured
        # (the built-in planners' episodes; a user policy is not recorded).
        for planner in cfg.planners:
            for seed in range(cfg.seed, cfg.seed + min(args.video, cfg.episodes)):
                mp4 = Path(args.out) / "videos" / f"{planner}_seed{seed}.mp4"
                record_episode(
                    cfg.scenario,
                    planner,
                    seed,
                    mp4,
                    view=args.view,
                    overlays=args.overlay or ("path",),
                    progress=True,
                    drive=cfg.drive,
                )
                print(f"wrote {mp4}")
    return 0


def cmd_video(args: argparse.Namespace) -> int:
    """Records one seeded episode as an mp4."""
    from proxemic.viz.video import record_episode

    metrics: dict[str, Any] = {}
    out = record_episode(
        args.scenario,
        args.planner,
        args.seed,
        args.out,
        view=args.view,
        fps=args.fps,
        max_steps=args.max_steps,
        width=args.width,
        height=args.height,
        overlays=args.overlay or ("path",),
        progress=True,
        metrics=metrics,
        drive=args.drive,
        field="--out",
        start_step=args.start_step,
    )
    outcome = metrics.get("outcome", "running")
    steps, duration = metrics.get("steps"), metrics.get("duration")
    if outcome == "running":
        ended = f"stopped by --max-steps after {steps} steps ({duration:.1f} s), before the episode ended"
    else:
        ended = f"outcome: {outcome} after {steps} steps ({duration:.1f} s)"
    print(f"wrote {out}; {ended}")
    return 0


def _add_video_view_args(p: argparse.ArgumentParser) -> None:
    from proxemic.viz.topdown import OVERLAYS
    from proxemic.viz.video import VIEWS

    p.add_argument("--view", choices=VIEWS, default="topdown", help="camera of the video (default: topdown)")
    p.add_argument(
        "--overlay",
        action="append",
        choices=OVERLAYS,
        help="top-down overlay; repeat for several (default: path)",
    )


def _parse_range(text: str) -> tuple[str, tuple[float, float]]:
    """``name=low:high`` to (name, (low, high))."""
    name, sep, rng = text.partition("=")
    lo, sep2, hi = rng.partition(":")
    try:
        if not (sep and sep2):
            raise ValueError
        return name.strip(), (float(lo), float(hi))
    except ValueError:
        raise argparse.ArgumentTypeError(f"expected NAME=LOW:HIGH (e.g. repulsion_gain=0:2), got {text!r}") from None


def _parse_point(text: str) -> tuple[float, float]:
    """``x,y`` to a point."""
    try:
        x, y = (float(v) for v in text.split(","))
    except ValueError:
        raise argparse.ArgumentTypeError(f"expected a point X,Y in metres (e.g. 14,7.8), got {text!r}") from None
    return x, y


def _parse_weights(text: str) -> tuple[float, float, float, float]:
    """``a,b,c,d`` to four floats."""
    try:
        a, b, c, d = (float(x) for x in text.split(","))
    except ValueError:
        raise argparse.ArgumentTypeError(f"expected four numbers a,b,c,d (e.g. 1,1,1,-1), got {text!r}") from None
    return a, b, c, d


def cmd_tune(args: argparse.Namespace) -> int:
    """Calderita's gain search (§5.4): the controller gains minimising G over seeded episodes."""
    from proxemic.tuning import DEFAULT_RANGES, DEFAULT_TARGETS, CostWeights, TuneConfig, curve_text, run_tune

    a, b, c, d = args.weights
    scenes = args.scenario or list(DEFAULT_TARGETS)
    goals = args.target or [None]
    cfg = TuneConfig(
        targets=[(s, g) for s in scenes for g in goals],
        planner=args.planner,
        trials=args.trials,
        episodes=args.episodes,
        seed=args.seed,
        samples=args.samples,
        ranges=dict(args.gain) if args.gain else dict(DEFAULT_RANGES),
        weights=CostWeights(a, b, c, d, failure_penalty=args.failure_penalty),
        out=Path(args.out),
        workers=args.workers,
        backend=args.backend,
        ray_address=args.ray_address,
    )
    t0 = time.perf_counter()
    result = run_tune(cfg)
    best = result["best"]
    print()
    where = ", ".join(t["scenario"] + (f" to {tuple(t['goal'])}" if t["goal"] else "") for t in result["targets"])
    print(f"## G curve ({where}; {cfg.planner}; seeds {result['seeds']})")
    print()
    print(curve_text(result))
    print()
    gains = ", ".join(f"{k} = {best[k]:.4g}" for k in result["ranges"])
    print(f"best gains (trial {best['trial']}): {gains}; G = {best['G']:.3f} (success {best['success']:.2f})")
    print(
        f"{len(result['trials'])} gain points in {time.perf_counter() - t0:.1f} s; wrote {cfg.out}/trials.csv, "
        "episodes.csv, episodes.parquet, tune.json and tune.png"
    )
    return 0


def cmd_reproduce(args: argparse.Namespace) -> int:
    """Runs a paper's experiments and prints our metrics beside the published ones."""
    from proxemic.reproduce import reproduce

    out = Path(args.out) / args.paper
    t0 = time.perf_counter()
    print(reproduce(args.paper, out, episodes=args.episodes, seed=args.seed))
    print(f"{time.perf_counter() - t0:.1f} s; wrote {out}/report.md, episodes.csv and the figures")
    return 0


def cmd_schema(args: argparse.Namespace) -> int:
    """Prints the JSON Schema of scenario files (emitted by the core from its scenario types)."""
    from proxemic.reference import scenario_schema

    print(json.dumps(scenario_schema(), indent=2, ensure_ascii=False))
    return 0


def cmd_scenes(args: argparse.Namespace) -> int:
    """Lists the bundled scenarios and their environment ids."""
    from proxemic.registration import ENV_IDS

    ids = {v: k for k, v in ENV_IDS.items()}
    for name in scenarios.available():
        _core, desc = scenarios.load(name)
        scene = desc["scene"]
        print(
            f"{ids.get(name, '-'):28s} {name:16s} {len(desc['persons']):3d} people  "
            f"{len(desc['robots'])} robot(s)  {scene['bounds'][2] - scene['bounds'][0]:.0f} x "
            f"{scene['bounds'][3] - scene['bounds'][1]:.0f} m"
        )
    return 0


def cmd_generate(args: argparse.Namespace) -> int:
    """Writes a generated scene's scenario file."""
    params: dict[str, float | str] = {}
    for key in scenarios.GENERATE_PARAMS:
        value = getattr(args, key, None)
        if value is not None:
            params[key] = value
    text = scenarios.generate_toml(args.seed, **params)
    out = Path(args.out)
    out.parent.mkdir(parents=True, exist_ok=True)
    out.write_text(text)
    name = scenarios.generated_name(args.seed, **params)
    print(f"wrote {out} ({name}; load it with gym.make('proxemic/Generated-v5', scenario={name!r}) or by path)")
    return 0


def cmd_crowd_card(args: argparse.Namespace) -> int:
    """Writes the crowd card (the pedestrian model against each recording)."""
    from proxemic import crowdcard

    window = tuple(args.window) if args.window else None
    cards = crowdcard.write_cards(args.recordings, args.out, window=window)
    for c in cards:
        cl = c["closed_loop"]
        print(
            f"{c['recording']}: closed-loop ADE {cl['proxemic']['ade_m']:.3f} m "
            f"(straight line {cl['straight_line']['ade_m']:.3f}), open-loop ADE "
            f"{c['open_loop']['proxemic']['ade_m']:.3f} m (constant velocity "
            f"{c['open_loop']['constant_velocity']['ade_m']:.3f})"
        )
    if args.docs:
        crowdcard.write_docs(cards, args.out, args.docs)
        print(f"updated {args.docs}")
    print(f"wrote {args.out}")
    return 0


def cmd_crowd_fit(args: argparse.Namespace) -> int:
    """Fits the pedestrian model's interaction parameters on recordings (the calibration)."""
    from proxemic import crowdcard

    best, history = crowdcard.calibrate(args.recordings, rounds=args.rounds)
    fitted = min(history, key=lambda h: float(h["objective"]))
    print(json.dumps({"fitted": best, "evaluations": len(history), "at_fit": fitted}, indent=2))
    if args.out:
        Path(args.out).write_text(json.dumps({"fitted": best, "history": history}, indent=2) + "\n")
    return 0


class _Parser(argparse.ArgumentParser):
    """An argument parser whose errors are one line on stderr (exit code 2), naming the argument."""

    def error(self, message: str) -> NoReturn:
        """Prints ``<prog>: error: <message> (see <prog> --help)`` and exits with code 2."""
        self.exit(2, f"{self.prog}: error: {message} (see '{self.prog} --help')\n")


def _positive_int(text: str) -> int:
    """An argparse type: an integer of at least 1."""
    try:
        value = int(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"expected an integer of at least 1, got {text!r}") from None
    if value < 1:
        raise argparse.ArgumentTypeError(f"expected an integer of at least 1, got {value}")
    return value


def _finite_float(text: str) -> float:
    """An argparse type: a finite number."""
    try:
        value = float(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"expected a finite number, got {text!r}") from None
    if not math.isfinite(value):
        raise argparse.ArgumentTypeError(f"expected a finite number, got {text!r}")
    return value


def _planner_help(what: str) -> str:
    """`what` followed by the built-in planners' names (``proxemic.PLANNERS``)."""
    from proxemic import PLANNERS

    return f"{what}; one of: {', '.join(PLANNERS)}"


#: The scenario argument's help: names, env ids and paths are all accepted.
SCENARIO_HELP = "bundled scenario name, env id (e.g. proxemic/Museum-v5; see `proxemic scenes`) or TOML path"


def build_parser() -> argparse.ArgumentParser:
    """The argument parser of the ``proxemic`` command."""
    from proxemic.tuning import DEFAULT_RANGES

    p = _Parser(prog="proxemic", description="Evaluation gym for socially-aware robot navigation.")
    sub = p.add_subparsers(dest="command", required=True)
    d = sub.add_parser(
        "demo", help="planners compared in the museum and the care center on test-split seeds, with plots"
    )
    d.add_argument(
        "--scenario", action="append", help=f"scenario(s) to run: {SCENARIO_HELP} (default: museum and care_center)"
    )
    d.add_argument(
        "--planner",
        action="append",
        help=_planner_help("planner(s) to compare (default: " + ", ".join(DEMO_PLANNERS) + ")"),
    )
    d.add_argument("--episodes", type=_positive_int, default=10, help="seeded episodes per planner (default: 10)")
    d.add_argument(
        "--seed",
        type=int,
        default=DEMO_FIRST_SEED,
        help=f"first seed (default: {DEMO_FIRST_SEED}, the first of the test split's episode seeds; proxemic.splits)",
    )
    d.add_argument("--workers", type=_positive_int, default=os.cpu_count() or 1, help="processes (default: all cores)")
    d.add_argument("--out", default="out", help="output folder (default: out)")
    d.set_defaults(func=cmd_demo)
    e = sub.add_parser("eval", help="seeded comparison of planners and your policy with summaries and plots")
    e.add_argument("--scenario", default=None, help=f"{SCENARIO_HELP} (default: museum; not with --suite)")
    e.add_argument(
        "--suite",
        choices=["francis2023", "crowdnav"],
        default=None,
        help="run a scenario suite instead of one scenario: francis2023 (every archetype of Francis et al. 2023, "
        "episode k on the scene of seed k; a table per archetype); crowdnav (CrowdNav's circle and square "
        "crossing, four settings with its holonomic and its unicycle robot, every built-in planner and a "
        "--policy, beside CrowdNav's own measured figures and the literature's)",
    )
    e.add_argument(
        "--archetype", action="append", default=None, help="with --suite: run only this archetype (repeat for more)"
    )
    e.add_argument(
        "--max-time",
        type=float,
        default=None,
        help="with --suite: episode length in seconds, in [5, 600] (default: each archetype's own)",
    )
    e.add_argument(
        "--drive",
        choices=scenarios.DRIVES,
        default=None,
        help="every robot's drive: holonomic (Pepper's base) or differential (unicycle, no sideways motion); "
        "default: the scenario's own; with --suite crowdnav: both",
    )
    e.add_argument(
        "--planner",
        action="append",
        help=_planner_help(
            "a built-in planner; repeat to compare (default without --policy: the non-social baselines "
            + ", ".join(BASELINE_PLANNERS)
            + "; with --suite crowdnav: every planner)"
        ),
    )
    e.add_argument(
        "--policy",
        default=None,
        metavar="MODULE:FACTORY",
        help="your policy: the import path of a factory make(observation_space, action_space) returning a "
        "callable obs -> action or an object with predict(obs, deterministic=True) (e.g. examples.my_policy:make)",
    )
    e.add_argument("--policy-name", default=None, help="the policy's label in tables and plots (default: its module)")
    e.add_argument(
        "--episodes",
        type=_positive_int,
        default=None,
        help="episodes per planner (default: 20; with --suite crowdnav: 500 per setting, CrowdNav's test size)",
    )
    e.add_argument(
        "--seed",
        type=int,
        default=None,
        help="first seed; every planner runs the same seeds (default: 0; with --suite crowdnav: 10000, the test "
        "split's first scene seed)",
    )
    e.add_argument(
        "--out",
        default=None,
        help="output folder (default: a new out/eval/<date>-<time>/ per run, so no run overwrites another; "
        "a given folder's files are replaced and its old videos removed)",
    )
    e.add_argument("--workers", type=_positive_int, default=os.cpu_count() or 1, help="processes (default: all cores)")
    e.add_argument("--backend", choices=["process", "ray"], default="process", help="where episodes run")
    e.add_argument("--ray-address", default=None, help="address of an existing Ray cluster (default: start one)")
    e.add_argument(
        "--video", type=int, default=0, metavar="N", help="record the first N episodes per planner into OUT/videos/"
    )
    _add_video_view_args(e)
    e.set_defaults(func=cmd_eval)
    v = sub.add_parser("video", help="record one seeded episode as an mp4")
    v.add_argument("--scenario", default="museum", help=f"{SCENARIO_HELP} (default: museum)")
    v.add_argument(
        "--planner", default=None, help=_planner_help("the robot's built-in planner (default: the scenario's)")
    )
    v.add_argument("--seed", type=int, default=0, help="episode seed (default: 0)")
    v.add_argument(
        "--drive",
        choices=scenarios.DRIVES,
        default=None,
        help="every robot's drive: holonomic or differential (default: the scenario's own)",
    )
    v.add_argument("--out", default="out/episode.mp4", help="output file (default: out/episode.mp4)")
    v.add_argument("--fps", type=float, default=None, help="frames per second (default: the control rate)")
    v.add_argument("--max-steps", type=int, default=None, help="stop after this many steps (default: episode end)")
    v.add_argument(
        "--start-step",
        type=int,
        default=0,
        help="first step recorded: a clip from this step on, of the same episode (default: 0, the reset)",
    )
    v.add_argument("--width", type=int, default=FRAME_SIZE[0], help=f"frame width, even (default: {FRAME_SIZE[0]})")
    v.add_argument("--height", type=int, default=FRAME_SIZE[1], help=f"frame height, even (default: {FRAME_SIZE[1]})")
    _add_video_view_args(v)
    v.set_defaults(func=cmd_video)
    t = sub.add_parser("tune", help="Calderita's gain search: controller gains minimising G = aH + bD + cQ + dP")
    t.add_argument(
        "--scenario",
        action="append",
        help=f"target scene(s): {SCENARIO_HELP}; repeat for several (default: calderita_exp1 and _exp2)",
    )
    t.add_argument(
        "--target",
        action="append",
        type=_parse_point,
        metavar="X,Y",
        help="a goal for the robot in every scene, repeat for several (default: each scene's own goal)",
    )
    t.add_argument(
        "--planner",
        default="calderita",
        help="the planner whose band gains are tuned: calderita (default, Calderita's system) or eband",
    )
    t.add_argument("--trials", type=_positive_int, default=20, help="gain points evaluated at most (default: 20)")
    t.add_argument(
        "--episodes", type=_positive_int, default=3, help="seeded episodes per target and gain point (default: 3)"
    )
    t.add_argument("--seed", type=int, default=0, help="first episode seed and the search's seed (default: 0)")
    t.add_argument(
        "--samples", type=_positive_int, default=4, help="values of one gain tried per search step (default: 4)"
    )
    t.add_argument(
        "--gain",
        action="append",
        type=_parse_range,
        metavar="NAME=LOW:HIGH",
        help="a gain to tune and its range; repeat (default: "
        + " ".join(f"{n}={lo:g}:{hi:g}" for n, (lo, hi) in DEFAULT_RANGES.items())
        + ")",
    )
    t.add_argument(
        "--weights",
        type=_parse_weights,
        default=(1.0, 1.0, 1.0, -1.0),
        metavar="A,B,C,D",
        help="G's weights on heading change (/rad), distance (/m), time (/s), mean distance to people (/m) "
        "(default: 1,1,1,-1)",
    )
    t.add_argument(
        "--failure-penalty", type=_finite_float, default=100.0, help="added to G per failed episode (default: 100)"
    )
    t.add_argument("--out", default="out/tune", help="output folder (default: out/tune)")
    t.add_argument("--workers", type=_positive_int, default=os.cpu_count() or 1, help="processes (default: all cores)")
    t.add_argument("--backend", choices=["process", "ray"], default="process", help="where episodes run")
    t.add_argument("--ray-address", default=None, help="address of an existing Ray cluster (default: start one)")
    t.set_defaults(func=cmd_tune)
    r = sub.add_parser("reproduce", help="a paper's experiments: our metrics beside the published ones")
    from proxemic.reproduce import PAPERS

    r.add_argument("paper", choices=list(PAPERS), help="which paper (its own planner runs, with plain A* and ours)")
    r.add_argument(
        "--episodes", type=_positive_int, default=10, help="seeded episodes per planner and scene (default: 10)"
    )
    r.add_argument("--seed", type=int, default=0, help="first seed (default: 0)")
    r.add_argument("--out", default="out/reproduce", help="output folder; the paper's name is appended")
    r.set_defaults(func=cmd_reproduce)
    g = sub.add_parser("generate", help="write a generated scene (seeded floor plan, furniture, people, robots)")
    g.add_argument("--seed", type=int, required=True, help="the scene's seed (a non-negative integer)")
    g.add_argument("--robots", type=_positive_int, help="robots (default 1, at most 8)")
    g.add_argument("--encounters", type=int, help="conversation groups on each robot's way (0 or 1; default 0)")
    g.add_argument(
        "--reaction",
        choices=["ignore", "aware", "yield", "curious", "cautious"],
        help="the people's reaction to robots (default aware; docs/people.md)",
    )
    g.add_argument(
        "--drive",
        choices=["holonomic", "differential"],
        help="every robot's drive (default holonomic; docs/scenarios.md)",
    )
    g.add_argument("--objects-per-room", dest="objects_per_room", type=int, help="objects per room (default 3)")
    for key, unit in [
        ("width", "m"),
        ("height", "m"),
        ("corridor_width", "m"),
        ("door_width", "m"),
        ("density", "people per 100 m^2"),
        ("group_share", "share"),
        ("walker_share", "share"),
        ("seated_share", "share"),
        ("max_time", "s"),
    ]:
        g.add_argument(f"--{key.replace('_', '-')}", dest=key, type=_finite_float, help=f"{key} ({unit})")
    g.add_argument("--out", default="scene.toml", help="the scenario file to write (default: scene.toml)")
    g.set_defaults(func=cmd_generate)
    cc = sub.add_parser("crowd-card", help="the pedestrian model against recorded crowds (card.md, card.json, plots)")
    cc.add_argument("recordings", nargs="+", help="replay CSV files t,id,x,y (e.g. ETH/UCY scenes)")
    cc.add_argument("--out", required=True, help="output folder (one sub-folder per recording if several)")
    cc.add_argument(
        "--window",
        nargs=2,
        type=_finite_float,
        metavar=("T0", "T1"),
        help="keep only the tracks lying wholly in this time window (s, the recording's clock)",
    )
    cc.add_argument("--docs", help="also put the cards (tables and plots) into this docs page, between its markers")
    cc.set_defaults(func=cmd_crowd_card)
    cf = sub.add_parser("crowd-fit", help="fit the pedestrian model's interaction parameters on recordings")
    cf.add_argument("recordings", nargs="+", help="replay CSV files t,id,x,y (the training recordings)")
    cf.add_argument("--rounds", type=_positive_int, default=2, help="coordinate-descent passes (default 2)")
    cf.add_argument("--out", help="write the fit and every evaluation to this JSON file")
    cf.set_defaults(func=cmd_crowd_fit)
    s = sub.add_parser("scenes", help="list the bundled scenarios")
    s.set_defaults(func=cmd_scenes)
    sc = sub.add_parser("schema", help="print the JSON Schema of scenario files (for editor completion)")
    sc.set_defaults(func=cmd_schema)
    return p


def main(argv: list[str] | None = None) -> int:
    """Entry point of the ``proxemic`` command."""
    args = build_parser().parse_args(argv)
    if (getattr(args, "episodes", 1) or 1) < 1:
        print("proxemic: error: --episodes must be at least 1", file=sys.stderr)
        return 2
    if getattr(args, "video", 0) < 0:
        print("proxemic: error: --video must be at least 0", file=sys.stderr)
        return 2
    try:
        return int(args.func(args))
    except ProxemicError as e:
        print(f"proxemic: error: {e}", file=sys.stderr)
        return 2
    except (OSError, ImportError) as e:
        print(f"proxemic: error: {e}", file=sys.stderr)
        return 2
    except KeyboardInterrupt:
        print("proxemic: interrupted; the episodes that finished are kept in the output folder", file=sys.stderr)
        return 130


if __name__ == "__main__":
    sys.exit(main())
