"""The papers' claims about the social planner against plain A*, asserted as stated, on the test split.

Seeded episodes of the full social planner (``social``: social A* global path, Social Momentum near
people, ORCA among robots; Daza et al. 2021 Algorithm 1) against plain A* (``astar``) and against the
non-social baseline that avoids collisions (``astar_orca``: the plain A* path followed with ORCA,
people not reciprocating), the same seeds for all, on three scene sets: the museum, the care
center, and generated scenes (``generated/<seed>``, one episode each). Seeds come only from the test split of
:mod:`proxemic.splits` (the constants and scene edits were tuned on the tuning split; the module
says which on which); :func:`test_splits_are_disjoint` fails if the splits overlap.

The claims, each checked on every scene set:

- intimate zone: no entry, the zone measured from the person's body edge to the robot's body edge
  (0.45 m of clearance, ``gap_person_min``), on the episodes that start with that room (no person
  within 0.45 m of the robot's body at the start); the centre-distance reading is reported too;
- personal-zone time in seconds, summed over the episodes, at least 50% less than plain A*'s;
- o-space entries and interaction crossings (person-person and person-object), counted, at least
  50% fewer;
- time inside an active object space (Calderita's Psi(Objects)), in seconds, at least 80% less;
- social's collision rate at most plain A*'s and at most 2%; its timeout rate at most 5%; its
  success rate within 5 points of plain A*'s (both ways);
- time to goal at most 1.3x plain A*'s and L_ratio at least 0.8, over the episodes both planners
  complete (paired), with the 95% bootstrap interval in the message.

Every claim that compares social with a baseline (the reductions, collisions, success, time) is
checked against ``astar_orca`` as well (test ids ``...-vs-astar_orca``): "social halves
personal-zone time" means something only against a baseline that also arrives. The claims about
social alone (intimate zone, timeouts, L_ratio) are checked once.

The yielding claims (``YIELD_CLAIMS``, test ids ``test_yield_claim_*``) hold social to a polite
person's standard against ``astar_orca``: no intimate-zone entry the robot causes, never at fault in
a contact, at most half the baseline's robot-caused personal-zone seconds, success at least the
baseline's with at most 2% timeouts, and the paired time to goal's 95% upper bound at most 1.3.

Each paper's own planner (``daza2021``, ``sousa2022``, ``calderita``) is held to the claims its
paper makes against the classical planner (``PAPER_CLAIMS``, test ids ``<planner>-<scene>-<claim>``),
at the same strength and on the same episodes.

Every claim about something plain A* does (intimate entries, zone time, entries, crossings, object
time) must be exercised in every scene set: :func:`test_claims_are_exercised` fails if plain A*
never does it there, so no claim passes vacuously.

A claim that does not hold on the test split is a strict xfail stating the measured figure
(``KNOWN_FAILURES``): it is never weakened, and the mark fails the moment the claim starts to hold.

``make test`` runs the CI sets (``CI_EPISODE_SEEDS`` per bundled scene, ``CI_SCENE_SEEDS``
generated scenes); ``make test-full`` (marker ``full``) runs the whole test split.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from pathlib import Path
from typing import Any

import pytest

from proxemic import scenarios, splits
from proxemic.evaluation import EvalConfig, iter_results, paired_ratio
from test_record_invariants import CROWDS, replay_scene

SOCIAL, ASTAR, ASTAR_ORCA = "social", "astar", "astar_orca"
#: The baselines the claims compare social with; every planner run on each seed.
BASELINES = (ASTAR, ASTAR_ORCA)
#: The papers' own planners and the claims each paper makes against the classical path planner,
#: asserted against plain A* at the strength above:
#: - Daza et al. 2021 Sect. 5: "the intimate zones of people will never be invaded by robots", and
#:   "the modified path is at least 80% similar to the A* path" (L_ratio >= 0.8, Table 2);
#: - Sousa et al. 2022 Sect. 4.5: the A* path crosses "the proxemics space for groups and for a
#:   single person", theirs "respects groups and individual space" (personal-zone time and o-space
#:   entries);
#: - Calderita et al. 2020 Sect. 6, Tables 1-2: the social path keeps out of people's personal
#:   spaces and of the objects' interaction spaces in use, where the classical path does not
#:   (personal-zone time and active object-space time).
PAPER_CLAIMS: dict[str, tuple[str, ...]] = {
    "daza2021": ("intimate", "l_ratio"),
    "sousa2022": ("personal_seconds", "ospace_entries"),
    "calderita": ("personal_seconds", "active_object_seconds"),
}
PLANNERS = (SOCIAL, *BASELINES, *PAPER_CLAIMS)
#: How the messages name each baseline.
LABELS = {ASTAR: "plain A*", ASTAR_ORCA: "astar_orca"}
#: The bundled scenes of the claims.
SCENES = ("museum", "care_center")
#: The scene set of generated scenes: ``generated/<seed>`` with these parameters (a conversation
#: group on the robot's shortest way, 2.5 people per 100 m^2; chosen on tuning scene seeds 0-29).
GENERATED = "generated"
GENERATED_QUERY = "?encounters=1&density=2.5"
SCENE_SETS = (*SCENES, GENERATED)
#: Episode seeds per bundled scene in ``make test`` (a fixed prefix of the test split).
CI_EPISODE_SEEDS = splits.TEST_EPISODE_SEEDS[:20]
#: Generated scenes in ``make test`` (a fixed prefix of the test split).
CI_SCENE_SEEDS = splits.TEST_SCENE_SEEDS[:50]
#: The whole test split (``make test-full``).
FULL_EPISODE_SEEDS = splits.TEST_EPISODE_SEEDS
FULL_SCENE_SEEDS = splits.TEST_SCENE_SEEDS

#: Clearance of the intimate zone (m): Hall's 0.45 m, here from body edge to body edge.
INTIMATE = 0.45

Records = dict[str, list[dict[str, Any]]]


def _episodes(name: str, seed: int, planners: tuple[str, ...] = PLANNERS) -> Records:
    """`planners` on scenario `name` with episode seed `seed`, in this process; each record gains
    ``duration`` (s) and the closest person's body-edge gap at the start (``start_gap``, m; people
    the scenario file does not list, such as replayed ones, count with a 0.2 m body)."""
    core, desc = scenarios.load(name)
    radius = desc["robots"][0]["radius"]
    out: Records = {p: [] for p in planners}
    cfg = EvalConfig(scenario=name, planners=list(planners), episodes=1, seed=seed, workers=1)
    for res in iter_results(cfg):
        if res.robot is None or res.people is None:
            # A multi-robot scene keeps the tracks of its first robot only: the others' start gap
            # is unknown (NaN: never "roomy", so they stay out of the intimate-zone claims).
            gaps = [math.nan]
        else:
            radii = [p["radius"] for p in desc["persons"]]
            radii += [0.2] * (len(res.people[0]) - len(radii))
            gaps = [
                math.dist(tuple(q), tuple(res.robot[0, :2])) - rp - radius
                for q, rp in zip(res.people[0], radii, strict=False)
            ]
        out[res.record["planner"]].append(
            {**res.record, "duration": res.record["steps"] * core.control_dt, "start_gap": min(gaps, default=math.inf)}
        )
    return out


def _run(scene: str, seeds: tuple[int, ...]) -> Records:
    """The planners on `seeds` of `scene` (for generated scenes: scene `generated/<seed>`,
    episode seed `seed`), in this process (:func:`_episodes`)."""
    out: Records = {p: [] for p in PLANNERS}
    for seed in seeds:
        name = f"generated/{seed}{GENERATED_QUERY}" if scene == GENERATED else scene
        for planner, recs in _episodes(name, seed, PLANNERS).items():  # the module's list now (a tuner may set it)
            out[planner].extend(recs)
    return out


_CACHE: dict[tuple[str, tuple[int, ...]], Records] = {}


def records(scene: str, seeds: tuple[int, ...]) -> Records:
    """The episodes of `scene` on `seeds`, run once per test session (2 processes)."""
    key = (scene, seeds)
    if key not in _CACHE:
        import multiprocessing as mp

        with mp.get_context("fork").Pool(2) as pool:
            parts = pool.starmap(_run, [(scene, (s,)) for s in seeds])
        _CACHE[key] = {p: [r for part in parts for r in part[p]] for p in PLANNERS}
    return _CACHE[key]


# --- the readings of each claim ------------------------------------------------------------------


def _seconds(r: dict[str, Any], pct_key: str) -> float:
    """Seconds of an episode spent where the percentage-of-instants metric `pct_key` counts."""
    v = r.get(pct_key)
    return 0.0 if v is None or not math.isfinite(v) else v / 100.0 * r["duration"]


def _count(r: dict[str, Any], key: str) -> float:
    v = r.get(key)
    return 0.0 if v is None else float(v)


#: Per-episode amount of each reduction claim: (reading, the share it must cut at least).
REDUCTIONS: dict[str, tuple[Callable[[dict[str, Any]], float], float]] = {
    "personal_seconds": (lambda r: _seconds(r, "psi_personal"), 0.5),
    "ospace_entries": (lambda r: _count(r, "ospace_entries"), 0.5),
    "interaction_crossings": (
        lambda r: _count(r, "interaction_crossings_person_person") + _count(r, "interaction_crossings_person_object"),
        0.5,
    ),
    "active_object_seconds": (lambda r: _seconds(r, "psi_objects_active"), 0.8),
}


def roomy(recs: list[dict[str, Any]]) -> list[dict[str, Any]]:
    """The episodes that start with room to stay out of the intimate zone (body-edge gap >= 0.45 m)."""
    return [r for r in recs if r["start_gap"] >= INTIMATE]


def intimate_entries(recs: list[dict[str, Any]]) -> list[int]:
    """Seeds of the roomy episodes with a body-edge gap below 0.45 m at some instant."""
    return [r["seed"] for r in roomy(recs) if r["gap_person_min"] is not None and r["gap_person_min"] < INTIMATE]


def centre_entries(recs: list[dict[str, Any]]) -> list[int]:
    """Seeds of the roomy episodes with a centre distance below 0.45 m (the old, weaker reading)."""
    return [r["seed"] for r in roomy(recs) if r["dist_person_min"] is not None and r["dist_person_min"] < INTIMATE]


def _intimate(rec: Records, baseline: str = ASTAR, subject: str = SOCIAL) -> None:
    room = roomy(rec[subject])
    assert len(room) >= len(rec[subject]) // 2, "most episodes start with a person within 0.45 m"
    entered = intimate_entries(rec[subject])
    assert not entered, (
        f"{subject} came within 0.45 m body edge to body edge in {len(entered)}/{len(room)} episodes "
        f"(seeds {entered}); by centre distance in {len(centre_entries(rec[subject]))}"
    )


def _reduction(name: str) -> Callable[[Records], None]:
    reading, cut = REDUCTIONS[name]

    def check(rec: Records, baseline: str = ASTAR, subject: str = SOCIAL) -> None:
        ours, base = sum(map(reading, rec[subject])), sum(map(reading, rec[baseline]))
        assert ours <= (1 - cut) * base, (
            f"{name}: {subject} {ours:.2f} vs {LABELS[baseline]} {base:.2f} (claim: at least {cut:.0%} less)"
        )

    return check


def rate(recs: list[dict[str, Any]], key: str) -> float:
    """Share of episodes with `key` true."""
    return sum(bool(r.get(key)) for r in recs) / len(recs)


def _collisions(rec: Records, baseline: str = ASTAR, subject: str = SOCIAL) -> None:
    s, a = rate(rec[subject], "collision"), rate(rec[baseline], "collision")
    assert s <= a and s <= 0.02, (
        f"collision rate: {subject} {s:.1%} vs {LABELS[baseline]} {a:.1%} (claim: <= the baseline's and <= 2%)"
    )


def _timeouts(rec: Records, baseline: str = ASTAR, subject: str = SOCIAL) -> None:
    s = rate(rec[subject], "timeout")
    assert s <= 0.05, f"timeout rate of {subject}: {s:.1%} (claim: <= 5%)"


def _success(rec: Records, baseline: str = ASTAR, subject: str = SOCIAL) -> None:
    s, a = rate(rec[subject], "success"), rate(rec[baseline], "success")
    assert s >= a - 0.05, f"success: {subject} {s:.1%} vs {LABELS[baseline]} {a:.1%} (claim: at most 5 points below)"


def _paired(rec: Records, key: str, baseline: str = ASTAR, subject: str = SOCIAL) -> tuple[list[float], list[float]]:
    """`key` of `subject` and of `baseline` over the episodes both complete (same scene and seed)."""
    astar = {(r["scenario"], r["seed"]): r for r in rec[baseline] if r["success"]}
    pairs = [
        (r, astar[(r["scenario"], r["seed"])])
        for r in rec[subject]
        if r["success"] and (r["scenario"], r["seed"]) in astar
    ]
    ok = [(x[key], y[key]) for x, y in pairs if x.get(key) is not None and y.get(key) is not None]
    return [float(x) for x, _ in ok], [float(y) for _, y in ok]


def _time(rec: Records, baseline: str = ASTAR, subject: str = SOCIAL) -> None:
    s, a = _paired(rec, "time_to_goal", baseline, subject)
    assert len(s) >= 2, f"only {len(s)} episodes both planners complete"
    r, lo, hi = paired_ratio(s, a)
    print(f"paired time to goal ratio {subject}/{baseline}: {r:.3f} [{lo:.3f}, {hi:.3f}] over {len(s)} pairs")
    assert r <= 1.3, (
        f"paired time to goal: {subject}/{baseline} {r:.3f} [95% CI {lo:.3f}, {hi:.3f}], {len(s)} pairs (claim: <= 1.3)"
    )


def _l_ratio(rec: Records, baseline: str = ASTAR, subject: str = SOCIAL) -> None:
    s, _a = _paired(rec, "l_ratio", ASTAR, subject)
    assert len(s) >= 2, f"only {len(s)} episodes both planners complete"
    r, lo, hi = paired_ratio(s, [1.0] * len(s))
    print(f"paired L_ratio of {subject}: {r:.3f} [{lo:.3f}, {hi:.3f}] over {len(s)} pairs")
    assert r >= 0.8, (
        f"L_ratio of {subject} over the paired episodes: {r:.3f} [95% CI {lo:.3f}, {hi:.3f}] (claim: >= 0.8)"
    )


CLAIMS: dict[str, Callable[..., None]] = {
    "intimate": _intimate,
    **{name: _reduction(name) for name in REDUCTIONS},
    "collisions": _collisions,
    "timeouts": _timeouts,
    "success": _success,
    "time": _time,
    "l_ratio": _l_ratio,
}

#: The claims that compare social with a baseline: checked against every baseline of ``BASELINES``.
RELATIVE = (*REDUCTIONS, "collisions", "success", "time")

#: (scene set, claim) -> the measured figure, for claims that do not hold on the test split (CI sets).
KNOWN_FAILURES: dict[tuple[str, str], str] = {
    ("museum", "intimate"): "social within 0.45 m body edge to body edge in 3/20 episodes (seeds 1005, 1009, 1018; "
    "centre reading: 0/20), all person-caused: people squeezing past the waiting robot in a doorway (robot-caused "
    "0/20)",
}
#: The same for the full test split.
KNOWN_FULL_FAILURES: dict[tuple[str, str], str] = {
    ("museum", "intimate"): "social within 0.45 m body edge to body edge in 7/60 episodes (seeds 1005, 1009, 1018, "
    "1028, 1036, 1043, 1045; centre reading: 0/60); robot-caused in 1/60 (seed 1036), the others people squeezing "
    "past the waiting robot",
}
#: (scene set, claim) -> the measured figure, for claims against ``astar_orca`` that do not hold on
#: the test split (CI sets).
KNOWN_FAILURES_VS_ORCA: dict[tuple[str, str], str] = {}
#: The same for the full test split.
KNOWN_FULL_FAILURES_VS_ORCA: dict[tuple[str, str], str] = {}
#: (scene set, claim) -> the measured figure, where plain A* never does what the claim cuts (none:
#: the care center's conversation on the robot's way in the physical therapy room, placed on tuning
#: seeds, exercises its o-space and interaction claims).
NOT_EXERCISED: dict[tuple[str, str], str] = {}
#: The same for ``astar_orca``.
NOT_EXERCISED_VS_ORCA: dict[tuple[str, str], str] = {}


def _seeds(scene: str, full: bool) -> tuple[int, ...]:
    if scene == GENERATED:
        return FULL_SCENE_SEEDS if full else CI_SCENE_SEEDS
    return FULL_EPISODE_SEEDS if full else CI_EPISODE_SEEDS


def _cases(full: bool) -> list[Any]:
    out = []
    for baseline in BASELINES:
        known = {
            (ASTAR, False): KNOWN_FAILURES,
            (ASTAR, True): KNOWN_FULL_FAILURES,
            (ASTAR_ORCA, False): KNOWN_FAILURES_VS_ORCA,
            (ASTAR_ORCA, True): KNOWN_FULL_FAILURES_VS_ORCA,
        }[(baseline, full)]
        for scene in SCENE_SETS:
            for claim in CLAIMS if baseline == ASTAR else RELATIVE:
                m = [pytest.mark.full] if full else []
                if reason := known.get((scene, claim)):
                    m.append(pytest.mark.xfail(strict=True, reason=reason))
                suffix = "" if baseline == ASTAR else f"-vs-{baseline}"
                out.append(pytest.param(scene, claim, baseline, marks=m, id=f"{scene}-{claim}{suffix}"))
    return out


@pytest.mark.parametrize(("scene", "claim", "baseline"), _cases(full=False))
def test_claim_ci(scene: str, claim: str, baseline: str) -> None:
    CLAIMS[claim](records(scene, _seeds(scene, False)), baseline)


@pytest.mark.parametrize(("scene", "claim", "baseline"), _cases(full=True))
def test_claim_full(scene: str, claim: str, baseline: str) -> None:
    CLAIMS[claim](records(scene, _seeds(scene, True)), baseline)


#: (scene set, paper planner, claim) -> the measured figure, for paper claims that do not hold on the
#: test split (CI sets, and the whole split).
KNOWN_PAPER_FAILURES: dict[tuple[str, str, str], str] = {
    ("museum", "daza2021", "intimate"): "daza2021 within 0.45 m body edge to body edge in 20/20 episodes (centre "
    "reading: 0/20)",
    ("care_center", "daza2021", "intimate"): "daza2021 within 0.45 m body edge to body edge in 20/20 episodes "
    "(centre reading: 0/20)",
    (GENERATED, "daza2021", "intimate"): "daza2021 within 0.45 m body edge to body edge in 15/50 scenes (centre "
    "reading: 0/50)",
    ("care_center", "sousa2022", "personal_seconds"): "personal-zone time: sousa2022 65.49 s vs plain A* 116.77 s "
    "(44% less, claim 50% less)",
    (GENERATED, "sousa2022", "personal_seconds"): "personal-zone time: sousa2022 62.86 s vs plain A* 69.61 s (10% "
    "less, claim 50% less)",
    ("museum", "calderita", "personal_seconds"): "personal-zone time: calderita 153.57 s vs plain A* 168.71 s (9% "
    "less, claim 50% less)",
    (GENERATED, "calderita", "active_object_seconds"): "active object-space time: calderita 11.76 s vs plain A* "
    "10.17 s (more, claim 80% less)",
}
KNOWN_FULL_PAPER_FAILURES: dict[tuple[str, str, str], str] = {
    ("museum", "daza2021", "intimate"): "daza2021 within 0.45 m body edge to body edge in 60/60 episodes (centre "
    "reading: 0/60)",
    ("care_center", "daza2021", "intimate"): "daza2021 within 0.45 m body edge to body edge in 60/60 episodes "
    "(centre reading: 0/60)",
    (GENERATED, "daza2021", "intimate"): "daza2021 within 0.45 m body edge to body edge in 19/60 scenes (centre "
    "reading: 0/60)",
    ("care_center", "sousa2022", "personal_seconds"): "personal-zone time: sousa2022 190.68 s vs plain A* 346.32 s "
    "(45% less, claim 50% less)",
    (GENERATED, "sousa2022", "personal_seconds"): "personal-zone time: sousa2022 94.30 s vs plain A* 90.23 s (5% "
    "more, claim 50% less)",
    ("museum", "calderita", "personal_seconds"): "personal-zone time: calderita 507.58 s vs plain A* 457.01 s (11% "
    "more, claim 50% less)",
    (GENERATED, "calderita", "active_object_seconds"): "active object-space time: calderita 15.86 s vs plain A* "
    "10.17 s (more, claim 80% less)",
}


def _paper_cases(full: bool) -> list[Any]:
    known = KNOWN_FULL_PAPER_FAILURES if full else KNOWN_PAPER_FAILURES
    out = []
    for planner, claims in PAPER_CLAIMS.items():
        for scene in SCENE_SETS:
            for claim in claims:
                m = [pytest.mark.full] if full else []
                if reason := known.get((scene, planner, claim)):
                    m.append(pytest.mark.xfail(strict=True, reason=reason))
                out.append(pytest.param(scene, claim, planner, marks=m, id=f"{planner}-{scene}-{claim}"))
    return out


@pytest.mark.parametrize(("scene", "claim", "planner"), _paper_cases(full=False))
def test_paper_claim_ci(scene: str, claim: str, planner: str) -> None:
    """Each paper's own planner against plain A*, on the claims its paper makes (``PAPER_CLAIMS``)."""
    CLAIMS[claim](records(scene, _seeds(scene, False)), ASTAR, planner)


