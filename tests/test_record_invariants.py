"""Every episode record satisfies its invariants (the core checks them where the record is made and
raises :class:`proxemic.InvariantError` naming the episode and the invariant; see
``rust/proxemic-core/src/metrics/invariants.rs``): over every registered env, generated scenes, every
Francis et al. 2023 archetype, recorded crowds replayed (hotel and univ, people reacting within
0 m and 1.5 m) and every built-in planner, with short episodes and a few seeds each.

``python tests/test_record_invariants.py`` runs the same episodes with more seeds and windows and
prints how many records broke which invariant (the count the issue asked for)."""

from __future__ import annotations

import csv
import sys
from collections import Counter
from collections.abc import Iterator
from pathlib import Path

import pytest

from proxemic import _core
from proxemic.env import ProxemicEnv
from proxemic.errors import InvariantError
from proxemic.francis2023 import ARCHETYPES, scenario_name
from proxemic.registration import ENV_IDS

ROOT = Path(__file__).resolve().parent.parent
CROWDS = ROOT.parent / "shared" / "data" / "recorded_crowds"
if not CROWDS.is_dir():  # worktrees sit one level deeper than the repository's checkout
    CROWDS = Path("/work/shared/data/recorded_crowds")

#: Control steps per episode at most (short episodes; the record is checked whether it ended or not).
STEPS = 60


def run(env: ProxemicEnv, seed: int, steps: int = STEPS) -> list[dict]:
    """Runs one episode of `env` with its built-in planner for at most `steps` steps, returns its records.

    Raises:
        InvariantError: a record broke an invariant.
    """
    _obs, info = env.reset(seed=seed)
    for _ in range(steps):
        _obs, _r, terminated, truncated, info = env.step(info["planner_action"])
        if terminated or truncated:
            break
    return [dict(m) for m in env.unwrapped.world.episode_metrics()]


def replay_scene(tmp: Path, name: str, t0: float, react_radius: float, window: float = 60.0) -> Path:
    """A scene around the recording `name` (hotel, univ ...) from `t0` for `window` seconds, the robot
    crossing it from one side to the other, everyone reacting within `react_radius` (m)."""
    src = CROWDS / f"{name}.csv"
    with src.open() as f:
        rows = list(csv.DictReader(f))
    xs = [float(r["x"]) for r in rows]
    ys = [float(r["y"]) for r in rows]
    x0, x1, y0, y1 = min(xs) - 1, max(xs) + 1, min(ys) - 1, max(ys) + 1
    ym = (y0 + y1) / 2
    path = tmp / f"{name}_{t0:g}_{react_radius:g}.toml"
    path.write_text(
        f'[scene]\nname = "{name}"\nbounds = [{x0}, {y0}, {x1}, {y1}]\n\n'
        f"[[robot]]\nstart = [{x0 + 0.5}, {ym}, 0]\ngoal = [{x1 - 0.5}, {ym}]\n\n"
        f'[[replay]]\nfile = "{src}"\nt0 = {t0}\nreact_radius = {react_radius}\n\n'
        f"[episode]\nmax_time = {window}\n"
    )
    return path


#: Replayed windows checked besides every recording's first: (recording, t0, react radius, planner) of
#: a record that once broke an invariant (a physics person contact with a replayed person leaving in the
#: step, blamed on a person 4.3 m away).
REPLAY_EXTRA = (("hotel", 540.0, 0.0, "astar_orca"),)


def cases(
    tmp: Path, seeds: int = 2, windows: int = 1, replays: bool = True
) -> Iterator[tuple[str, str | Path, str | None, int, int]]:
    """(family, scene, planner or None for the scene's own, seed, steps) of every checked episode:
    without `replays`, every scene family but the recorded crowds; with it, only those (the first
    `windows` 60 s windows of hotel and univ within the recording, people reacting within 0 m and
    1.5 m, every built-in planner, 600 steps; and :data:`REPLAY_EXTRA`)."""
    if replays:
        for name in ("hotel", "univ"):
            with (CROWDS / f"{name}.csv").open() as f:
                end = max(float(r["t"]) for r in csv.DictReader(f))
            for w in range(windows):
                if 60.0 * w >= end:
                    break
                for react in (0.0, 1.5):
                    scene = replay_scene(tmp, name, 60.0 * w, react)
                    for planner in _core.PLANNERS:
                        yield f"replay {name} t0={60 * w} react={react:g}", scene, planner, w, 600
        for name, t0, react, planner in REPLAY_EXTRA:
            yield f"replay {name} t0={t0:g} react={react:g}", replay_scene(tmp, name, t0, react), planner, 0, 600
        return
    for env_id, scene in ENV_IDS.items():
        for seed in range(seeds):
            yield env_id, scene, None, seed, STEPS
    for seed in range(seeds):
        yield "generated", f"generated/{seed}", None, seed, STEPS
    for k, archetype in enumerate(ARCHETYPES):
        yield "francis2023", scenario_name(archetype, k), None, k, STEPS
    for k, planner in enumerate(_core.PLANNERS):
        yield "planner", "museum" if k % 2 else f"generated/{k}", planner, k, STEPS


