"""The papers' claims about the social planner against plain A*, asserted on our measured metrics.

Seeded museum and care-center episodes, the full social planner (``social``: social A* global path,
Social Momentum near people, ORCA among robots; Daza et al. 2021 Algorithm 1) against plain A*
(``astar``), the same seeds for both. A CI-sized subset (``CI_SEEDS``) runs in ``make test``; the
full suite (``FULL_SEEDS``) is marked ``full`` (``make test-full``).

Claims that our planner or our scenes do not meet are marked ``xfail(strict=True)`` with the
measured reason (see ``KNOWN_FAILURES``): they are reported on every run, and the mark fails the
moment the claim starts to hold, so it cannot rot.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from typing import Any

import pytest

from proxemic.evaluation import EvalConfig, iter_results

SOCIAL, ASTAR = "social", "astar"
SCENES = ("museum", "care_center")
#: Claims also checked on a paper scene that exercises them: Calderita's first experiment, where
#: plain A* crosses the round table's space during its therapy (neither museum nor care center
#: puts an active object space on A*'s way).
EXTRA_CASES = (("calderita_exp1", "objects"),)
#: Episode seeds of the CI subset (chosen once, fixed: seed 4 is a care-center episode where plain
#: A* enters an intimate zone).
CI_SEEDS = (0, 1, 4, 5)
#: Episode seeds of the full suite.
FULL_SEEDS = tuple(range(20))

Records = dict[str, list[dict[str, Any]]]

#: (scene, claim) -> why it fails on our measurements, in both suites (measured on the 50-person
#: museum and the agenda-driven care center with its nurse-station delivery, CI seeds / all 20).
KNOWN_FAILURES: dict[tuple[str, str], str] = {
    ("museum", "personal"): "museum: social spends 45% (CI seeds) / 21% (20 seeds) less time in personal zones "
    "than A* (13.0% vs 23.5%; 22.6% vs 28.6%), not 50% (the corridor is 2.8 m wide with two-way traffic: "
    "there is no room to keep 1.2 m from everyone)",
    ("museum", "time"): "museum: social takes 1.35x A*'s time to goal (78.4 s vs 58.0 s: Social Momentum slows "
    "and detours in the crowded corridor); the claim allows 1.3x",
    ("museum", "ospace"): "museum: plain A*'s path never enters a group's o-space (0% on every seed) while "
    "social does on the full suite (0.37%), so the claim has nothing to halve",
    ("museum", "interactions"): "museum: neither planner crosses a person-person or person-object interaction "
    "segment on these seeds, so the claim is not exercised",
    ("museum", "objects"): "museum: no object activity is scheduled (no agenda), so no time inside an active "
    "object space for either planner",
    ("care_center", "personal"): "care_center: social spends 43% (CI seeds) / 35% (20 seeds) less time in "
    "personal zones than A* (7.7% vs 13.6%; 10.1% vs 15.6%), short of the 50% claimed",
    ("care_center", "interactions"): "care_center: neither planner crosses an interaction segment on these "
    "seeds, so the claim is not exercised",
    ("care_center", "objects"): "care_center: plain A*'s path never enters an object space while its activity "
    "is on, so the claim is not exercised",
    ("care_center", "time"): "care_center: social takes 1.5x A*'s time to goal (44.5 s vs 29.4 s); the claim "
    "allows 1.3x",
    ("care_center", "l_ratio"): "care_center: social's L_ratio is 0.73 (CI seeds) / 0.76 (20 seeds), below 0.8 "
    "(its executed path is longer than A*'s: the same slow-down as the time claim)",
}

#: Failures of the full suite only (the CI seeds happen to meet the claim).
KNOWN_FULL_FAILURES: dict[tuple[str, str], str] = {
    ("museum", "intimate"): "museum, 20 seeds: social enters an intimate zone on seed 2 although it started "
    "with room (not yet analysed)",
    ("care_center", "ospace"): "care_center, 20 seeds: social spends 26.7% of its time in groups' o-spaces vs "
    "A*'s 38.4% (30% less, not 50%; the CI seeds reach 52% less)",
}

#: Hall's intimate radius (m, centre distance) of both scenes: an episode whose robot starts with
#: a person closer than this has no room to stay out of the intimate zone.
INTIMATE = 0.45


def _run(scene: str, seeds: tuple[int, ...]) -> Records:
    """Both planners on `seeds`, in this process; each record gains the closest person's centre
    distance at the start (m)."""
    out: Records = {SOCIAL: [], ASTAR: []}
    for seed in seeds:
        cfg = EvalConfig(scenario=scene, planners=[SOCIAL, ASTAR], episodes=1, seed=seed, workers=1)
        for res in iter_results(cfg):
            assert res.robot is not None and res.people is not None
            start_gap = float(((res.people[0] - res.robot[0, :2]) ** 2).sum(axis=1).min() ** 0.5)
            out[res.record["planner"]].append({**res.record, "start_person_distance": start_gap})
    return out


_CACHE: dict[tuple[str, tuple[int, ...]], Records] = {}


def records(scene: str, seeds: tuple[int, ...]) -> Records:
    """The episodes of `scene` on `seeds`, run once per test session."""
    key = (scene, seeds)
    if key not in _CACHE:
        _CACHE[key] = _run_pool(scene, seeds)
    return _CACHE[key]


def _run_pool(scene: str, seeds: tuple[int, ...]) -> Records:
    """`_run` on 2 processes, one seed per task, records in seed order."""
    import multiprocessing as mp

    ctx = mp.get_context("fork")
    with ctx.Pool(2) as pool:
        parts = pool.starmap(_run, [(scene, (s,)) for s in seeds])
    return {p: [r for part in parts for r in part[p]] for p in (SOCIAL, ASTAR)}


def mean(recs: list[dict[str, Any]], key: str) -> float:
    """Mean of the defined values of `key` (NaN when none)."""
    vals = [r[key] for r in recs if r.get(key) is not None and math.isfinite(r[key])]
    return sum(vals) / len(vals) if vals else math.nan


def _halved(key: str) -> Callable[[Records], None]:
    def check(rec: Records) -> None:
        social, astar = mean(rec[SOCIAL], key), mean(rec[ASTAR], key)
        assert astar > 0, f"plain A* has {key} = 0 on these seeds: the claim is not exercised"
        assert social <= 0.5 * astar, f"{key}: social {social:.3f} vs plain A* {astar:.3f} (claim: at most half)"

    return check


def _intimate(rec: Records) -> None:
    # Where it has room: the episode does not start with a person inside the intimate zone (the
    # care center's staff walker can spawn 0.4 m from the robot's start, seeds 8 and 18).
    roomy = [r for r in rec[SOCIAL] if r["start_person_distance"] >= INTIMATE]
    assert len(roomy) >= len(rec[SOCIAL]) // 2, "most episodes start with a person in the intimate zone"
    entered = [r["seed"] for r in roomy if r["psi_intimate"] > 0]
    assert not entered, f"social entered an intimate zone on seeds {entered}"
    astar = [r for r in rec[ASTAR] if r["start_person_distance"] >= INTIMATE]
    assert any(r["psi_intimate"] > 0 for r in astar), "plain A* never entered an intimate zone it had room to avoid"


def _personal(rec: Records) -> None:
    _halved("psi_personal")(rec)


def _interactions(rec: Records) -> None:
    for key in ("interaction_crossings_person_person", "interaction_crossings_person_object"):
        _halved(key)(rec)


def _success(rec: Records) -> None:
    rate = {p: sum(r["success"] for r in rec[p]) / len(rec[p]) for p in rec}
    assert rate[SOCIAL] >= rate[ASTAR] - 0.05, f"success: social {rate[SOCIAL]:.2f} vs plain A* {rate[ASTAR]:.2f}"


def _time(rec: Records) -> None:
    social, astar = mean(rec[SOCIAL], "time_to_goal"), mean(rec[ASTAR], "time_to_goal")
    assert social <= 1.3 * astar, f"time to goal: social {social:.1f} s vs plain A* {astar:.1f} s (claim: <= 1.3x)"


def _l_ratio(rec: Records) -> None:
    value = mean(rec[SOCIAL], "l_ratio")
    assert value >= 0.8, f"L_ratio of social: {value:.3f} (claim: >= 0.8)"


CLAIMS: dict[str, Callable[[Records], None]] = {
    "intimate": _intimate,
    "personal": _personal,
    "ospace": _halved("ospace_pct"),
    "interactions": _interactions,
    "objects": _halved("psi_objects"),
    "success": _success,
    "time": _time,
    "l_ratio": _l_ratio,
}


def _cases(full: bool) -> list[Any]:
    marks = [pytest.mark.full] if full else []
    out = []
    cases = [(scene, claim) for scene in SCENES for claim in CLAIMS] + list(EXTRA_CASES)
    for scene, claim in cases:
        m = list(marks)
        reason = KNOWN_FAILURES.get((scene, claim)) or (KNOWN_FULL_FAILURES.get((scene, claim)) if full else None)
        if reason:
            m.append(pytest.mark.xfail(strict=True, reason=reason))
        out.append(pytest.param(scene, claim, marks=m, id=f"{scene}-{claim}"))
    return out


@pytest.mark.parametrize(("scene", "claim"), _cases(full=False))
def test_claim_ci(scene: str, claim: str) -> None:
    CLAIMS[claim](records(scene, CI_SEEDS))


@pytest.mark.parametrize(("scene", "claim"), _cases(full=True))
def test_claim_full(scene: str, claim: str) -> None:
    CLAIMS[claim](records(scene, FULL_SEEDS))
