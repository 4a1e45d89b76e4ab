"""Calderita et al.'s Tables 1-2: the mechanism each row reports, and the direction of each
paired comparison the paper makes (the social path against the non-social one), on the scenes
`proxemic reproduce calderita` runs.

One episode per scene and planner, test-split seed 1000 (the scenes' people stand still, so the
seeds differ only by the people's phase). A mechanism our scenes do not exercise stays a strict
xfail stating the figure measured and its cause; no scene was moved to make one pass.
"""

from __future__ import annotations

import functools

import numpy as np
import pytest

from proxemic.env import ProxemicEnv
from proxemic.errors import InputError
from proxemic.evaluation import run_task
from proxemic.reproduce import DENSITY_ZONES, density_zone_shares

SEED = 1000


@functools.cache
def run(scene: str, planner: str) -> tuple[dict[str, float], int]:
    """The episode metrics of `planner` on `scene` (seed :data:`SEED`) and its re-plan count."""
    env = ProxemicEnv(scene, autopilot=True, planner=planner)
    env.reset(seed=SEED)
    zero = np.zeros(3, np.float32)
    while True:
        _, _, terminated, truncated, _ = env.step(zero)
        if terminated or truncated:
            break
    metrics = {k: float(v) for k, v in env.flat_metrics().items() if isinstance(v, (int, float))}
    replans = env.world.replans(0)
    env.close()
    assert metrics["success"], f"{planner} did not reach its goal in {scene}"
    return metrics, replans


def test_table1_paths_are_longer_than_the_non_social_path():
    """Table 1: d_t 14.03 m (Path 1) and 17.40 m (Path 2) against 12.81 m for the non-social path."""
    base = run("calderita_exp1", "astar")[0]["d_t"]
    assert run("calderita_exp1_test1", "calderita")[0]["d_t"] > base
    assert run("calderita_exp1", "calderita")[0]["d_t"] > base


def test_table1_path1_keeps_farther_from_senior_1_than_the_non_social_path():
    """Table 1: d_min(senior_1) 1.39 m on Path 1 against 0.51 m for the non-social path."""
    ours = run("calderita_exp1_test1", "calderita")[0]["d_min_senior_1"]
    assert ours > run("calderita_exp1_test1", "astar")[0]["d_min_senior_1"]


def test_table1_path1_crosses_the_idle_tv_space_and_path2_does_not():
    """Table 1: Psi(Objects) 34.98% on Path 1 ("the robot uses the TV's [...] spaces [...] since
    it is not in use"), 1.64% on Path 2 (TV therapy on)."""
    path1 = run("calderita_exp1_test1", "calderita")[0]
    path2 = run("calderita_exp1", "calderita")[0]
    assert path1["psi_object_any_tv"] > 0.0
    assert path2["psi_object_any_tv"] < path1["psi_object_any_tv"]


@pytest.mark.xfail(
    strict=True,
    reason="measured (seed 1000): calderita passes 0.55 m behind senior_1 on Table 1 Path 2, plain "
    "A* 2.05 m (the paper: 1.89 m against 0.51 m). In our calderita_exp1 the TV's active space "
    "fills the way north of the round table, so the social path goes south of it, right behind "
    "senior_1 (her Gaussian is shortest behind, sigma_r = 1 m); the paper's Path 2 passes nearer "
    "senior_2 (1.13 m) instead. A scene placement question (Fig. 17a is not available), not moved.",
)
def test_table1_path2_keeps_farther_from_senior_1_than_the_non_social_path():
    """Table 1: d_min(senior_1) 1.89 m on Path 2 against 0.51 m for the non-social path."""
    ours = run("calderita_exp1", "calderita")[0]["d_min_senior_1"]
    assert ours > run("calderita_exp1", "astar")[0]["d_min_senior_1"]


