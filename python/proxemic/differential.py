"""Success rates of a differential-drive robot beside the holonomic one, measured on the test split.

``python -m proxemic.differential docs/scenarios.md`` runs the built-in planners
:data:`PLANNERS` with both drives on the museum and the care center (test episode seeds from
``1000``) and on every Francis et al. 2023 panel (test scene seeds from ``10000``), and writes
the table into the generated block of the page's "Differential-drive robots" section.
"""

from __future__ import annotations

from collections.abc import Sequence
from pathlib import Path
from typing import Any

from proxemic import francis2023, markdown
from proxemic.env import ProxemicEnv
from proxemic.errors import input_error
from proxemic.runner import run_episode
from proxemic.splits import TEST_EPISODE_SEEDS, TEST_SCENE_SEEDS

#: The planners compared (the non-social baseline and the social planner).
PLANNERS: tuple[str, ...] = ("astar_orca", "social")

#: The built-in scenes run on test episode seeds.
BUILTIN_SCENES: tuple[str, ...] = ("museum", "care_center")

#: Test episodes per built-in scene (episode seeds ``1000 ..``).
SCENE_EPISODES = 20

#: Test scenes per Francis et al. 2023 panel (scene seeds ``10000 ..``, episode seed ``1000``).
PANEL_EPISODES = 10

#: The drives compared, holonomic first.
DRIVES: tuple[str, ...] = ("holonomic", "differential")

#: The first line of the generated block in the docs page.
DOCS_BEGIN = "<!-- BEGIN GENERATED: python -m proxemic.differential docs/scenarios.md (do not edit by hand) -->"
#: ... and its last.
DOCS_END = "<!-- END GENERATED -->"


def scenes() -> list[str]:
    """The scenes compared: the built-in ones, then every Francis et al. 2023 panel (archetype)."""
    return [*BUILTIN_SCENES, *(francis2023.PREFIX + a for a in francis2023.ARCHETYPES)]


def _tasks(scene: str, scene_episodes: int, panel_episodes: int) -> list[tuple[str, int]]:
    """The (scenario name, episode seed) pairs of `scene` on the test split."""
    if scene.startswith(francis2023.PREFIX):
        archetype = scene[len(francis2023.PREFIX) :]
        seeds = TEST_SCENE_SEEDS[:panel_episodes]
        return [(francis2023.scenario_name(archetype, seed=s), TEST_EPISODE_SEEDS[0]) for s in seeds]
    return [(scene, s) for s in TEST_EPISODE_SEEDS[:scene_episodes]]


def _seeds_text(scene: str, scene_episodes: int, panel_episodes: int) -> str:
    """The seeds of `scene`'s episodes, as the table states them."""
    if scene.startswith(francis2023.PREFIX):
        return f"scene {TEST_SCENE_SEEDS[0]}-{TEST_SCENE_SEEDS[panel_episodes - 1]}"
    return f"episode {TEST_EPISODE_SEEDS[0]}-{TEST_EPISODE_SEEDS[scene_episodes - 1]}"


def success(scenario: str, seed: int, planner: str, drive: str) -> bool:
    """Whether the robot with the built-in `planner` and `drive` reaches its goal in `scenario` from `seed`."""
    env = ProxemicEnv(scenario, autopilot=True, planner=planner, drive=drive)
    try:
        return bool(run_episode(scenario, seed, env=env).metrics["success"])
    finally:
        env.close()