@pytest.mark.parametrize(("scene", "claim", "planner"), _paper_cases(full=True))
def test_paper_claim_full(scene: str, claim: str, planner: str) -> None:
    CLAIMS[claim](records(scene, _seeds(scene, True)), ASTAR, planner)


# --- the yielding claims: social against the collision-free baseline, at their strength ----------------
#
# A polite robot gives way: whatever the people do, the robot itself never moves into anyone's
# intimate zone nor into a contact, halves the personal-zone time it causes, and arrives as often
# and nearly as fast as ``astar_orca``. "Robot-caused" is the rule of ``collisions_robot_fault``: the
# robot's velocity toward the person above 0.05 m/s at that instant (``docs/metrics.md``, who
# approached whom).


def _robot_intimate(rec: Records, baseline: str = ASTAR_ORCA, subject: str = SOCIAL) -> None:
    room = roomy(rec[subject])
    entered = [
        (r["seed"], int(r["intimate_gap_entries_robot_caused"]))
        for r in room
        if r.get("intimate_gap_entries_robot_caused")
    ]
    assert not entered, (
        f"{subject} moved into someone's intimate zone (body gap < 0.45 m) in {len(entered)}/{len(room)} episodes, "
        f"{sum(n for _, n in entered)} entries (seed, entries: {entered})"
    )


