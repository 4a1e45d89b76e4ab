"""SNQI (robot-sf's composite): the published formula and weights, the baseline, the sensitivity line."""

from __future__ import annotations

import math

import pytest

from proxemic import snqi
from proxemic.evaluation import summarise


def _rec(planner: str, success: bool, t: float | None = None, hc: int = 0, near: int = 0, **kw: float) -> dict:
    return {
        "planner": planner,
        "success": success,
        "time_to_goal": t,
        "max_time": 100.0,
        "hc_count": hc,
        "near_misses": near,
        "force_exceed_events": kw.get("force", 0),
        "comfort_exposure": kw.get("comfort", 0.0),
        "jerk_avg": kw.get("jerk", 0.0),
    }


#: robot-sf's published canonical weights, in its ``WEIGHT_NAMES`` order: ``canonical_weights`` of
#: ``recompute_snqi_weights`` in ``robot_sf/benchmark/snqi/compute.py``, repository
#: ``ll7/robot_sf_ll7``, commit ``af4b7c2c8b04576289b529c30c1367b16f3f7c3b``.
PUBLISHED = (
    ("w_success", 1.0),
    ("w_time", 0.8),
    ("w_collisions", 2.0),
    ("w_near", 1.0),
    ("w_comfort", 0.5),
    ("w_force_exceed", 1.5),
    ("w_jerk", 0.3),
)

#: Each term alone at its full size (normalised term 1): (weight, record, sign of its effect).
UNIT_TERMS = {
    "w_success": ({"success": True, "time_to_goal": 0.0}, +1.0),
    "w_time": ({}, -1.0),
    "w_collisions": ({"hc_count": 2}, -1.0),
    "w_near": ({"near_misses": 5}, -1.0),
    "w_comfort": ({"comfort_exposure": 1.0}, -1.0),
    "w_force_exceed": ({"force_exceed_events": 10}, -1.0),
    "w_jerk": ({"jerk_avg": 3.0}, -1.0),
}
UNIT_STATS = {
    "hc_count": (0.0, 2.0),
    "near_misses": (0.0, 5.0),
    "force_exceed_events": (0.0, 10.0),
    "jerk_avg": (0.0, 3.0),
}


class _Reads(dict):  # type: ignore[type-arg]
    """A weights mapping that notes which weights are read."""

    def __init__(self, *args: object) -> None:
        super().__init__(*args)
        self.read: set[str] = set()

    def __getitem__(self, key: str) -> float:
        self.read.add(key)
        return float(super().__getitem__(key))


def test_the_weights_are_robot_sfs_published_ones_in_its_order():
    assert list(snqi.WEIGHTS.items()) == list(PUBLISHED)


def test_every_weight_is_a_term_of_the_score_and_every_term_has_a_weight():
    weights = _Reads(snqi.WEIGHTS)
    r = _rec("x", True, t=25.0, hc=1, near=3, force=5, comfort=0.2, jerk=2.0)
    snqi.episode_snqi(r, UNIT_STATS, weights)
    assert weights.read == set(snqi.WEIGHTS)
    assert set(snqi.NORMALISED) < set(snqi.WEIGHTS)


@pytest.mark.parametrize("weight", list(UNIT_TERMS))
def test_each_weight_moves_the_score_by_its_published_value(weight: str):
    """An episode whose only term is ``weight``'s, at full size, scores that weight (signed),
    measured against the same episode with the weight set to zero."""
    fields, sign = UNIT_TERMS[weight]
    # every other term at zero: a success at once (time term 0; a failure for w_time's term), no
    # contacts, no near misses, no exposure, no force events, no jerk
    base = {**_rec("x", weight != "w_time", t=0.0), **fields}
    published = dict(PUBLISHED)
    zeroed = {**snqi.WEIGHTS, weight: 0.0}
    effect = snqi.episode_snqi(base, UNIT_STATS) - snqi.episode_snqi(base, UNIT_STATS, zeroed)
    assert math.isclose(effect, sign * published[weight]), (weight, effect)


def test_normalisation_is_median_p95_clamped():
    assert snqi.normalise(3.0, 1.0, 5.0) == 0.5
    assert snqi.normalise(0.0, 1.0, 5.0) == 0.0  # below the median: no penalty
    assert snqi.normalise(9.0, 1.0, 5.0) == 1.0  # beyond p95: saturates
    assert snqi.normalise(2.0, 1.0, 1.0) == 1.0  # flat baseline: denominator 1, clamped


