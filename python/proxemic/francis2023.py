"""The scenario suite of Francis et al. 2023: its archetypes as seeded scenes, and the suite evaluation.

Francis et al. 2023, "Principles and guidelines for evaluating social robot navigation algorithms".

Each archetype (the 25 panels of the paper's Fig. 7: frontal approach, pedestrian obstruction,
overtaking both ways, down path, intersections (crossings at 90 and 45 degrees, waiting and
proceeding), blind corner, narrow hallway and doorway, entering and exiting a room and an elevator,
joining and leaving a group, following, leading and accompanying a person, a dense crowd, parallel
and perpendicular traffic, circular crossing, robot crowding) is a scene family of the core's
generator: its widths, lengths, speeds, angles and offsets are drawn from a
seed within ranges written beside the code (``rust/proxemic-core/src/scenario/generate/francis2023``).

A scene is named ``francis2023/<archetype>`` (seed 0) or ``francis2023/<archetype>?seed=N`` (and
``&max_time=T`` to shorten or lengthen the episode, seconds in [5, 600], and ``&drive=differential``
for a differential-drive robot, same scene otherwise); the name works wherever a
scenario name does (``gym.make("proxemic/Generated-v5", scenario=...)``, ``proxemic.parallel_env``,
``proxemic eval --scenario``), and ``gym.make("proxemic/Francis2023-v7", archetype=..., scene_seed=N)``
is the same env. The suite (:func:`run_suite`, ``proxemic eval --suite francis2023``) runs episode
``k`` of every archetype on the scene of seed ``seed + k``, with episode seed ``seed + k``: the
scene's parameters vary from episode to episode, and every planner meets the same scenes.
"""

from __future__ import annotations

import contextlib
import math
from collections.abc import Mapping, Sequence
from dataclasses import dataclass
from pathlib import Path
from typing import Any

from proxemic import _core, evaluation, markdown, reference, scenarios
from proxemic.errors import input_error, typed_repr
from proxemic.evaluation import episodes as eval_episodes
from proxemic.evaluation import summary as eval_summary

#: Prefix of a Francis et al. 2023 scene's name.
PREFIX = "francis2023/"

#: The archetypes, in the order the suite runs them.
ARCHETYPES: tuple[str, ...] = tuple(_core.FRANCIS2023_ARCHETYPES)

#: The suite's name for ``proxemic eval --suite``.
SUITE = "francis2023"


def scenario_name(archetype: str, seed: int = 0, max_time: float | None = None, drive: str = "holonomic") -> str:
    """The scene name ``francis2023/<archetype>[?seed=N&max_time=T&drive=D]``.

    `drive` is every robot's drive (``holonomic``, the default and left out of the name, or
    ``differential``; the core checks the name).

    Raises:
        UnknownNameError: `archetype` is not one of :data:`ARCHETYPES` (with a suggestion).
        InputError: `archetype` not a string, `seed` not a non-negative integer, `max_time` not a
            number, `drive` not a string.
    """
    from proxemic.errors import UnknownNameError

    if not isinstance(archetype, str):
        raise input_error("archetype", f"one of {list(ARCHETYPES)}", typed_repr(archetype))
    if archetype not in ARCHETYPES:
        raise UnknownNameError(
            f"unknown archetype {archetype!r}{scenarios.suggest(archetype, ARCHETYPES)}: expected one of "
            f"{', '.join(ARCHETYPES)}",
            field="archetype",
            expected=f"one of {list(ARCHETYPES)}",
            found=archetype,
        )
    if isinstance(seed, bool) or not isinstance(seed, int) or seed < 0:
        raise input_error("seed", "a non-negative integer", seed)
    pairs = [f"seed={seed}"] if seed else []
    if max_time is not None:
        if isinstance(max_time, bool) or not isinstance(max_time, (int, float)):
            raise input_error("max_time", "a number of seconds", max_time)
        pairs.append(f"max_time={float(max_time):g}")
    if not isinstance(drive, str):
        raise input_error("drive", "a drive name (holonomic or differential)", typed_repr(drive))
    if drive != "holonomic":
        pairs.append(f"drive={drive}")
    return f"{PREFIX}{archetype}" + ("?" + "&".join(pairs) if pairs else "")


