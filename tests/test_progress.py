"""The progress monitor every built-in planner runs, checked on the test split.

- The doorway trap (``tests/data/doorway_trap.toml``): a ward corridor with two side doorways, a
  nurse standing past them and a walker coming out of one across the robot's way. With the monitor
  off, ``social`` stays between the doorways and the nurse until the time runs out on some seeds;
  with it, ``social`` reaches the goal on every seed of :data:`TRAP_SEEDS` (test split).
- On the generated scenes of the claims suite (``generated/<seed>?encounters=1&density=2.5``, the
  scene seeds of the test split, one episode each, episode seed = scene seed), each planner of
  :data:`PLANNERS` times out in at most 2% of the episodes and collides in at most 2%. A planner the
  compiled core does not have (``astar_orca`` before it is merged) is skipped. ``make test`` runs the
  CI prefix of the split (the episodes of ``social`` are the claims suite's own, run once per
  session), ``make test-full`` (marker ``full``) the whole split. A claim that does not hold is a
  strict xfail stating the measured figure (:data:`KNOWN_FAILURES`), never weakened.
- The monitor's record reaches the episode metrics and ``eval``'s records, and its settings are
  checked like every scenario field.

The monitor's constants were chosen on the tuning split only (see
``proxemic_core::control::progress``).
"""

from __future__ import annotations

import multiprocessing as mp
from pathlib import Path
from typing import Any

import pytest

import proxemic
import test_social_vs_astar as claims
from proxemic import scenarios, splits
from proxemic.errors import ScenarioError
from proxemic.evaluation import EvalConfig, iter_results

#: The planners whose timeout and collision rates are claimed on generated scenes.
PLANNERS = ("social", "astar_orca")
#: Largest share of episodes that may time out, and that may collide.
MAX_TIMEOUTS = 0.02
MAX_COLLISIONS = 0.02
#: (planner, claim, full split) -> the measured figure, for claims that do not hold.
KNOWN_FAILURES: dict[tuple[str, str, bool], str] = {}


def _run(planner: str, seed: int) -> dict[str, Any]:
    name = f"generated/{seed}{claims.GENERATED_QUERY}"
    cfg = EvalConfig(scenario=name, planners=[planner], episodes=1, seed=seed, workers=1, out=None)
    return next(iter(iter_results(cfg))).record


_CACHE: dict[tuple[str, tuple[int, ...]], list[dict[str, Any]]] = {}


def episodes(planner: str, seeds: tuple[int, ...]) -> list[dict[str, Any]]:
    """The records of `planner` on the generated scenes `seeds` (run once per session, 2 processes)."""
    if planner == claims.SOCIAL:
        return claims.records(claims.GENERATED, seeds)[claims.SOCIAL]
    key = (planner, seeds)
    if key not in _CACHE:
        with mp.get_context("fork").Pool(2) as pool:
            _CACHE[key] = pool.starmap(_run, [(planner, s) for s in seeds])
    return _CACHE[key]


def _cases(full: bool) -> list[Any]:
    out = []
    for planner in PLANNERS:
        for claim in ("timeouts", "collisions"):
            marks: list[Any] = [pytest.mark.full] if full else []
            if planner not in proxemic.PLANNERS:
                marks.append(pytest.mark.skip(reason=f"{planner} is not a planner of this build"))
            reason = KNOWN_FAILURES.get((planner, claim, full))
            if reason:
                marks.append(pytest.mark.xfail(strict=True, reason=reason))
            out.append(pytest.param(planner, claim, marks=marks, id=f"{planner}-{claim}"))
    return out