def test_episode_score_by_hand():
    stats = {
        "hc_count": (0.0, 2.0),
        "near_misses": (1.0, 5.0),
        "force_exceed_events": (0.0, 10.0),
        "jerk_avg": (1.0, 3.0),
    }
    r = _rec("x", True, t=25.0, hc=1, near=3, force=5, comfort=0.2, jerk=2.0)
    # 1 - 0.8*0.25 - 2*0.5 - 1*0.5 - 0.5*0.2 - 1.5*0.5 - 0.3*0.5
    expected = 1.0 - 0.2 - 1.0 - 0.5 - 0.1 - 0.75 - 0.15
    assert math.isclose(snqi.episode_snqi(r, stats), expected)
    # a failure: no success term, time_norm 1
    f = _rec("x", False, hc=0, near=0)
    assert math.isclose(snqi.episode_snqi(f, stats), -0.8)


def test_the_baseline_is_astar_when_it_ran():
    recs = [_rec("astar", True, 10.0, hc=h) for h in (0, 0, 4)] + [_rec("social", True, 10.0, hc=9)]
    stats = snqi.baseline_stats(recs)
    assert stats["hc_count"][0] == 0.0 and math.isclose(stats["hc_count"][1], 3.6)
    pooled = snqi.baseline_stats([r for r in recs if r["planner"] == "social"])
    assert pooled["hc_count"] == (9.0, 9.0)


def test_sensitivity_line_names_the_weight_that_flips_the_ranking():
    # a always arrives (time_norm 0.1) touching a person once, the baseline's median: no penalty;
    # b arrives half the time; astar arrives always but touches 2 people in half its episodes
    # (its p95: penalty 1 x w_collisions there).
    a = [_rec("a", True, 10.0, hc=1) for _ in range(4)]
    b = [_rec("b", s, 10.0 if s else None) for s in (True, False, True, False)]
    base = [_rec("astar", True, 10.0, hc=h) for h in (0, 0, 2, 2)]
    recs = a + b + base
    stats = snqi.baseline_stats(recs)
    assert stats["hc_count"] == (1.0, 2.0)
    means = snqi.planner_means(recs, stats)
    assert math.isclose(means["a"], 0.92)
    assert math.isclose(means["b"], (2 * 0.92 - 2 * 0.8) / 4)
    assert math.isclose(means["astar"], 0.92 - 1.0)
    line = snqi.sensitivity_line(recs)
    assert line.startswith("SNQI ranking (robot-sf, canonical weights): a (+0.920) > b (+0.060) > astar (-0.080).")
    # halving w_collisions lifts astar to 0.42, above b
    assert "w_collisions x0.5: a > astar > b" in line
    assert "w_collisions x1.5" not in line  # a heavier collision weight keeps the order


def test_sensitivity_reports_a_flip():
    stats = {"hc_count": (0.0, 2.0)}
    # a arrives always at once (time_norm 0), touching a person each time (penalty 2 x 0.5);
    # b arrives in half its episodes without touching anyone.
    a = [_rec("a", True, 0.0, hc=1) for _ in range(4)]
    b = [_rec("b", s, 0.0 if s else None) for s in (True, True, False, False)]
    means = snqi.planner_means(a + b, stats)
    assert math.isclose(means["a"], 0.0) and math.isclose(means["b"], 0.1)
    moved = {(w, f): r for w, f, r in snqi.sensitivity(a + b, stats)}
    assert moved[("w_collisions", 0.5)] == ["a", "b"]  # a: 0.5 > b: 0.1
    assert moved[("w_collisions", 1.5)] == ["b", "a"]
    assert moved[("w_success", 1.5)] == ["a", "b"]  # a: 0.5 > b: 0.35
    assert moved[("w_time", 0.5)] == ["b", "a"]


def test_summary_rows_carry_the_mean_snqi():
    recs = [_rec("astar", True, 50.0), _rec("astar", False), _rec("social", True, 20.0)]
    rows = summarise(recs)
    assert rows[0]["snqi"] == pytest.approx(0.5 * (1 - 0.4) + 0.5 * (-0.8))
    assert rows[1]["snqi"] == pytest.approx(1 - 0.16)
    assert "snqi" not in recs[0]  # the records themselves are left as they were