def _never_at_fault(rec: Records, baseline: str = ASTAR_ORCA, subject: str = SOCIAL) -> None:
    fault = [(r["seed"], int(r["collisions_robot_fault"])) for r in rec[subject] if r.get("collisions_robot_fault")]
    assert not fault, (
        f"{subject} at fault in a contact in {len(fault)}/{len(rec[subject])} episodes (seed, events: {fault})"
    )


def _robot_personal(rec: Records, baseline: str = ASTAR_ORCA, subject: str = SOCIAL) -> None:
    def total(p: str) -> float:
        return sum(_count(r, "personal_gap_time_robot_caused") for r in rec[p])

    ours, base = total(subject), total(baseline)
    assert ours <= 0.5 * base, (
        f"robot-caused personal-zone time: {subject} {ours:.2f} s vs {LABELS[baseline]} {base:.2f} s "
        f"({1 - ours / base if base else 0:.0%} less; claim: at least 50% less)"
    )


def _success_at_least(rec: Records, baseline: str = ASTAR_ORCA, subject: str = SOCIAL) -> None:
    s, a = rate(rec[subject], "success"), rate(rec[baseline], "success")
    t = rate(rec[subject], "timeout")
    assert s >= a and t <= 0.02, (
        f"success: {subject} {s:.1%} vs {LABELS[baseline]} {a:.1%}, timeouts {t:.1%} "
        "(claim: success at least the baseline's, timeouts at most 2%)"
    )