def test_table2_path2_is_longer_and_stays_out_of_the_object_spaces():
    """Table 2: Path 2 16.28 m and Psi(Objects) 0% against 10.92 m and 73.22% non-social."""
    ours, base = run("calderita_exp2_path2", "calderita")[0], run("calderita_exp2_path2", "astar")[0]
    assert ours["d_t"] > base["d_t"]
    assert ours["psi_objects_any"] == 0.0 < base["psi_objects_any"]


@pytest.mark.xfail(
    strict=True,
    reason="measured (seed 1000): calderita_exp2_path2 re-plans 0 times. Its first path (table "
    "idle) already runs at y = 3.8-4.2 m (x = 11-14 m), 1-1.4 m south of the table's space (edge at "
    "y = 5.2 m), while plain A* crosses that space (13.4% of its time), so the rise of R(t) never "
    "touches the path. The cause is the people, not the idle space: the same scene without the "
    "table's interaction space plans the identical path; without senior_1, senior_2 and the "
    "therapist (seated facing south across the table, sigma_h = 2 m ahead) the path runs at "
    "y = 4.7-5.0 m there, along the space's edge. The paper's first path 'crosses near the table and the senior' "
    "(Fig. 20a); Fig. 17b is not available, and the scene was not moved.",
)
def test_table2_path2_replans_when_the_table_activity_starts():
    """Fig. 20: at instant 2 the table's space rises in cost and the robot re-plans away from it."""
    metrics, replans = run("calderita_exp2_path2", "calderita")
    assert replans >= 1
    assert metrics["psi_object_active_ot_table"] == 0.0


@pytest.mark.xfail(
    strict=True,
    reason="measured (seed 1000): psi_object_any_ot_table 0.0% on calderita_exp2_path1 (paper "
    "Psi(Objects) 69.85%). The row starts at 11:05 with the table already active, so the first "
    "plan goes round the table's space; the paper's Path 1 is the first path kept while the "
    "therapy runs, and no planner setting keeps a calderita path without re-planning.",
)
def test_table2_path1_crosses_the_table_space_during_the_therapy():
    """Table 2 Path 1: 'the robot crosses the occupational therapy room during the therapy'."""
    assert run("calderita_exp2_path1", "calderita")[0]["psi_object_active_ot_table"] > 0.0


def test_density_zones_along_are_the_g_d_contours():
    """One person alone: the G_d contours lie at Hall's radii to her side (0.45/1.2/3.6 m), and
    ahead of her, where her Gaussian is wider (sigma_h = 2 m against sigma_s = 4/3 m), 1.5 times
    farther."""
    world = ProxemicEnv("calderita_exp1", autopilot=True, planner="calderita").world
    side = np.array([[0.0, 0.3], [0.0, 0.8], [0.0, 2.0], [0.0, 5.0]])
    ahead = np.array([[0.6, 0.0], [1.5, 0.0], [5.0, 0.0], [5.6, 0.0]])
    her = np.zeros((4, 1, 3))  # at the origin, facing +x, at every instant
    assert world.density_zones_along(side, her).tolist() == [0, 1, 2, 3]
    # 1.5 times the radii ahead: 5.0 m is social there, public to her side
    assert world.density_zones_along(ahead, her).tolist() == [0, 1, 2, 3]
    with pytest.raises(InputError, match="people"):
        world.density_zones_along(side, np.zeros((3, 1, 3)))


def test_reproduce_scores_psi_per_zone_on_the_g_d_contours():
    """psi_gd_* (the paper's zones) cover every instant once, beside the Hall-circle psi_*."""
    res = run_task(("calderita_exp1_test1", "calderita", SEED), keep=True)
    shares = density_zone_shares("calderita_exp1_test1", "calderita", res)
    assert sorted(shares) == sorted(f"psi_gd_{z}" for z in DENSITY_ZONES)
    assert sum(shares.values()) == pytest.approx(100.0)
    assert shares != {f"psi_gd_{z}": res.record[f"psi_{z}"] for z in DENSITY_ZONES}
