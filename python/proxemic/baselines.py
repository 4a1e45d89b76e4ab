"""Every built-in planner's figures on the test split: the generated tables of ``docs/learned.md``.

``python -m proxemic.baselines docs/learned.md`` runs every built-in planner
(:data:`PLANNERS`: ``learned`` first, then every hand-written one) on the test split
(:mod:`proxemic.splits`) of the museum, the care center, generated scenes and every Francis et al.
2023 archetype, and writes the tables into the page's generated block (between :data:`DOCS_BEGIN`
and :data:`DOCS_END`). Episodes run as ``proxemic eval`` runs them
(:func:`proxemic.evaluation.run_task` on a :class:`~proxemic.evaluation.Backend`) and are
summarised by :func:`proxemic.evaluation.summarise`; nothing here computes a metric.
"""

from __future__ import annotations

import sys
from collections.abc import Mapping, Sequence
from dataclasses import dataclass
from pathlib import Path
from typing import Any

from proxemic import _core, francis2023, markdown, scenarios, splits
from proxemic.errors import input_error
from proxemic.evaluation import episodes as eval_episodes
from proxemic.evaluation.backend import Backend
from proxemic.evaluation.metrics import METRICS
from proxemic.evaluation.summary import cell, header, summarise

#: Every built-in planner, the shipped learned policy first (the core's ``PlannerKind::NAMES``).
PLANNERS: tuple[str, ...] = ("learned", *(p for p in _core.PLANNERS if p != "learned"))
#: The generated scenes' parameters (those of the claims suite: one encounter, density 2.5).
GENERATED_PARAMS: dict[str, float | str] = {"encounters": 1, "density": 2.5}
#: The columns of a scene set's table (registry keys), after planner and episodes.
COLUMNS: tuple[str, ...] = (
    "success",
    "collision",
    "timeout",
    "time_to_goal",
    "personal_gap_time",
    "intimate_gap_time",
)
#: Default episodes per scene set (museum, care center: episode seeds; generated: scene seeds).
EPISODES = 20
#: Default scenes per Francis archetype (scene and episode seeds).
FRANCIS_EPISODES = 5

#: The generated block of the page, between this line ...
DOCS_BEGIN = "<!-- BEGIN GENERATED: python -m proxemic.baselines docs/learned.md (do not edit by hand) -->"
#: ... and this one.
DOCS_END = "<!-- END GENERATED: proxemic.baselines -->"


@dataclass(frozen=True)
class SceneSet:
    """One scene set of the tables: a bundled scene on test episode seeds, or generated test scenes."""

    #: Key and heading.
    key: str
    #: Bundled scene name, or ``None`` for generated scenes (one scene per test scene seed).
    scene: str | None

    def seeds(self, episodes: int) -> tuple[int, ...]:
        """The first `episodes` seeds of the test split this set runs."""
        pool = splits.TEST_SCENE_SEEDS if self.scene is None else splits.TEST_EPISODE_SEEDS
        return pool[:episodes]

    def task(self, planner: str, seed: int) -> tuple[str, str, int]:
        """The (scene name, planner, episode seed) of one episode."""
        if self.scene is None:
            return (scenarios.generated_name(seed, **GENERATED_PARAMS), planner, seed)
        return (self.scene, planner, seed)

    def title(self, episodes: int) -> str:
        """The table's heading, naming the seeds."""
        s = self.seeds(episodes)
        if self.scene is None:
            query = "&".join(f"{k}={v}" for k, v in GENERATED_PARAMS.items())
            return f"generated (test scene seeds {s[0]}-{s[-1]}, one episode each, `?{query}`)"
        return f"{self.key} (test episode seeds {s[0]}-{s[-1]})"


#: The scene sets, in the page's order (Francis's archetypes follow them).
SETS: tuple[SceneSet, ...] = (
    SceneSet("museum", "museum"),
    SceneSet("care_center", "care_center"),
    SceneSet("generated", None),
)