def _time_upper(rec: Records, baseline: str = ASTAR_ORCA, subject: str = SOCIAL) -> None:
    s, a = _paired(rec, "time_to_goal", baseline, subject)
    assert len(s) >= 2, f"only {len(s)} episodes both planners complete"
    r, lo, hi = paired_ratio(s, a)
    assert hi <= 1.3, (
        f"paired time to goal: {subject}/{LABELS[baseline]} {r:.3f} [95% CI {lo:.3f}, {hi:.3f}], {len(s)} pairs "
        "(claim: upper bound <= 1.3)"
    )


def _recovery_keeps_spaces(rec: Records, baseline: str = ASTAR_ORCA, subject: str = SOCIAL) -> None:
    entered = [
        (r["seed"], int(r["recovery_ospace_entries"]), int(r["recovery_object_entries"]))
        for r in rec[subject]
        if r["recovery_ospace_entries"] or r["recovery_object_entries"]
    ]
    seconds = sum(float(r["recovery_time"]) for r in rec[subject])
    assert not entered, (
        f"{subject} entered an o-space or an active object space while recovering in {len(entered)}/"
        f"{len(rec[subject])} episodes ({seconds:.1f} s in recovery; seed, o-space entries, object entries: "
        f"{entered})"
    )


#: The yielding claims, each asserted for ``social`` against ``astar_orca`` on every scene set.
YIELD_CLAIMS: dict[str, Callable[..., None]] = {
    "robot_caused_intimate": _robot_intimate,
    "never_at_fault": _never_at_fault,
    "robot_caused_personal_seconds": _robot_personal,
    "success_and_timeouts": _success_at_least,
    "time_upper_bound": _time_upper,
    "recovery_keeps_spaces": _recovery_keeps_spaces,
}
#: (scene set, claim) -> the measured figure, for yielding claims that do not hold on the test split
#: (CI sets).
KNOWN_YIELD_FAILURES: dict[tuple[str, str], str] = {
    ("museum", "robot_caused_personal_seconds"): "robot-caused personal-zone time: social 362.8 s vs astar_orca "
    "492.7 s (26% less, claim 50%)",
    ("care_center", "robot_caused_personal_seconds"): "robot-caused personal-zone time: social 158.7 s vs "
    "astar_orca 186.5 s (15% less, claim 50%)",
    (GENERATED, "robot_caused_personal_seconds"): "robot-caused personal-zone time: social 106.8 s vs astar_orca "
    "138.0 s (23% less, claim 50%)",
}
#: The same for the full test split.
KNOWN_FULL_YIELD_FAILURES: dict[tuple[str, str], str] = {
    ("museum", "robot_caused_intimate"): "social moved into an intimate zone in 1/60 episodes (seed 1036), one entry",
    ("museum", "robot_caused_personal_seconds"): "robot-caused personal-zone time: social 1054.6 s vs astar_orca "
    "1451.0 s (27% less, claim 50%)",
    ("care_center", "robot_caused_personal_seconds"): "robot-caused personal-zone time: social 484.7 s vs "
    "astar_orca 531.4 s (9% less, claim 50%)",
    (GENERATED, "robot_caused_personal_seconds"): "robot-caused personal-zone time: social 129.7 s vs astar_orca "
    "174.4 s (26% less, claim 50%)",
}