def measure(
    scene_names: Sequence[str] | None = None,
    *,
    scene_episodes: int = SCENE_EPISODES,
    panel_episodes: int = PANEL_EPISODES,
    progress: bool = True,
) -> list[dict[str, Any]]:
    """One row per (scene, planner of :data:`PLANNERS`): the holonomic and differential success rates.

    Each row has ``scene``, ``planner``, ``holonomic`` and ``differential`` (success rates in
    [0, 1]), ``episodes`` (per drive) and ``seeds``. Both drives run the same scenes and seeds.

    Raises:
        InputError: An episode count out of the test split (not in [1, 60]).
    """
    from tqdm import tqdm

    for field, n in (("scene_episodes", scene_episodes), ("panel_episodes", panel_episodes)):
        if isinstance(n, bool) or not isinstance(n, int) or not 1 <= n <= len(TEST_SCENE_SEEDS):
            raise input_error(field, f"an integer in [1, {len(TEST_SCENE_SEEDS)}]", n)
    chosen = list(scene_names) if scene_names is not None else scenes()
    work = {s: _tasks(s, scene_episodes, panel_episodes) for s in chosen}
    total = sum(len(t) for t in work.values()) * len(PLANNERS) * len(DRIVES)
    rows = []
    with tqdm(total=total, desc="differential drive", unit="ep", disable=not progress) as bar:
        for scene, tasks in work.items():
            for planner in PLANNERS:
                rates: dict[str, float] = {}
                for drive in DRIVES:
                    wins = 0
                    for name, seed in tasks:
                        wins += success(name, seed, planner, drive)
                        bar.update(1)
                    rates[drive] = wins / len(tasks)
                rows.append(
                    {
                        "scene": scene,
                        "planner": planner,
                        **rates,
                        "episodes": len(tasks),
                        "seeds": _seeds_text(scene, scene_episodes, panel_episodes),
                    }
                )
    return rows


def table_text(rows: Sequence[dict[str, Any]]) -> str:
    """The rows of :func:`measure` as a markdown table."""
    header = ["scene", "planner", "holonomic success", "differential success", "episodes", "seeds"]
    return markdown.table(
        header,
        (
            [
                f"`{r['scene']}`",
                f"`{r['planner']}`",
                f"{r['holonomic']:.2f}",
                f"{r['differential']:.2f}",
                str(r["episodes"]),
                r["seeds"],
            ]
            for r in rows
        ),
    )


def write_docs(
    path: Path, *, scene_episodes: int = SCENE_EPISODES, panel_episodes: int = PANEL_EPISODES
) -> list[dict[str, Any]]:
    """Measures every scene and writes the table into `path`'s generated block; returns the rows.

    Raises:
        InputError: `path` has no block (the marker lines :data:`DOCS_BEGIN` and :data:`DOCS_END`),
            checked before the run.
    """
    markdown.check_block(path, DOCS_BEGIN, DOCS_END)
    rows = measure(scene_episodes=scene_episodes, panel_episodes=panel_episodes)
    block = (
        f"Success rates on the test split, `python -m proxemic.differential docs/scenarios.md "
        f"--scene-episodes {scene_episodes} --panel-episodes {panel_episodes}` regenerates this block "
        f"(built-in scenes: {scene_episodes} episode seeds each; Francis et al. 2023 panels: "
        f"{panel_episodes} scene seeds each, episode seed {TEST_EPISODE_SEEDS[0]}; both drives on "
        f"the same seeds):\n\n{table_text(rows)}\n"
    )
    markdown.write_block(path, DOCS_BEGIN, DOCS_END, block)
    return rows


def main(argv: Sequence[str] | None = None) -> int:
    """``python -m proxemic.differential docs/scenarios.md``: regenerates the docs' success-rate table."""
    import argparse

    parser = argparse.ArgumentParser(prog="python -m proxemic.differential", description=main.__doc__)
    parser.add_argument("page", type=Path, help="the docs page with the generated block (docs/scenarios.md)")
    parser.add_argument("--scene-episodes", type=int, default=SCENE_EPISODES, help="episodes per built-in scene")
    parser.add_argument("--panel-episodes", type=int, default=PANEL_EPISODES, help="scene seeds per Francis panel")
    args = parser.parse_args(argv)
    write_docs(args.page, scene_episodes=args.scene_episodes, panel_episodes=args.panel_episodes)
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