def _check(planner: str, claim: str, seeds: tuple[int, ...]) -> None:
    recs = episodes(planner, seeds)
    assert len(recs) == len(seeds)
    if claim == "timeouts":
        bad = [r["seed"] for r in recs if r["timeout"]]
        limit = MAX_TIMEOUTS
    else:
        bad = [r["seed"] for r in recs if r["collision"]]
        limit = MAX_COLLISIONS
    share = len(bad) / len(recs)
    recoveries = sum(int(r["recoveries"]) for r in recs)
    print(f"{planner}: {claim} in {len(bad)}/{len(recs)} generated scenes ({share:.1%}); {recoveries} recoveries")
    assert share <= limit, (
        f"{planner}: {claim} in {len(bad)}/{len(recs)} generated scenes ({share:.1%}, claim <= {limit:.0%}), "
        f"seeds {bad}; {recoveries} recoveries in all"
    )


@pytest.mark.parametrize(("planner", "claim"), _cases(full=False))
def test_generated_rates_ci(planner: str, claim: str) -> None:
    _check(planner, claim, claims.CI_SCENE_SEEDS)


@pytest.mark.parametrize(("planner", "claim"), _cases(full=True))
def test_generated_rates_full(planner: str, claim: str) -> None:
    _check(planner, claim, claims.FULL_SCENE_SEEDS)


# --- the doorway trap ----------------------------------------------------------------------------------

#: The scene of the trap.
TRAP = Path(__file__).with_name("data") / "doorway_trap.toml"
#: Episode seeds of the trap (test split; the monitor's constants were chosen on tuning seeds).
TRAP_SEEDS = splits.TEST_EPISODE_SEEDS[:20]


def _trap_episode(path: str, seed: int) -> dict[str, Any]:
    cfg = EvalConfig(scenario=path, planners=["social"], episodes=1, seed=seed, workers=1, out=None)
    return next(iter(iter_results(cfg))).record


def _trap(tmp_path: Path, monitor: bool) -> list[dict[str, Any]]:
    text = TRAP.read_text()
    if not monitor:
        text = text.replace('planner = "social"\n', 'planner = "social"\nprogress = { enabled = false }\n', 1)
        assert "enabled = false" in text
    path = tmp_path / "trap.toml"
    path.write_text(text)
    with mp.get_context("fork").Pool(2) as pool:
        return pool.starmap(_trap_episode, [(str(path), s) for s in TRAP_SEEDS])


@pytest.mark.xfail(
    strict=True,
    reason="measured on test seeds 1000-1019 since the people react to robots (and walk with the "
    "calibrated social force): without the monitor social times out on 0 of 20 seeds, with the nurse "
    "set to ignore the robot too; the scene no longer reproduces the deadlock it was built for",
)
def test_the_trap_holds_social_without_the_monitor(tmp_path: Path) -> None:
    """The scene reproduces the deadlock: without the monitor, `social` times out on some seeds."""
    recs = _trap(tmp_path, monitor=False)
    stuck = [r["seed"] for r in recs if r["timeout"]]
    print(f"monitor off: social timed out on {len(stuck)}/{len(recs)} seeds {stuck}")
    assert stuck, "social reached the goal on every seed without the monitor: the scene no longer traps it"


def test_social_gets_through_the_trap_with_the_monitor(tmp_path: Path) -> None:
    recs = _trap(tmp_path, monitor=True)
    failed = [(r["seed"], r["outcome"], r["recoveries"]) for r in recs if not r["success"]]
    print(f"monitor on: {sum(r['recoveries'] for r in recs)} recoveries over {len(recs)} seeds")
    assert not failed, f"social failed in the doorway trap on (seed, outcome, recoveries) {failed}"


# --- the monitor's record and settings ---------------------------------------------------------------

#: A 12 x 4 m room whose only way to the goal is a 1.6 m gap with a person standing in it.
BLOCKED = """
[scene]
name = "blocked"
bounds = [0, 0, 12, 4]

[[wall]]
from = [0, 0]
to = [12, 0]
[[wall]]
from = [12, 0]
to = [12, 4]
[[wall]]
from = [12, 4]
to = [0, 4]
[[wall]]
from = [0, 4]
to = [0, 0]
[[wall]]
from = [6, 0]
to = [6, 1.1]
[[wall]]
from = [6, 2.9]
to = [6, 4]

[[person]]
behaviour = "standing"
pose = [6.0, 2.0, 0.0]

[[robot]]
start = [2, 2, 0]
goal = [10, 2]
planner = "astar_stop_placeholder"
{progress}

[episode]
max_time = 40
"""


