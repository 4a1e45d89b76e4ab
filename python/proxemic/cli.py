"""The ``proxemic`` command line."""

from __future__ import annotations

import argparse
import math
import os
import sys
import time
from pathlib import Path

import numpy as np

from proxemic import scenarios
from proxemic.errors import ProxemicError

#: The social-map pictures of the demo: (scenario, time of day or None for the scene's start).
DEMO_SOCIAL_MAPS: tuple[tuple[str, str | None], ...] = (("sousa2022_fig16", None), ("calderita_exp1", None))


def cmd_demo(args: argparse.Namespace) -> int:
    """The main job: planners compared on seeded episodes, metrics tables, trajectory and social-map plots."""
    from proxemic.evaluation import EvalConfig, run_eval, summary_markdown
    from proxemic.social import SocialMap

    out = Path(args.out)
    planners = args.planner or ["astar", "social_astar"]
    written: list[Path] = []
    for scenario in args.scenario or ["museum", "care_center"]:
        cfg = EvalConfig(
            scenario=scenario,
            planners=planners,
            episodes=args.episodes,
            seed=args.seed,
            out=out / Path(scenario).stem,
            workers=args.workers,
        )
        t0 = time.perf_counter()
        rows = run_eval(cfg)
        print()
        print(
            f"## {scenario}: {', '.join(planners)}, {args.episodes} seeded episodes each "
            f"({time.perf_counter() - t0:.1f} s)"
        )
        print()
        print(summary_markdown(rows))
        written += [cfg.out / "summary.md", cfg.out / "metrics.png"]
        written += [cfg.out / f"trajectories_{p}.png" for p in planners]
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


def cmd_eval(args: argparse.Namespace) -> int:
    """Seeded comparison of planners: records, summary with confidence intervals, plots."""
    from proxemic.evaluation import EvalConfig, run_eval, summary_markdown

    cfg = EvalConfig(
        scenario=args.scenario,
        planners=args.planner or ["astar"],
        episodes=args.episodes,
        seed=args.seed,
        out=Path(args.out),
        workers=args.workers,
        backend=args.backend,
        ray_address=args.ray_address,
    )
    t0 = time.perf_counter()
    rows = run_eval(cfg)
    print()
    print(summary_markdown(rows))
    print()
    print(
        f"{len(cfg.tasks())} episodes in {time.perf_counter() - t0:.1f} s; wrote {cfg.out}/episodes.csv, "
        f"episodes.parquet, summary.md and plots"
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


def build_parser() -> argparse.ArgumentParser:
    """The argument parser of the ``proxemic`` command."""
    p = argparse.ArgumentParser(prog="proxemic", description="Evaluation gym for socially-aware robot navigation.")
    sub = p.add_subparsers(dest="command", required=True)
    d = sub.add_parser("demo", help="planners compared in the museum and the care center, with plots")
    d.add_argument("--scenario", action="append", help="scenario(s) to run (default: museum and care_center)")
    d.add_argument("--planner", action="append", help="planner(s) to compare (default: astar and social_astar)")
    d.add_argument("--episodes", type=int, default=10, help="seeded episodes per planner (default: 10)")
    d.add_argument("--seed", type=int, default=0, help="first seed (default: 0)")
    d.add_argument("--workers", type=int, default=os.cpu_count() or 1, help="processes (default: all cores)")
    d.add_argument("--out", default="out", help="output folder (default: out)")
    d.set_defaults(func=cmd_demo)
    e = sub.add_parser("eval", help="seeded comparison of planners with summaries and plots")
    e.add_argument("--scenario", default="museum", help="bundled scenario name or TOML path (default: museum)")
    e.add_argument("--planner", action="append", help="a built-in planner; repeat to compare (default: astar)")
    e.add_argument("--episodes", type=int, default=20, help="episodes per planner (default: 20)")
    e.add_argument("--seed", type=int, default=0, help="first seed; every planner runs the same seeds (default: 0)")
    e.add_argument("--out", default="out/eval", help="output folder (default: out/eval)")
    e.add_argument("--workers", type=int, default=os.cpu_count() or 1, help="processes (default: all cores)")
    e.add_argument("--backend", choices=["process", "ray"], default="process", help="where episodes run")
    e.add_argument("--ray-address", default=None, help="address of an existing Ray cluster (default: start one)")
    e.set_defaults(func=cmd_eval)
    r = sub.add_parser("reproduce", help="a paper's experiments: our metrics beside the published ones")
    r.add_argument("paper", choices=["daza2021", "sousa2022", "calderita"], help="which paper")
    r.add_argument("--episodes", type=int, default=5, help="seeded episodes per planner and scene (default: 5)")
    r.add_argument("--seed", type=int, default=0, help="first seed (default: 0)")
    r.add_argument("--out", default="out/reproduce", help="output folder; the paper's name is appended")
    r.set_defaults(func=cmd_reproduce)
    s = sub.add_parser("scenes", help="list the bundled scenarios")
    s.set_defaults(func=cmd_scenes)
    return p


def main(argv: list[str] | None = None) -> int:
    """Entry point of the ``proxemic`` command."""
    args = build_parser().parse_args(argv)
    if getattr(args, "episodes", 1) < 1:
        print("proxemic: error: --episodes must be at least 1", file=sys.stderr)
        return 2
    try:
        return int(args.func(args))
    except ProxemicError as e:
        print(f"proxemic: error: {e}", file=sys.stderr)
        return 2
    except OSError as e:
        print(f"proxemic: error: {e}", file=sys.stderr)
        return 2


if __name__ == "__main__":
    sys.exit(main())