def check_all(tmp: Path, replays: bool) -> int:
    """Runs the episodes of :func:`cases`, fails on the first broken record; returns the records checked."""
    checked = 0
    for family, scene, planner, seed, steps in cases(tmp, replays=replays):
        env = ProxemicEnv(scenario=scene, planner=planner)
        try:
            checked += len(run(env, seed, steps))
        except InvariantError as e:
            pytest.fail(f"{family} {scene} planner {planner} seed {seed}: {e}")
        finally:
            env.close()
    return checked


def test_records_of_every_scene_family_and_planner(tmp_path):
    assert check_all(tmp_path, replays=False) > 0


def test_records_of_replayed_crowds(tmp_path):
    if not (CROWDS / "hotel.csv").is_file() or not (CROWDS / "univ.csv").is_file():
        pytest.skip(f"replays not checked: the recorded crowds (hotel.csv, univ.csv) are not in {CROWDS}")
    assert check_all(tmp_path, replays=True) > 0


def test_an_env_names_its_reset_seed_in_a_broken_record(monkeypatch):
    """A broken record raised through the env names the env, the seed given to ``reset`` and the core's
    episode (which names the world's own seed, drawn from the env's)."""

    class Broken:
        def episode_metrics(self, robots: list[int]) -> list[dict]:
            raise InvariantError(
                "museum, seed 99, robot 0: invariant outcome_agrees broken: x",
                file="museum, seed 99, robot 0",
                field="outcome_agrees",
                found="outcome = Success but success = false",
            )

    env = ProxemicEnv("museum")
    try:
        env.reset(seed=7)
        monkeypatch.setattr(env, "world", Broken())
        with pytest.raises(InvariantError) as info:
            env.metrics()
    finally:
        env.close()
    e = info.value
    assert e.field == "outcome_agrees"
    assert e.file is not None and "reset(seed=7)" in e.file and "museum, seed 99, robot 0" in e.file
    assert "outcome = Success but success = false" in str(e)


class _Broken:
    """A core world whose every record is broken (delegating everything else to the real one)."""

    def __init__(self, world: object) -> None:
        self._world = world

    def __getattr__(self, name: str) -> object:
        return getattr(self._world, name)

    def episode_metrics(self, robots: list[int] | None = None) -> list[dict]:
        raise InvariantError(
            "museum, seed 99, robot 0: invariant outcome_agrees broken: x",
            file="museum, seed 99, robot 0",
            field="outcome_agrees",
            found="outcome = Success but success = false",
        )


def test_the_vector_and_parallel_envs_name_their_reset_seed_in_a_broken_record():
    """A broken record raised through the vector env (an ended world's final info; world k reset
    with seed s + k) and the PettingZoo parallel env (its metrics) names the env, the seed given to
    ``reset`` and the core's episode."""
    import proxemic
    from proxemic.vector import ProxemicVectorEnv

    venv = ProxemicVectorEnv("museum", num_envs=2)
    try:
        venv.reset(seed=7)
        venv.sims[1].world = _Broken(venv.sims[1].world)  # type: ignore[assignment]
        with pytest.raises(InvariantError) as info:
            venv._infos([0, 1], [1])  # world 1's episode ended: its final info has its metrics
    finally:
        venv.close()
    e = info.value
    assert e.field == "outcome_agrees" and e.file is not None
    assert "world 1, reset(seed=8)" in e.file and "museum, seed 99, robot 0" in e.file
    penv = proxemic.parallel_env("museum_multi", robots=2)
    try:
        penv.reset(seed=5)
        penv.world = _Broken(penv.world)  # type: ignore[assignment]
        with pytest.raises(InvariantError) as info:
            penv.episode_metrics()
    finally:
        penv.close()
    e = info.value
    assert e.file is not None and "reset(seed=5)" in e.file and "museum, seed 99, robot 0" in e.file
    assert "outcome = Success but success = false" in str(e)


def census(seeds: int, windows: int) -> Counter[str]:
    """Runs :func:`cases` and counts the broken records by family and invariant (printing each)."""
    import tempfile

    broken: Counter[str] = Counter()
    with tempfile.TemporaryDirectory() as tmp:
        every = [*cases(Path(tmp), seeds, windows, replays=False), *cases(Path(tmp), seeds, windows, replays=True)]
        for family, scene, planner, seed, steps in every:
            env = ProxemicEnv(scenario=scene, planner=planner)
            try:
                run(env, seed, steps)
            except InvariantError as e:
                broken[f"{family.split(' t0=')[0]} {planner}: {e.field}"] += 1
                print(f"{family} {Path(str(scene)).name} planner {planner} seed {seed}: {e}", flush=True)
            finally:
                env.close()
    return broken


if __name__ == "__main__":
    counts = census(int(sys.argv[1]) if len(sys.argv) > 1 else 4, int(sys.argv[2]) if len(sys.argv) > 2 else 4)
    print(dict(counts) or "no broken record")
