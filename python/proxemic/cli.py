"""The ``proxemic`` command line."""

from __future__ import annotations

import argparse
import os
import sys
import time
from pathlib import Path

import numpy as np

from proxemic import scenarios
from proxemic.errors import ProxemicError


def _summary_rows(records: list, planner: str) -> list[dict]:
    from proxemic.runner import EpisodeRecord

    recs: list[EpisodeRecord] = records
    rows = []
    for r in recs:
        m = r.metrics
        rows.append(
            {
                "seed": r.seed,
                "outcome": m["outcome"],
                "time to goal [s]": m["time_to_goal"],
                "path length [m]": m["path_length"],
                "min dist to people [m] (centre)": m["min_person_distance"],
                "min gap to people [m] (surface)": m["min_person_gap"],
                "steps": m["steps"],
            }
        )
    n = len(recs)
    succ = sum(r.metrics["success"] for r in recs)
    ttg = [r.metrics["time_to_goal"] for r in recs if r.metrics["time_to_goal"] is not None]
    rows.append(
        {
            "seed": f"all ({planner})",
            "outcome": f"{succ}/{n} success",
            "time to goal [s]": float(np.mean(ttg)) if ttg else None,
            "path length [m]": float(np.mean([r.metrics["path_length"] for r in recs])),
            "min dist to people [m] (centre)": float(np.min([_num(r.metrics["min_person_distance"]) for r in recs])),
            "min gap to people [m] (surface)": float(np.min([_num(r.metrics["min_person_gap"]) for r in recs])),
            "steps": int(np.sum([r.metrics["steps"] for r in recs])),
        }
    )
    return rows


def _num(v: float | None) -> float:
    return float("inf") if v is None else float(v)


def cmd_demo(args: argparse.Namespace) -> int:
    """Plain A* in the museum: seeded episodes, a metrics table and a trajectory plot."""
    from tqdm import tqdm

    from proxemic.env import ProxemicEnv
    from proxemic.runner import run_episode
    from proxemic.viz.plots import format_table, plot_episodes

    out = Path(args.out)
    out.mkdir(parents=True, exist_ok=True)
    env = ProxemicEnv(args.scenario, autopilot=True)
    records = []
    t0 = time.perf_counter()
    seeds = range(args.seed, args.seed + args.episodes)
    for seed in tqdm(seeds, desc=f"{env.scenario['scene']['name']} / astar", unit="episode"):
        records.append(run_episode(args.scenario, seed, env=env))
    wall = time.perf_counter() - t0
    steps = sum(r.metrics["steps"] for r in records)
    rows = _summary_rows(records, "astar")
    columns = list(rows[0].keys())
    table = format_table(rows, columns, floatfmt=".2f")
    print()
    print(
        f"Scenario {env.scenario['scene']['name']!r}, planner astar (plain A*), {len(records)} episodes, "
        f"{steps} control steps in {wall:.1f} s ({steps / wall:.0f} steps/s including recording)"
    )
    print()
    print(table)
    (out / "metrics.md").write_text(table + "\n")
    episodes = [
        {
            "label": f"seed {r.seed}",
            "robot": r.robot,
            "people": r.people,
            "path": r.path if i == 0 else None,
            "outcome": r.metrics["outcome"],
        }
        for i, r in enumerate(records)
    ]
    png = plot_episodes(
        env.scenario,
        episodes,
        out / "trajectories.png",
        title=f"{env.scenario['scene']['name']}: plain A*, {len(records)} seeded episodes",
    )
    env.close()
    print()
    print(f"wrote {out / 'metrics.md'} and {png}")
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
    d = sub.add_parser("demo", help="plain A* in the museum: metrics table and trajectory plot")
    d.add_argument("--scenario", default="museum", help="bundled scenario name or TOML path (default: museum)")
    d.add_argument("--episodes", type=int, default=8, help="number of seeded episodes (default: 8)")
    d.add_argument("--seed", type=int, default=0, help="first seed (default: 0)")
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
