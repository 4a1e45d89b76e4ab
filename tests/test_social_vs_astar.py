"""The papers' claims about the social planner against plain A*, asserted on our measured metrics.

Seeded museum and care-center episodes, the full social planner (``social``: social A* global path,
Social Momentum near people, ORCA among robots; Daza et al. 2021 Algorithm 1) against plain A*
(``astar``), the same seeds for both. A CI-sized subset (``CI_SEEDS``) runs in ``make test``; the
full suite (``FULL_SEEDS``) is marked ``full`` (``make test-full``).

Every claim is asserted on every scene. A halving claim ("at least 50% less than plain A*") on a
scene where plain A* never does the thing on these seeds demands that the social planner never
does it either; :func:`test_claims_are_exercised` makes sure each such claim is exercised (plain A*
does it) on the scenes named in ``EXERCISED``, so the suite cannot pass vacuously.

Claims that our planner does not meet are marked ``xfail(strict=True)`` with the measured reason
(``KNOWN_FAILURES``): they are reported on every run, and the mark fails the moment the claim
starts to hold, so it cannot rot.
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
#: plain A* crosses the round table's space during its therapy.
EXTRA_CASES = (("calderita_exp1", "objects"),)
#: Episode seeds of the CI subset (``make test``; about 30 s on 2 cores).
CI_SEEDS = tuple(range(20))
#: Episode seeds of the full suite (``make test-full``).
FULL_SEEDS = tuple(range(60))

Records = dict[str, list[dict[str, Any]]]

#: Where each halving claim is exercised: the scenes whose plain A* episodes (CI seeds) cross
#: groups' o-spaces (the museum's corridor gallery talk stands on A*'s way), interaction segments
#: (between the docent and the visitor, and between them and the painting), spend time in
#: personal zones, or inside an object space while its activity is on (the museum's gallery talk,
#: the care center's physiotherapy assessment on the stretcher).
EXERCISED: dict[str, tuple[str, ...]] = {
    "personal": ("museum", "care_center"),
    "ospace": ("museum",),
    "interactions": ("museum",),
    "objects": ("museum", "care_center", "calderita_exp1"),
}

#: (scene, claim) -> why it fails on our measurements, in both suites.
KNOWN_FAILURES: dict[tuple[str, str], str] = {}

#: Failures of the full suite only (the CI seeds happen to meet the claim).
KNOWN_FULL_FAILURES: dict[tuple[str, str], str] = {}

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


def _halved(*keys: str) -> Callable[[Records], None]:
    """At most half of plain A*'s mean, for each key (none at all where plain A* has none)."""

    def check(rec: Records) -> None:
        for key in keys:
            social, astar = mean(rec[SOCIAL], key), mean(rec[ASTAR], key)
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


def _success(rec: Records) -> None:
    rate = {p: sum(r["success"] for r in rec[p]) / len(rec[p]) for p in rec}
    assert rate[SOCIAL] >= rate[ASTAR] - 0.05, f"success: social {rate[SOCIAL]:.2f} vs plain A* {rate[ASTAR]:.2f}"


def _time(rec: Records) -> None:
    social, astar = mean(rec[SOCIAL], "time_to_goal"), mean(rec[ASTAR], "time_to_goal")
    assert social <= 1.3 * astar, f"time to goal: social {social:.1f} s vs plain A* {astar:.1f} s (claim: <= 1.3x)"


def _l_ratio(rec: Records) -> None:
    value = mean(rec[SOCIAL], "l_ratio")
    assert value >= 0.8, f"L_ratio of social: {value:.3f} (claim: >= 0.8)"


#: The metrics of each halving claim.
HALVED_KEYS: dict[str, tuple[str, ...]] = {
    "personal": ("psi_personal",),
    "ospace": ("ospace_pct",),
    "interactions": ("interaction_crossings_person_person", "interaction_crossings_person_object"),
    "objects": ("psi_objects_active",),
}

CLAIMS: dict[str, Callable[[Records], None]] = {
    "intimate": _intimate,
    **{claim: _halved(*keys) for claim, keys in HALVED_KEYS.items()},
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


@pytest.mark.parametrize("claim", sorted(EXERCISED))
def test_claims_are_exercised(claim: str) -> None:
    """Plain A* does what each halving claim halves, on every scene named for it (CI seeds)."""
    for scene in EXERCISED[claim]:
        rec = records(scene, CI_SEEDS)
        for key in HALVED_KEYS[claim]:
            assert mean(rec[ASTAR], key) > 0, f"{scene}: plain A* has {key} = 0 on the CI seeds"