def _yield_cases(full: bool) -> list[Any]:
    known = KNOWN_FULL_YIELD_FAILURES if full else KNOWN_YIELD_FAILURES
    out = []
    for scene in SCENE_SETS:
        for claim in YIELD_CLAIMS:
            m = [pytest.mark.full] if full else []
            if reason := known.get((scene, claim)):
                m.append(pytest.mark.xfail(strict=True, reason=reason))
            out.append(pytest.param(scene, claim, marks=m, id=f"{scene}-{claim}"))
    return out


@pytest.mark.parametrize(("scene", "claim"), _yield_cases(full=False))
def test_yield_claim_ci(scene: str, claim: str) -> None:
    """``social`` gives way: the yielding claims against ``astar_orca`` (``YIELD_CLAIMS``), CI sets."""
    YIELD_CLAIMS[claim](records(scene, _seeds(scene, False)))


@pytest.mark.parametrize(("scene", "claim"), _yield_cases(full=True))
def test_yield_claim_full(scene: str, claim: str) -> None:
    YIELD_CLAIMS[claim](records(scene, _seeds(scene, True)))


#: Scene seeds per Francis archetype for the yielding claim (a prefix of the test split's scene
#: seeds in ``make test``, all of them in ``make test-full``); each archetype's scene of that seed is
#: run with the same episode seed.
CI_FRANCIS_SEEDS = splits.TEST_SCENE_SEEDS[:10]
FULL_FRANCIS_SEEDS = splits.TEST_SCENE_SEEDS