def make_env(
    archetype: str = "frontal_approach",
    scene_seed: int = 0,
    max_time: float | None = None,
    drive: str = "holonomic",
    **kwargs: Any,
) -> Any:
    """The gymnasium env of one archetype's scene (``gym.make("proxemic/Francis2023-v7", archetype=...)``).

    Args:
        archetype: One of :data:`ARCHETYPES`.
        scene_seed: The scene's seed (its drawn parameters); the episode seed is ``reset(seed=...)``'s.
        max_time: Episode length (s) instead of the archetype's own.
        drive: The robot's drive, ``holonomic`` (default) or ``differential``.
        **kwargs: Passed on to :class:`proxemic.env.ProxemicEnv` (``planner``, ``render_mode``, ...).
    """
    from proxemic.env import ProxemicEnv

    return ProxemicEnv(scenario_name(archetype, scene_seed, max_time, drive), **kwargs)


@dataclass(frozen=True)
class SuiteResult:
    """What a suite run produced."""

    records: list[dict[str, Any]]
    """One dict per episode and robot (the columns of ``episodes.csv``, ``archetype`` first)."""
    summary: list[dict[str, Any]]
    """One row per (archetype, planner): :func:`proxemic.evaluation.summarise` of its records, with ``archetype``."""
    out: Path | None = None


def _is_number(v: Any) -> bool:
    return isinstance(v, (int, float)) and not isinstance(v, bool)


def _registry_keys() -> list[str]:
    return [str(m["key"]) for m in reference.metric_registry()]


def suite_tasks(
    planners: Sequence[str],
    episodes: int,
    seed: int = 0,
    max_time: float | None = None,
    archetypes: Sequence[str] = ARCHETYPES,
    drive: str = "holonomic",
) -> list[tuple[str, tuple[str, str, int]]]:
    """(archetype, (scene name, planner, episode seed)) of every episode, archetype-major."""
    return [
        (a, (scenario_name(a, seed + k, max_time, drive), p, seed + k))
        for a in archetypes
        for p in planners
        for k in range(episodes)
    ]


def run_suite(
    planners: Sequence[str],
    episodes: int = 1,
    *,
    seed: int = 0,
    out: str | Path | None = None,
    workers: int = 1,
    max_time: float | None = None,
    archetypes: Sequence[str] | None = None,
    progress: bool = True,
    drive: str = "holonomic",
) -> SuiteResult:
    """Runs every archetype (or `archetypes`) with every planner, `episodes` scenes each.

    Every robot drives with `drive` (``holonomic``, the default, or ``differential``). Writes into
    `out` (if given): ``episodes.csv`` and ``.parquet`` (one row per episode and robot,
    an ``archetype`` column first; the per-person and per-object columns of single scenes are left
    out, as the archetypes have different people), ``archetypes.csv`` (per archetype and planner:
    success and collision rates and the mean of every metric of the registry in the records) and
    ``summary.md`` (the headline table per archetype, then every metric).

    Raises:
        InputError: a bad planner, episode count or output folder.
        UnknownNameError: an unknown archetype.
    """
    from tqdm import tqdm

    chosen = tuple(archetypes) if archetypes else ARCHETYPES
    for a in chosen:
        scenario_name(a, drive=drive)
    for p in planners:
        scenarios.check_planner(p)
    if not planners:
        raise input_error("planners", "at least one planner", "none")
    if isinstance(episodes, bool) or not isinstance(episodes, int) or episodes < 1:
        raise input_error("episodes", "at least 1", episodes)
    outdir = None if out is None else Path(out)
    if outdir is not None:
        evaluation.check_out_dir(outdir)
    tasks = suite_tasks(planners, episodes, seed, max_time, chosen, drive)
    keep = set(_registry_keys()) | set(reference.RECORD_COLUMNS) | {"outcome"}
    records: list[dict[str, Any]] = []
    bar = tqdm(total=len(tasks), desc=f"{SUITE}: {', '.join(planners)}", unit="ep", disable=not progress)
    writer = (
        evaluation.RecordWriter(outdir / "episodes.csv", outdir / "episodes.parquet", [t for _, t in tasks])
        if outdir is not None
        else None
    )
    try:
        with (
            writer if writer is not None else contextlib.nullcontext(),
            evaluation.Backend("process", workers) as backend,
        ):
            items = [(t, False) for _, t in tasks]
            for (archetype, _), res in zip(tasks, backend.imap(eval_episodes._run_task_kw, items), strict=True):
                for r in [res, *res.others]:
                    row = {"archetype": archetype, **{k: v for k, v in r.record.items() if k in keep}}
                    records.append(row)
                    if writer is not None:
                        writer.write(row)
                bar.update(1)
    finally:
        bar.close()
    summary = summarise_by_archetype(records)
    if outdir is not None:
        write_archetype_table(records, outdir / "archetypes.csv")
        (outdir / "summary.md").write_text(summary_markdown(records, summary, episodes, seed) + "\n")
    return SuiteResult(records, summary, outdir)