def table_header() -> list[str]:
    """The header of a scene set's table."""
    return ["planner", "episodes", *(header(m) for m in COLUMNS)]


def francis_header() -> list[str]:
    """The header of the Francis table: archetype, then one column per planner."""
    return ["archetype", *PLANNERS]


def _cell(row: Mapping[str, Any], m: str) -> str:
    if m == "success":
        return cell(row, m)
    if m in ("collision", "timeout"):
        return f"{row[m]:.0%}"
    v, n = row[m], row[f"{m}_n"]
    text = "n/a" if v != v else f"{v:{METRICS[m].fmt}}"
    return f"{text} (n={n})" if n < row["episodes"] and n else text


def set_table(rows: Sequence[Mapping[str, Any]]) -> str:
    """A scene set's table: one line per planner (summary rows of :func:`summarise`)."""
    body = [[str(r["planner"]), str(r["episodes"]), *(_cell(r, m) for m in COLUMNS)] for r in rows]
    return markdown.table(table_header(), body)


def francis_table(records: Sequence[Mapping[str, Any]]) -> str:
    """Success (and collision) per archetype and planner."""
    body = []
    for a in francis2023.ARCHETYPES:
        rows = {r["planner"]: r for r in summarise([dict(r) for r in records if r["archetype"] == a])}
        body.append([a, *(f"{rows[p]['success']:.0%} ({rows[p]['collision']:.0%} coll.)" for p in PLANNERS)])
    return markdown.table(francis_header(), body)


def headline(name: str, rows: Sequence[Mapping[str, Any]]) -> str:
    """One line: learned's success and collision rates beside the best and worst hand-written planners'.

    Best and worst by success, then fewer collisions; planners tied there are all named.
    """
    by = {r["planner"]: r for r in rows}
    hand = [r for r in rows if r["planner"] != "learned"]

    def rank(r: Mapping[str, Any]) -> tuple[float, float]:
        return (r["success"], -r["collision"])

    def fig(r: Mapping[str, Any]) -> str:
        return f"{r['success']:.0%} success, {r['collision']:.0%} collisions"

    def named(pick: Mapping[str, Any]) -> str:
        return ", ".join(str(r["planner"]) for r in hand if rank(r) == rank(pick)) + f" {fig(pick)}"

    best, worst = max(hand, key=rank), min(hand, key=rank)
    return f"- {name}: learned {fig(by['learned'])}; best hand-written {named(best)}; worst {named(worst)}"


def run(
    episodes: int = EPISODES, francis_episodes: int = FRANCIS_EPISODES, workers: int = 2, progress: bool = True
) -> tuple[dict[str, list[dict[str, Any]]], list[dict[str, Any]]]:
    """Runs every planner on every set: summary rows per set, and the Francis records (one per robot).

    Raises:
        InputError: a bad episode count.
    """
    from tqdm import tqdm

    for name, n, most in (
        ("episodes", episodes, len(splits.TEST_EPISODE_SEEDS)),
        ("francis_episodes", francis_episodes, len(splits.TEST_EPISODE_SEEDS)),
    ):
        if isinstance(n, bool) or not isinstance(n, int) or not 1 <= n <= most:
            raise input_error(name, f"an integer in 1..{most} (the test split's seeds)", n)
    tasks: list[tuple[str, tuple[str, str, int]]] = [
        (s.key, s.task(p, seed)) for s in SETS for p in PLANNERS for seed in s.seeds(episodes)
    ]
    francis_seed = splits.TEST_EPISODE_SEEDS[0]
    tasks += [
        (f"francis:{a}", t)
        for a, t in francis2023.suite_tasks(PLANNERS, francis_episodes, francis_seed, archetypes=francis2023.ARCHETYPES)
    ]
    records: dict[str, list[dict[str, Any]]] = {}
    bar = tqdm(total=len(tasks), desc="test split, every planner", unit="ep", disable=not progress)
    try:
        with Backend("process", workers) as backend:
            items = [(t, False) for _, t in tasks]
            for (key, _), res in zip(tasks, backend.imap(eval_episodes._run_task_kw, items), strict=True):
                records.setdefault(key, []).extend(r.record for r in [res, *res.others])
                bar.update(1)
    finally:
        bar.close()
    summaries = {s.key: summarise(records[s.key]) for s in SETS}
    francis = [
        {**r, "archetype": key.partition(":")[2]}
        for key, recs in records.items()
        if key.startswith("francis:")
        for r in recs
    ]
    return summaries, francis