def _run_francis(archetype: str, seed: int) -> Records:
    """``social`` and ``astar_orca`` on the scene of `archetype` drawn with `seed`, every robot."""
    from proxemic import francis2023

    return _episodes(francis2023.scenario_name(archetype, seed=seed), seed, (SOCIAL, ASTAR_ORCA))


_FRANCIS: dict[tuple[int, ...], dict[str, Records]] = {}


def francis_records(seeds: tuple[int, ...]) -> dict[str, Records]:
    """Every archetype's episodes on `seeds`, by archetype, run once per test session (2 processes)."""
    if seeds not in _FRANCIS:
        import multiprocessing as mp

        from proxemic import francis2023

        jobs = [(a, s) for a in francis2023.ARCHETYPES for s in seeds]
        with mp.get_context("fork").Pool(2) as pool:
            parts = pool.starmap(_run_francis, jobs)
        by: dict[str, Records] = {a: {SOCIAL: [], ASTAR_ORCA: []} for a in francis2023.ARCHETYPES}
        for (a, _), part in zip(jobs, parts, strict=True):
            for planner, recs in part.items():
                by[a][planner].extend(recs)
        _FRANCIS[seeds] = by
    return _FRANCIS[seeds]


#: archetype -> the measured figure, for Francis archetypes where social's success or timeouts
#: miss the yielding claim (CI seeds).
KNOWN_FRANCIS_FAILURES: dict[str, str] = {
    "dense_crowd": "social succeeds in 10% (astar_orca 100%), times out in 90% (seeds 10000-10009): no opening "
    "with a 0.45 m gap on both sides in a crowd of at least 1 person/m^2 (docs/planners.md)",
    "pedestrian_obstruction": "social succeeds in 90% (astar_orca 100%), times out in 10% (seed 10000; 10/10 on "
    "tuning seeds 0-9)",
    "perpendicular_traffic": "social succeeds in 30% (astar_orca 100%), times out in 70% (seeds 10000-10003, "
    "10005, 10006, 10008). Measured cause: the band a walker's required gap closes across the robot's line "
    "(+-1.3 m: 0.45 m + 0.4 s x speed, plus both radii) was free of people in 0-17% of each episode, at most 2.5 s "
    "at a time, while crossing it and both lanes (3.9 m at 0.55 m/s) takes about 7 s: with people predicted at "
    "constant velocity only people who give way let it cross",
}
#: The same on the whole test split.
KNOWN_FULL_FRANCIS_FAILURES: dict[str, str] = {
    "dense_crowd": "social succeeds in 6.7% (astar_orca 100%), times out in 93.3% (60 seeds)",
    "pedestrian_obstruction": "social succeeds in 98.3% (astar_orca 100%), times out in 1.7% (60 seeds)",
    "entering_elevator": "social succeeds in 91.7% (astar_orca 100%), times out in 8.3% (60 seeds)",
    "parallel_traffic": "social succeeds in 98.3% (astar_orca 100%), times out in 1.7% (60 seeds)",
    "perpendicular_traffic": "social succeeds in 36.7% (astar_orca 100%), times out in 63.3% (60 seeds)",
}


def _francis_cases(full: bool) -> list[Any]:
    from proxemic import francis2023

    known = KNOWN_FULL_FRANCIS_FAILURES if full else KNOWN_FRANCIS_FAILURES
    out = []
    for a in francis2023.ARCHETYPES:
        m = [pytest.mark.full] if full else []
        if reason := known.get(a):
            m.append(pytest.mark.xfail(strict=True, reason=reason))
        out.append(pytest.param(a, marks=m, id=a))
    return out


@pytest.mark.parametrize("archetype", _francis_cases(full=False))
def test_yield_success_in_every_francis_archetype_ci(archetype: str) -> None:
    """In every Francis archetype social succeeds at least as often as astar_orca, with at most 2%
    timeouts: a narrow hallway is passed by stepping aside or waiting, not by timing out."""
    YIELD_CLAIMS["success_and_timeouts"](francis_records(CI_FRANCIS_SEEDS)[archetype])


@pytest.mark.parametrize("archetype", _francis_cases(full=True))
def test_yield_success_in_every_francis_archetype_full(archetype: str) -> None:
    YIELD_CLAIMS["success_and_timeouts"](francis_records(FULL_FRANCIS_SEEDS)[archetype])


#: The recorded crowds (``../shared/data/recorded_crowds``, never bundled, never tuned on) replayed
#: with everyone reacting within 1.5 m of a robot: each recording from each start time, for
#: ``REPLAY_WINDOW`` seconds, the robot crossing the recording's area through its middle from west
#: to east (``test_record_invariants.replay_scene``; ``make test-full``).
RECORDINGS = ("eth", "hotel", "univ", "zara1", "zara2")
REPLAY_T0 = (0.0, 60.0, 120.0)
REPLAY_WINDOW = 90.0
REPLAY_REACT = 1.5


_REPLAYS: list[Records] = []


def replay_records() -> Records:
    """``social`` and ``astar_orca`` on every replay window, run once per test session (2 processes)."""
    if not _REPLAYS:
        import multiprocessing as mp
        import tempfile

        folder = Path(tempfile.mkdtemp(prefix="proxemic-replays-"))
        names = [str(replay_scene(folder, n, t0, REPLAY_REACT, REPLAY_WINDOW)) for n in RECORDINGS for t0 in REPLAY_T0]
        with mp.get_context("fork").Pool(2) as pool:
            parts = pool.starmap(_episodes, [(n, 0, (SOCIAL, ASTAR_ORCA)) for n in names])
        _REPLAYS.append({p: [r for part in parts for r in part[p]] for p in (SOCIAL, ASTAR_ORCA)})
    return _REPLAYS[0]