def summarise_by_archetype(records: Sequence[dict[str, Any]]) -> list[dict[str, Any]]:
    """One :func:`proxemic.evaluation.summarise` row per (archetype, planner), with ``archetype`` first."""
    rows = []
    for a in dict.fromkeys(r["archetype"] for r in records):
        for row in evaluation.summarise([r for r in records if r["archetype"] == a]):
            rows.append({"archetype": a, **row})
    return rows


def metric_means(records: Sequence[dict[str, Any]]) -> list[dict[str, Any]]:
    """Per (archetype, planner): episodes, the collision rate and every registry metric's mean.

    Every registry metric with a numeric value in the records is a column (None where no episode
    of that archetype and planner has one).
    """
    # Booleans (success, hc, ...) count as 0/1: their mean is the rate.
    keys = [k for k in _registry_keys() if any(_is_number(r.get(k)) or isinstance(r.get(k), bool) for r in records)]
    out = []
    for a in dict.fromkeys(r["archetype"] for r in records):
        for p in dict.fromkeys(r["planner"] for r in records):
            recs = [r for r in records if r["archetype"] == a and r["planner"] == p]
            if not recs:
                continue
            row: dict[str, Any] = {"archetype": a, "planner": p, "episodes": len(recs)}
            row["collision"] = sum(eval_summary.collided(r) for r in recs) / len(recs)
            for k in keys:
                vals = [float(r[k]) for r in recs if _is_number(r.get(k)) or isinstance(r.get(k), bool)]
                vals = [x for x in vals if math.isfinite(x)]
                row[k] = sum(vals) / len(vals) if vals else None
            out.append(row)
    return out


def write_archetype_table(records: Sequence[dict[str, Any]], path: Path) -> None:
    """Writes :func:`metric_means` as CSV."""
    import csv

    rows = metric_means(records)
    if not rows:
        return
    with path.open("w", newline="") as fh:
        w = csv.DictWriter(fh, fieldnames=list(rows[0]))
        w.writeheader()
        w.writerows(rows)


def _fmt(v: Any) -> str:
    if v is None or (isinstance(v, float) and math.isnan(v)):
        return "n/a"
    return f"{v:.3g}" if isinstance(v, float) else str(v)


def headline_table(summary: Sequence[Mapping[str, Any]]) -> str:
    """The headline metrics (:data:`proxemic.evaluation.HEADLINE`) per archetype and planner (markdown).

    Cells are means with 95% intervals (a single episode has none).
    """
    cols = ["archetype", "planner", "episodes", *(eval_summary.header(m) for m in evaluation.HEADLINE)]
    rows = []
    for r in summary:
        n = f"{r['episodes']} x {r['robots']} robots" if r.get("robots", 1) > 1 else str(r["episodes"])
        rows.append(
            [str(r["archetype"]), str(r["planner"]), n, *(eval_summary.cell(r, m) for m in evaluation.HEADLINE)]
        )
    return markdown.table(cols, rows)


def headline_text(summary: Sequence[Mapping[str, Any]]) -> str:
    """A terminal table: one line per archetype and planner, the headline metrics' means."""
    heads = ["archetype", "planner", *(eval_summary.header(m) for m in evaluation.HEADLINE)]
    rows = []
    for r in summary:
        cells = [str(r["archetype"]), str(r["planner"])]
        for m in evaluation.HEADLINE:
            v = r[m]
            info = evaluation.METRICS[m]
            cells.append("n/a" if isinstance(v, float) and math.isnan(v) else f"{v:{info.fmt}}")
        rows.append(cells)
    widths = [max(len(x) for x in col) for col in zip(heads, *rows, strict=False)]

    def fmt(cells: Sequence[str]) -> str:
        pairs = enumerate(zip(cells, widths, strict=True))
        return "  ".join(c.ljust(w) if i < 2 else c.rjust(w) for i, (c, w) in pairs).rstrip()

    return "\n".join([fmt(heads), *(fmt(c) for c in rows)])