def _blocked(write_scenario: Any, planner: str, progress: str = "") -> dict[str, Any]:
    # One file per setting: eval caches its env per scenario path.
    name = "blocked_off.toml" if progress else "blocked.toml"
    path = write_scenario(BLOCKED.replace("astar_stop_placeholder", planner).replace("{progress}", progress), name)
    cfg = EvalConfig(scenario=str(path), planners=[planner], episodes=1, seed=0, workers=1, out=None)
    return next(iter(iter_results(cfg))).record


def test_a_blocked_robot_recovers_and_the_record_says_so(write_scenario: Any) -> None:
    """Behind a person standing in the only gap, `social` stalls: the monitor recovers (every 15 s
    window, the default) and counts the stalled time; with the monitor off, none is recorded."""
    on = _blocked(write_scenario, "social")
    assert on["recoveries"] >= 1, on
    assert on["monitor_stalled_time"] >= 15.0 - 1e-6, on
    off = _blocked(write_scenario, "social", "progress = { enabled = false }")
    assert (off["recoveries"], off["monitor_stalled_time"]) == (0, 0.0)


def test_the_same_seed_gives_the_same_recoveries(write_scenario: Any) -> None:
    a, b = _blocked(write_scenario, "social"), _blocked(write_scenario, "social")
    assert a == b


#: A 12 x 6 m room with two people standing 1.2 m apart (centres) across the straight way to the
#: goal: a gap the bodies fit through (0.88 m) but ORCA's discs (body + 0.08 m each) exactly fill.
#: The pair does not make way for the robot (`ignore`: people who see it shift aside, widening the gap).
PAIR_GAP = """
[scene]
name = "pair_gap"
bounds = [0, 0, 12, 6]
reaction = "ignore"

[[wall]]
from = [0, 0]
to = [12, 0]
[[wall]]
from = [12, 0]
to = [12, 6]
[[wall]]
from = [12, 6]
to = [0, 6]
[[wall]]
from = [0, 6]
to = [0, 0]

[[person]]
behaviour = "standing"
pose = [6.0, 2.4, 1.5708]

[[person]]
behaviour = "standing"
pose = [6.0, 3.6, -1.5708]

[[robot]]
start = [2, 3, 0]
goal = [10, 3]
planner = "astar_orca"

[episode]
max_time = 60
"""


def test_astar_orca_recovers_from_the_gap_of_a_pair(write_scenario: Any) -> None:
    """ORCA holds `astar_orca` in the gap of the pair; the recovery re-plans round the pair (ORCA's
    discs as obstacles, not the smaller inflated ones that left a channel through the gap)."""
    path = write_scenario(PAIR_GAP, "pair_gap.toml")
    cfg = EvalConfig(scenario=str(path), planners=["astar_orca"], episodes=1, seed=0, workers=1, out=None)
    rec = next(iter(iter_results(cfg))).record
    assert rec["recoveries"] >= 1, rec
    assert rec["success"], (rec["outcome"], rec["recoveries"])


@pytest.mark.parametrize(
    ("setting", "field"),
    [
        ("progress = { window = 0.0 }", "robot[0].progress.window"),
        ("progress = { distance = -1.0 }", "robot[0].progress.distance"),
        ("progress = { distance = 11.0 }", "robot[0].progress.distance"),
    ],
)
def test_bad_settings_name_the_field(write_scenario: Any, setting: str, field: str) -> None:
    path = write_scenario(BLOCKED.replace("astar_stop_placeholder", "social").replace("{progress}", setting))
    with pytest.raises(ScenarioError, match=field.replace("[", r"\[").replace("]", r"\]")):
        scenarios.load(str(path))