#: claim -> the measured figure, for yielding claims that do not hold on the replays.
KNOWN_REPLAY_FAILURES: dict[str, str] = {
    "robot_caused_intimate": "social moved into an intimate zone in 1/15 windows, one entry",
    "robot_caused_personal_seconds": "robot-caused personal-zone time: social 84.6 s vs astar_orca 111.0 s (24% "
    "less, claim 50%)",
    "time_upper_bound": "paired time to goal social/astar_orca 1.410 [95% CI 1.206, 1.644] over 15 pairs",
}


def _replay_cases() -> list[Any]:
    out = []
    for claim in YIELD_CLAIMS:
        m = [pytest.mark.full, pytest.mark.skipif(not (CROWDS / "eth.csv").is_file(), reason="no recordings here")]
        if reason := KNOWN_REPLAY_FAILURES.get(claim):
            m.append(pytest.mark.xfail(strict=True, reason=reason))
        out.append(pytest.param(claim, marks=m, id=claim))
    return out


#: A witness scene for the recovery claim (tests/data): a baseline that keeps to its path stalls
#: at a person in a doorway and its recovery path crosses a conversation's o-space. On the test
#: split no baseline recovers into an o-space any more (astar_orca never recovers in the museum
#: since standing people near a wall stay put).
RECOVERY_WITNESS = Path(__file__).with_name("data") / "recovery_through_a_conversation.toml"


def test_recovery_claim_can_fail_and_holds_on_the_witness_scene() -> None:
    """``recovery_keeps_spaces`` can fail: ``astar_orca`` enters the conversation's o-space while
    recovering on the witness scene; ``social`` recovers there too, keeping out of it."""
    rec = _episodes(str(RECOVERY_WITNESS), 0, (SOCIAL, ASTAR_ORCA))
    baseline = rec[ASTAR_ORCA][0]
    assert baseline["recovery_time"] > 0 and baseline["recovery_ospace_entries"] > 0, baseline
    with pytest.raises(AssertionError, match="while recovering"):
        _recovery_keeps_spaces(rec, subject=ASTAR_ORCA)
    assert rec[SOCIAL][0]["recovery_time"] > 0
    _recovery_keeps_spaces(rec)


def test_recovery_claim_is_exercised() -> None:
    """``social`` recovers in the Francis archetypes (CI seeds), and ``recovery_keeps_spaces`` holds there."""
    francis = francis_records(CI_FRANCIS_SEEDS)
    assert sum(r["recovery_time"] for rec in francis.values() for r in rec[SOCIAL]) > 0
    for rec in francis.values():
        _recovery_keeps_spaces(rec)


@pytest.mark.parametrize("claim", _replay_cases())
def test_yield_claim_on_recorded_crowds(claim: str) -> None:
    """The yielding claims among real pedestrians (ETH and UCY replayed, reacting within 1.5 m)."""
    YIELD_CLAIMS[claim](replay_records())


def _exercised_cases() -> list[Any]:
    out = []
    for baseline, not_exercised in ((ASTAR, NOT_EXERCISED), (ASTAR_ORCA, NOT_EXERCISED_VS_ORCA)):
        for scene in SCENE_SETS:
            for claim in ("intimate", *REDUCTIONS) if baseline == ASTAR else REDUCTIONS:
                reason = not_exercised.get((scene, claim))
                m = [pytest.mark.xfail(strict=True, reason=reason)] if reason else []
                suffix = "" if baseline == ASTAR else f"-{baseline}"
                out.append(pytest.param(scene, claim, baseline, marks=m, id=f"{scene}-{claim}{suffix}"))
    return out


@pytest.mark.parametrize(("scene", "claim", "baseline"), _exercised_cases())
def test_claims_are_exercised(scene: str, claim: str, baseline: str) -> None:
    """Each baseline does what each claim forbids or cuts, at least once, in every scene set (CI sets)."""
    rec = records(scene, _seeds(scene, False))
    if claim == "intimate":
        assert intimate_entries(rec[baseline]), (
            f"{scene}: {LABELS[baseline]} never came within 0.45 m of a body it had room to avoid"
        )
    else:
        total = sum(map(REDUCTIONS[claim][0], rec[baseline]))
        assert total > 0, f"{scene}: {LABELS[baseline]} has no {claim}"


def test_splits_are_disjoint() -> None:
    splits.check_disjoint()
    assert set(CI_EPISODE_SEEDS) <= set(splits.TEST_EPISODE_SEEDS)
    assert set(CI_SCENE_SEEDS) <= set(splits.TEST_SCENE_SEEDS)
    assert len(CI_SCENE_SEEDS) >= 50