def block_text(
    summaries: Mapping[str, Sequence[Mapping[str, Any]]],
    francis: Sequence[Mapping[str, Any]],
    episodes: int,
    francis_episodes: int,
) -> str:
    """The generated block: what was run, the headline, a table per scene set, the Francis table."""
    f_seeds = splits.TEST_EPISODE_SEEDS[:francis_episodes]
    francis_rows = summarise([dict(r) for r in francis])
    lines = [
        f"Every built-in planner on the test split ([`proxemic.splits`](choices.md)): {episodes} episodes per "
        f"scene set and planner, {francis_episodes} scenes per Francis archetype and planner "
        f"(`python -m proxemic.baselines docs/learned.md --episodes {episodes} "
        f"--francis-episodes {francis_episodes}` wrote this block). Success with its 95% Wilson interval; "
        "time to goal over the successful episodes (n = how many when fewer than all); zone times are "
        "seconds per episode, body gap to body gap.",
        "",
        "Learned against the best and worst hand-written planner (by success, then fewer collisions):",
        "",
        *(headline(s.key, summaries[s.key]) for s in SETS),
        headline(f"Francis, all {len(francis2023.ARCHETYPES)} archetypes pooled", francis_rows),
        "",
    ]
    for s in SETS:
        lines += [f"### {s.title(episodes)}", "", set_table(summaries[s.key]), ""]
    lines += [
        f"### Francis et al. 2023 ({len(francis2023.ARCHETYPES)} archetypes, scene seeds "
        f"{f_seeds[0]}-{f_seeds[-1]} each): success (collisions)",
        "",
        francis_table(francis),
        "",
    ]
    return "\n".join(lines)


def write_docs(path: Path, episodes: int = EPISODES, francis_episodes: int = FRANCIS_EPISODES, workers: int = 2) -> str:
    """Runs every planner and writes the block into `path`; returns the block.

    Raises:
        InputError: `path` has no block (the marker lines :data:`DOCS_BEGIN` and :data:`DOCS_END`),
            or a bad episode count.
    """
    markdown.check_block(path, DOCS_BEGIN, DOCS_END)
    summaries, francis = run(episodes, francis_episodes, workers)
    block = block_text(summaries, francis, episodes, francis_episodes)
    markdown.write_block(path, DOCS_BEGIN, DOCS_END, block)
    return block


def main(argv: Sequence[str] | None = None) -> int:
    """``python -m proxemic.baselines docs/learned.md``: regenerates the page's tables."""
    import argparse

    parser = argparse.ArgumentParser(prog="python -m proxemic.baselines", description=main.__doc__)
    parser.add_argument("page", type=Path, help="the docs page with the generated block (docs/learned.md)")
    parser.add_argument("--episodes", type=int, default=EPISODES, help=f"per scene set (default {EPISODES})")
    parser.add_argument(
        "--francis-episodes", type=int, default=FRANCIS_EPISODES, help=f"per archetype (default {FRANCIS_EPISODES})"
    )
    parser.add_argument("--workers", type=int, default=2, help="processes (default 2)")
    args = parser.parse_args(argv)
    block = write_docs(args.page, args.episodes, args.francis_episodes, args.workers)
    sys.stdout.write(block)
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