def summary_markdown(
    records: Sequence[dict[str, Any]], summary: Sequence[Mapping[str, Any]], episodes: int, seed: int
) -> str:
    """``summary.md``: the headline table per archetype, then every registry metric's mean."""
    means = metric_means(records)
    keys = [k for k in means[0] if k not in ("archetype", "planner")] if means else []
    full = markdown.table(
        ["archetype", "planner", *keys],
        ([str(r["archetype"]), str(r["planner"]), *(_fmt(r[k]) for k in keys)] for r in means),
    )
    return "\n\n".join(
        [
            f"# Francis et al. 2023 suite: {episodes} scene(s) per archetype and planner (scene and episode seeds "
            f"{seed}-{seed + episodes - 1})",
            "## Headline per archetype",
            headline_table(summary),
            "## Every metric per archetype (means over episodes and robots; units in metrics.md)",
            full,
        ]
    )


def plot_archetype(archetype: str, path: str | Path, seed: int = 0) -> Path:
    """A top-down picture of an archetype's scene of `seed`, written to `path` (PNG).

    Walls, every person where they start (a walk as a dashed line with an arrow; a follower of the
    robot behind it, an arrow its way; conversation groups as their members), every robot's start
    (with its heading) and goal, the straight line
    between them dotted.
    """
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    from matplotlib.patches import Circle

    from proxemic.viz.plots import _draw_map

    _, sc = scenarios.load(scenario_name(archetype, seed))
    fig, ax = plt.subplots(figsize=(4.2, 3.2), dpi=90)
    _draw_map(ax, sc)
    for p in sc["persons"]:
        route = p.get("route") or []
        if p["behaviour"] == "walker" and route:
            xs, ys = zip(*route, strict=True)
            ax.plot(xs, ys, color="tab:orange", lw=0.8, ls="--", zorder=4)
            x, y = route[0]
            if len(route) > 1:
                ax.annotate(
                    "",
                    xy=route[1],
                    xytext=route[0],
                    arrowprops={"arrowstyle": "->", "color": "tab:orange", "lw": 1.2},
                    zorder=5,
                )
        elif p["behaviour"] == "follower" and p.get("guide_robot") is not None and len(p["tour"]) > 1:
            # A follower of a robot starts gathered behind the robot's start, away from where it goes.
            (sx, sy), (nx, ny) = p["tour"][0], p["tour"][1]
            d = math.hypot(nx - sx, ny - sy)
            x, y = sx - (nx - sx) / d * p["gather_radius"], sy - (ny - sy) / d * p["gather_radius"]
            ax.annotate(
                "",
                xy=(x + (nx - sx) / d * 0.6, y + (ny - sy) / d * 0.6),
                xytext=(x, y),
                arrowprops={"arrowstyle": "->", "color": "tab:orange", "lw": 1.2},
                zorder=5,
            )
        else:
            x, y = (p.get("home") or p["pose"][:2])[:2]
        ax.add_patch(Circle((x, y), p["radius"], color="tab:orange", zorder=6))
    for k, r in enumerate(sc["robots"]):
        (x, y, th), (gx, gy) = r["start"], r["goal"]
        color = plt.get_cmap("tab10")(0 if k == 0 else 2 + k)
        ax.add_patch(Circle((x, y), r["radius"], color=color, zorder=7))
        ax.plot([x, x + 0.5 * math.cos(th)], [y, y + 0.5 * math.sin(th)], color="k", lw=1.0, zorder=8)
        ax.plot([x, gx], [y, gy], color=color, lw=0.8, ls=":", zorder=4)
        ax.plot([gx], [gy], marker="x", color=color, ms=7, mew=2, zorder=8)
    b = sc["scene"]["bounds"]
    ax.set_xlim(b[0], b[2])
    ax.set_ylim(b[1], b[3])
    ax.set_aspect("equal")
    ax.set_title(archetype.replace("_", " "), fontsize=9)
    ax.tick_params(labelsize=6)
    fig.tight_layout()
    out = Path(path)
    out.parent.mkdir(parents=True, exist_ok=True)
    fig.savefig(out)
    plt.close(fig)
    return out


def main(argv: Sequence[str] | None = None) -> int:
    """``python -m proxemic.francis2023 pictures DIR``: the docs' picture of every archetype (seed 0)."""
    import argparse

    parser = argparse.ArgumentParser(prog="python -m proxemic.francis2023")
    parser.add_argument("command", choices=["pictures"])
    parser.add_argument("folder", nargs="?", default="docs/images/francis2023")
    args = parser.parse_args(argv)
    for a in ARCHETYPES:
        print(plot_archetype(a, Path(args.folder) / f"{a}.png"))
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
