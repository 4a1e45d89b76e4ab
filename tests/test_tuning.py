"""proxemic tune: G from measured trajectories, the search's files, gains that change behaviour, bad input."""

from __future__ import annotations

import csv
import json
import math
import subprocess
import sys
from pathlib import Path

import numpy as np
import pyarrow.parquet as pq
import pytest

from proxemic import InputError, ScenarioError
from proxemic.cli import main
from proxemic.env import ProxemicEnv
from proxemic.runner import run_episode
from proxemic.tuning import CostWeights, TuneConfig, metric_terms, run_tune, run_tune_task

TARGET = "calderita_exp1"


def test_terms_are_the_core_metrics_and_g_weighs_them():
    metrics = {"chc": 1.5, "d_t": 2.0, "tau": 0.3, "cp_avg": 4.25, "path_length": 2.0}
    t = metric_terms(metrics)
    assert t == {"H": 1.5, "D": 2.0, "Q": 0.3, "P": 4.25}
    assert metric_terms({**metrics, "cp_avg": None})["P"] == 0.0  # no people: P = 0
    w = CostWeights(a=2, b=3, c=5, d=-7, failure_penalty=11)
    g = 2 * 1.5 + 3 * 2.0 + 5 * 0.3 - 7 * 4.25
    assert w.cost({**t, "success": True}) == pytest.approx(g)
    assert w.cost({**t, "success": False}) == pytest.approx(g + 11)


def test_runner_trajectory_is_the_executed_one():
    """The record's robot poses (the core's trajectory) are the poses the env reported step by step."""
    env = ProxemicEnv(TARGET, autopilot=True, planner="eband")
    rec = run_episode(TARGET, 0, env=env)
    env.reset(seed=0)
    poses = [env.robot_pose()]
    while True:
        _, _, terminated, truncated, _ = env.step(env.action_space.sample() * 0.0)
        poses.append(env.robot_pose())
        if terminated or truncated:
            break
    env.close()
    assert rec.robot.shape == (len(poses), 3) and np.array_equal(rec.robot, np.array(poses))
    assert rec.people.shape[:2] == (len(poses), env.world.num_people)


def _g_recomputed(gains: dict[str, float], seeds: list[int], w: dict[str, float], planner: str) -> float:
    """G of a gain point from fresh episodes of `planner`, with this test's own H, D, Q, P."""
    env = ProxemicEnv(TARGET, autopilot=True, planner=planner, eband=gains)
    dt = env.core_scenario.control_dt
    costs = []
    for seed in seeds:
        rec = run_episode(TARGET, seed, env=env)
        heading = sum(
            abs(math.remainder(b - a, math.tau)) for a, b in zip(rec.robot[:-1, 2], rec.robot[1:, 2], strict=True)
        )
        dist = sum(math.dist(a, b) for a, b in zip(rec.robot[:-1, :2], rec.robot[1:, :2], strict=True))
        near = [min(math.dist(r[:2], p) for p in ppl) for r, ppl in zip(rec.robot, rec.people, strict=True)]
        g = w["a"] * heading + w["b"] * dist + w["c"] * (len(rec.robot) - 1) * dt + w["d"] * sum(near) / len(near)
        costs.append(g + (0.0 if rec.metrics["success"] else w["failure_penalty"]))
    env.close()
    return sum(costs) / len(costs)


def test_tune_writes_every_point_and_g_comes_from_the_trajectories(tmp_path):
    runs = {}
    for workers in (1, 2):
        cfg = TuneConfig(
            targets=[TARGET],
            trials=3,
            episodes=1,
            samples=2,
            seed=3,
            ranges={"repulsion_gain": (0.0, 2.0)},
            out=tmp_path / f"w{workers}",
            workers=workers,
        )
        runs[workers] = run_tune(cfg, progress=False)
    result = runs[1]
    out = tmp_path / "w1"
    for name in ("trials.csv", "trials.parquet", "episodes.csv", "episodes.parquet", "tune.json", "tune.png"):
        assert (out / name).stat().st_size > 0, name
    assert json.loads((out / "tune.json").read_text()) == result
    assert runs[2] == result  # the same points and costs on one or two processes
    with (out / "trials.csv").open() as fh:
        trials = list(csv.DictReader(fh))
    assert [t["varied"] for t in trials] == ["start", "repulsion_gain", "repulsion_gain"]
    gains = [float(t["repulsion_gain"]) for t in trials]
    assert gains[0] == 0.5 and 0.0 <= gains[1] < 1.0 <= gains[2] < 2.0  # default, then one per half range
    assert pq.read_table(out / "episodes.parquet").num_rows == 3
    best = result["best"]
    assert best["G"] == min(float(t["G"]) for t in trials)
    assert len({round(float(t["G"]), 9) for t in trials}) == 3  # different gains, different G
    assert result["planner"] == "calderita"  # the default: Calderita's own band, on its social path
    g = _g_recomputed({"repulsion_gain": best["repulsion_gain"]}, result["seeds"], result["weights"], result["planner"])
    assert g == pytest.approx(best["G"], rel=1e-9)