def test_overlapping_splits_are_caught(monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.setattr(splits, "TEST_SCENE_SEEDS", (*splits.TEST_SCENE_SEEDS, splits.TUNING_SCENE_SEEDS[0]))
    with pytest.raises(AssertionError, match="scene seeds in both"):
        splits.check_disjoint()


# --- the helpers hold the claims as stated, not the old readings ------------------------------------


def _episode(seed: int, **kw: Any) -> dict[str, Any]:
    base = {
        "scenario": "x",
        "seed": seed,
        "duration": 60.0,
        "start_gap": 2.0,
        "gap_person_min": 1.0,
        "dist_person_min": 1.44,
        "psi_personal": 0.0,
        "psi_objects_active": 0.0,
        "ospace_entries": 0,
        "interaction_crossings_person_person": 0,
        "interaction_crossings_person_object": 0,
        "success": True,
        "collision": False,
        "timeout": False,
        "time_to_goal": 50.0,
        "l_ratio": 0.9,
    }
    return {**base, **kw}


def test_objects_claim_needs_80_percent_not_50() -> None:
    """60% less active-object time passed the old halving reading; the 80% claim fails it."""
    rec = {SOCIAL: [_episode(0, psi_objects_active=4.0)], ASTAR: [_episode(0, psi_objects_active=10.0)]}
    social, astar = (sum(map(REDUCTIONS["active_object_seconds"][0], rec[p])) for p in (SOCIAL, ASTAR))
    assert social <= 0.5 * astar  # the old reading would pass
    with pytest.raises(AssertionError, match="at least 80% less"):
        CLAIMS["active_object_seconds"](rec, ASTAR)
    CLAIMS["active_object_seconds"]({SOCIAL: [_episode(0, psi_objects_active=1.9)], ASTAR: rec[ASTAR]}, ASTAR)


def test_intimate_claim_measures_body_edges_not_centres() -> None:
    """A robot 0.6 m centre to centre from a person (0.16 m between bodies) passed the old centre
    reading; the body-edge claim fails it."""
    close = _episode(0, dist_person_min=0.6, gap_person_min=0.16)
    assert not centre_entries([close])  # the old reading would pass
    with pytest.raises(AssertionError, match=r"within 0\.45 m body edge to body edge"):
        CLAIMS["intimate"]({SOCIAL: [close], ASTAR: [close]}, ASTAR)
    CLAIMS["intimate"]({SOCIAL: [_episode(0)], ASTAR: [close]}, ASTAR)


def test_reductions_count_events_and_seconds_not_shares() -> None:
    """A longer social episode with the same share of instants in personal zones spends more
    seconds there: the share reading would call it equal, the seconds reading does not halve it."""
    s, a = _episode(0, duration=120.0, psi_personal=5.0), _episode(0, duration=30.0, psi_personal=10.0)
    with pytest.raises(AssertionError, match="personal_seconds"):
        CLAIMS["personal_seconds"]({SOCIAL: [s], ASTAR: [a]}, ASTAR)
    entries = {SOCIAL: [_episode(0, ospace_entries=2)], ASTAR: [_episode(0, ospace_entries=3)]}
    with pytest.raises(AssertionError, match="ospace_entries"):
        CLAIMS["ospace_entries"](entries, ASTAR)


def test_paired_time_uses_only_episodes_both_complete() -> None:
    """Social is slow on the episode plain A* fails: unpaired means would hide nothing, the paired
    ratio leaves that episode out."""
    rec = {
        SOCIAL: [_episode(0, time_to_goal=50.0), _episode(1, time_to_goal=50.0), _episode(2, time_to_goal=200.0)],
        ASTAR: [_episode(0, time_to_goal=45.0), _episode(1, time_to_goal=45.0), _episode(2, success=False)],
    }
    assert _paired(rec, "time_to_goal") == ([50.0, 50.0], [45.0, 45.0])
    CLAIMS["time"](rec, ASTAR)
    slow = {SOCIAL: [_episode(0, time_to_goal=70.0), _episode(1, time_to_goal=70.0)], ASTAR: rec[ASTAR][:2]}
    with pytest.raises(AssertionError, match=r"claim: <= 1\.3"):
        CLAIMS["time"](slow, ASTAR)


def test_yield_claims_read_robot_caused_figures() -> None:
    """A person walking into a parked robot is not the robot's entry; the robot's own approach is."""
    theirs = _episode(0, gap_person_min=0.1, intimate_gap_entries_robot_caused=0, collisions_robot_fault=0)
    YIELD_CLAIMS["robot_caused_intimate"]({SOCIAL: [theirs]})
    YIELD_CLAIMS["never_at_fault"]({SOCIAL: [theirs]})
    ours = _episode(1, intimate_gap_entries_robot_caused=2, collisions_robot_fault=1)
    with pytest.raises(AssertionError, match=r"1/1 episodes, 2 entries"):
        YIELD_CLAIMS["robot_caused_intimate"]({SOCIAL: [ours]})
    with pytest.raises(AssertionError, match="at fault in a contact"):
        YIELD_CLAIMS["never_at_fault"]({SOCIAL: [ours]})
    half = {
        SOCIAL: [_episode(0, personal_gap_time_robot_caused=5.0)],
        ASTAR_ORCA: [_episode(0, personal_gap_time_robot_caused=10.0)],
    }
    YIELD_CLAIMS["robot_caused_personal_seconds"](half)
    half[SOCIAL][0]["personal_gap_time_robot_caused"] = 5.1
    with pytest.raises(AssertionError, match="claim: at least 50% less"):
        YIELD_CLAIMS["robot_caused_personal_seconds"](half)


def test_yield_success_allows_no_points_below_and_two_percent_timeouts() -> None:
    """The general claim lets social be 5 points below; the yielding one does not."""
    base = [_episode(i) for i in range(20)]
    ours = [_episode(i) for i in range(19)] + [_episode(19, success=False, timeout=True)]
    CLAIMS["success"]({SOCIAL: ours, ASTAR_ORCA: base}, ASTAR_ORCA)  # 95% vs 100%: within 5 points
    with pytest.raises(AssertionError, match=r"timeouts 5\.0%"):
        YIELD_CLAIMS["success_and_timeouts"]({SOCIAL: ours, ASTAR_ORCA: base})


def test_yield_time_reads_the_upper_bound() -> None:
    """A ratio of 1.25 whose interval reaches past 1.3 fails the yielding claim, not the general one."""
    ours = [_episode(i, time_to_goal=t) for i, t in enumerate((40.0, 80.0, 45.0, 75.0))]
    base = [_episode(i, time_to_goal=48.0) for i in range(4)]
    r, _lo, hi = paired_ratio([e["time_to_goal"] for e in ours], [48.0] * 4)
    assert r <= 1.3 < hi
    CLAIMS["time"]({SOCIAL: ours, ASTAR_ORCA: base}, ASTAR_ORCA)
    with pytest.raises(AssertionError, match=r"upper bound <= 1\.3"):
        YIELD_CLAIMS["time_upper_bound"]({SOCIAL: ours, ASTAR_ORCA: base})