def test_gains_change_the_trajectory():
    a = run_tune_task((0, (TARGET, None), "eband", 1, (("repulsion_gain", 0.0),)))
    b = run_tune_task((1, (TARGET, None), "eband", 1, (("repulsion_gain", 2.0),)))
    assert a["success"] and b["success"]
    assert (a["H"], a["D"]) != (b["H"], b["D"])
    assert CostWeights().cost(a) != CostWeights().cost(b)


def test_targets_send_the_robot_to_other_goals():
    own = run_tune_task((0, (TARGET, None), "eband", 0, ()))
    near = run_tune_task((0, (TARGET, (4.0, 8.0)), "eband", 0, ()))
    assert (own["goal_x"], own["goal_y"]) == (14.0, 7.8) and (near["goal_x"], near["goal_y"]) == (4.0, 8.0)
    assert near["success"] and near["D"] < own["D"] - 3.0


def test_bad_gains_name_the_field():
    with pytest.raises(ScenarioError, match=r"eband\.contraction_gain: expected a number in \[0, 100\], got -1"):
        ProxemicEnv(TARGET, planner="eband", eband={"contraction_gain": -1.0})
    with pytest.raises(ScenarioError, match=r"eband\.kc: expected an elastic-band gain among") as e:
        ProxemicEnv(TARGET, planner="eband", eband={"kc": 1.0})
    assert e.value.field == "eband.kc" and e.value.found == '"kc"'
    with pytest.raises(InputError, match=r"gain\.repulsion_gain: expected a range 0 <= low < high <= 100"):
        TuneConfig(targets=[TARGET], ranges={"repulsion_gain": (2.0, 1.0)}).check()


def test_tune_cli_bad_input_exits_non_zero(tmp_path, capsys):
    base = ["tune", "--trials", "1", "--episodes", "1", "--out", str(tmp_path / "t")]
    assert main([*base, "--scenario", "atlantis"]) == 2
    assert "unknown scenario 'atlantis'" in capsys.readouterr().err
    assert main([*base, "--scenario", TARGET, "--target", "0.15,5"]) == 2
    assert "robot[0].goal: expected a position at least 0.24 m" in capsys.readouterr().err
    assert main([*base, "--scenario", TARGET, "--target", "100,5"]) == 2
    assert "robot[0].goal: expected a point inside scene.bounds" in capsys.readouterr().err
    assert main([*base, "--planner", "teleport"]) == 2
    assert 'planner: expected one of ["astar"' in capsys.readouterr().err
    assert main([*base, "--planner", "astar"]) == 2
    err = capsys.readouterr().err
    assert "planner: expected a planner with tunable gains, one of calderita, eband, got astar" in err
    assert main([*base, "--gain", "kc=0:1"]) == 2
    assert 'eband.kc: expected an elastic-band gain among ["contraction_gain"' in capsys.readouterr().err
    assert main([*base, "--gain", "repulsion_gain=2:1"]) == 2
    assert "expected a range 0 <= low < high <= 100" in capsys.readouterr().err
    blocked = tmp_path / "file"
    blocked.write_text("not a folder")
    assert main(["tune", "--trials", "1", "--episodes", "1", "--out", str(blocked / "sub")]) == 2
    assert "cannot be written" in capsys.readouterr().err
    assert not (tmp_path / "t").exists()


def test_tune_on_ray_matches_processes(tmp_path):
    pytest.importorskip("ray", reason="the ray backend needs ray (pip install 'proxemic[ray]'; make test installs it)")
    results = {}
    for backend in ("process", "ray"):
        cfg = TuneConfig(
            targets=[(TARGET, (4.0, 8.0))],
            trials=2,
            episodes=1,
            samples=1,
            ranges={"repulsion_gain": (0.0, 2.0)},
            out=tmp_path / backend,
            workers=2,
            backend=backend,
        )
        results[backend] = run_tune(cfg, progress=False)
    assert results["ray"] == results["process"]
    assert len(results["ray"]["trials"]) == 2


def test_tune_social_claims_reuses_its_cache_of_every_other_planner(tmp_path):
    """``examples/tune_social_claims.py --cache``: the first run stores every planner but ``social``,
    the second re-runs only ``social`` and prints the same figures, and a cache written before the
    papers' planners joined the claims' runner (baselines only) is run afresh, not a KeyError."""
    root = Path(__file__).resolve().parent.parent
    cache = tmp_path / "cache.json"
    cmd = [sys.executable, "examples/tune_social_claims.py", "--sets", "generated", "--scenes", "1"]
    cmd += ["--workers", "1", "--cache", str(cache)]

    def run() -> str:
        done = subprocess.run(cmd, cwd=root, capture_output=True, text=True, timeout=300)
        assert done.returncode == 0, done.stderr
        return done.stdout

    first = run()
    stored = json.loads(cache.read_text())
    (key,) = stored
    assert sorted(stored[key]) == sorted(["astar", "astar_orca", "daza2021", "sousa2022", "calderita"])
    assert "collision" in first and "calderita" in first
    assert run() == first
    cache.write_text(json.dumps({key: {p: stored[key][p] for p in ("astar", "astar_orca")}}))
    assert run() == first
    assert sorted(json.loads(cache.read_text())[key]) == sorted(stored[key])
