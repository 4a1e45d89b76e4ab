"""Evaluating any policy: the protocol, proxemic.evaluate, proxemic eval --policy, verdicts, errors."""

from __future__ import annotations

import csv
import math
import sys
from pathlib import Path

import numpy as np
import pytest

import proxemic
from proxemic.cli import main
from proxemic.errors import InputError
from proxemic.evaluation import (
    HEADLINE,
    METRICS,
    EvalConfig,
    headline_markdown,
    paired_ratio,
    run_evaluation,
    summarise,
    verdict,
)
from proxemic.policy import PolicyActor, build_policy, joint_policy, load_factory

ROOT = Path(__file__).resolve().parent.parent
MY_POLICY = "examples.my_policy:make"
SCENE = "daza2021_path3"  # a 10 m route past a group: short episodes


@pytest.fixture
def at_root(monkeypatch):
    """Runs from the repository root (where ``examples.my_policy`` imports), as docs/policies.md says."""
    monkeypatch.chdir(ROOT)
    yield ROOT
    for name in [m for m in sys.modules if m == "examples" or m.startswith("examples.")]:
        del sys.modules[name]


class Still:
    """A policy object with predict (the stable-baselines3 convention) and reset."""

    def __init__(self) -> None:
        self.seeds: list[int | None] = []

    def reset(self, seed: int | None) -> None:
        self.seeds.append(seed)

    def predict(self, obs, deterministic=True):
        return np.zeros((1, 3), dtype=np.float32), None  # a batch of one, with a state


def test_actor_accepts_callables_and_predict_and_checks_the_action_shape():
    assert PolicyActor(lambda obs: [0.1, 0.2, 0.3])({}).tolist() == pytest.approx([0.1, 0.2, 0.3])
    still = Still()
    actor = PolicyActor(still)
    actor.reset(7)
    assert still.seeds == [7] and actor({}).shape == (3,)
    with pytest.raises(InputError, match=r"policy: expected 3 finite real numbers .*, got shape \(2,\) of float64"):
        PolicyActor(lambda obs: [0.0, 0.0], name="short")({})
    with pytest.raises(InputError, match="expected a callable obs -> action, or an object with predict"):
        PolicyActor(42)


def test_the_policy_drives_the_env_and_the_same_seed_gives_the_same_episode(at_root):
    from examples.my_policy import GoalSeeker

    result = proxemic.evaluate(GoalSeeker(), scenario=SCENE, episodes=2, seed=3, planners=[])
    again = proxemic.evaluate(GoalSeeker(), scenario=SCENE, episodes=2, seed=3, planners=[])
    assert [r["seed"] for r in result.records] == [3, 4]
    assert result.records == again.records
    # a policy that does not move the robot gives another episode than the goal seeker
    still = proxemic.evaluate(Still(), scenario=SCENE, episodes=1, seed=3, planners=[], name="still")
    assert still.records[0]["path_length"] < 0.05 < result.records[0]["path_length"]
    assert still.records[0]["planner"] == "still"


def test_evaluate_runs_the_policy_and_the_planners_on_the_same_seeds(at_root, tmp_path):
    result = proxemic.evaluate(MY_POLICY, scenario=SCENE, episodes=2, seed=5, planners=["astar"], out=tmp_path)
    assert [(r["planner"], r["seed"]) for r in result.records] == [
        ("my_policy", 5),
        ("my_policy", 6),
        ("astar", 5),
        ("astar", 6),
    ]
    assert [row["planner"] for row in result.summary] == ["my_policy", "astar"]
    assert result.verdicts and result.verdicts[0].startswith("my_policy vs astar on 2 seeds")
    table = result.table()
    assert table.num_rows == 4 and "psi_personal" in table.column_names
    for name in ("episodes.csv", "episodes.parquet", "summary.md", "metrics.png", "trajectories_my_policy.png"):
        assert (tmp_path / name).exists(), name
    # the planner's records are those of a planner-only run: the policy does not disturb them (SCENE
    # has 2 robots: a planner-only run scores both, a run with a policy robot 0, the policy's robot)
    alone = proxemic.evaluate(scenario=SCENE, episodes=2, seed=5, planners=["astar"])
    assert [r["robot"] for r in alone.records] == [0, 1, 0, 1]
    assert [r for r in alone.records if r["robot"] == 0] == result.records[2:]


def test_cli_policy_gives_the_same_records_on_processes_and_ray(at_root, tmp_path, capsys):
    args = ["eval", "--scenario", SCENE, "--policy", MY_POLICY, "--planner", "astar", "--episodes", "2", "--seed", "1"]
    runs = {}
    backends = ["process"]
    try:
        import ray  # noqa: F401

        backends.append("ray")
    except ImportError:
        pass
    for backend in backends:
        out = tmp_path / backend
        assert main([*args, "--workers", "2", "--backend", backend, "--out", str(out)]) == 0
        with (out / "episodes.csv").open() as fh:
            runs[backend] = list(csv.DictReader(fh))
    printed = capsys.readouterr().out
    assert "success (%)" in printed and "my_policy vs astar" in printed
    assert max(len(line) for line in printed.split("my_policy vs astar")[0].splitlines()) <= 100  # fits a terminal
    assert [r["planner"] for r in runs["process"]] == ["my_policy", "my_policy", "astar", "astar"]
    assert main([*args, "--workers", "1", "--out", str(tmp_path / "one")]) == 0
    with (tmp_path / "one" / "episodes.csv").open() as fh:
        one = list(csv.DictReader(fh))
    for rows in runs.values():
        assert rows == one


@pytest.mark.parametrize(
    ("policy", "message"),
    [
        ("no_such_module_xyz:make", "cannot import 'no_such_module_xyz'"),
        ("examples.my_policy", "expected an import path 'module:factory'"),
        ("examples.my_policy:nothing", "has no attribute 'nothing'"),
        ("examples.my_policy:OBSTACLE_RANGE", "got 'OBSTACLE_RANGE', a float (--policy"),
        ("tests/bad_policies.py:short_action", r"got shape \(2,\) of float64"),
        ("tests/bad_policies.py:not_a_policy", "expected a callable obs -> action"),
        ("tests/bad_policies.py:no_arguments", "the factory must take (observation_space, action_space)"),
        ("tests/bad_policies.py:complex_action", "real numbers in [-1, 1], shape (3,), got shape (3,) of complex128"),
        ("tests/bad_policies.py:bool_action", "real numbers in [-1, 1], shape (3,), got shape (3,) of bool"),
        (
            "tests/bad_policies.py:raises_in_factory",
            "policy 'tests/bad_policies.py:raises_in_factory' raised RuntimeError: no weights file in its factory",
        ),
        ("tests/bad_policy_import.py:make", "raised RuntimeError: this policy module fails at import while its module"),
    ],
)
def test_a_bad_policy_is_a_one_line_error(at_root, tmp_path, capsys, policy, message):
    assert main(["eval", "--scenario", SCENE, "--policy", policy, "--episodes", "1", "--out", str(tmp_path)]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and "Traceback" not in err, err
    assert err.startswith("proxemic: error: ") and message.replace("\\", "") in err.replace("\\", ""), err
    assert not (tmp_path / "episodes.csv").exists()  # checked before any episode


@pytest.mark.parametrize(
    ("policy", "message"),
    [
        (
            "raises_at_step",
            "raised ZeroDivisionError: division by zero in the policy at step 0 of the episode of seed 0 on " + SCENE,
        ),
        ("exits_at_step", f"called sys.exit(3) at step 0 of the episode of seed 0 on {SCENE}"),
    ],
)
def test_a_policy_failing_in_an_episode_names_the_policy_the_episode_and_the_step(
    at_root, tmp_path, capsys, policy, message
):
    path = f"tests/bad_policies.py:{policy}"
    argv = ["eval", "--scenario", SCENE, "--policy", path, "--episodes", "1", "--workers", "1", "--out", str(tmp_path)]
    assert main(argv) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and "Traceback" not in err, err
    assert f"policy 'bad_policies' {message}" in err, err


def test_policy_labels_must_differ(at_root, tmp_path, capsys):
    args = ["eval", "--policy", MY_POLICY, "--policy-name", "astar", "--planner", "astar", "--out", str(tmp_path)]
    assert main(args) == 2
    err = capsys.readouterr().err
    assert "policy_name: expected a label no other policy or planner has" in err and "got astar" in err


def test_a_policy_object_cannot_go_to_ray():
    with pytest.raises(InputError, match="cannot be sent to backend 'ray'"):
        proxemic.evaluate(Still(), episodes=1, planners=[], backend="ray")


def test_load_factory_reads_a_file_path(at_root):
    factory = load_factory("examples/my_policy.py:make")
    assert factory.__name__ == "make"
    import gymnasium as gym

    env = gym.make("proxemic/Museum-v5")
    policy = build_policy("examples/my_policy.py:make", env.observation_space, env.action_space)
    obs, _ = env.reset(seed=0)
    assert env.action_space.contains(PolicyActor(policy)(obs))
    env.close()


def test_joint_policy_shared_or_per_agent():
    env = proxemic.parallel_env("daza2021_fig15")
    obs, _ = env.reset(seed=0)
    agents = list(env.possible_agents)
    shared = joint_policy(lambda o: np.zeros(3), agents)
    assert set(shared(obs)) == set(obs)
    still = {a: Still() for a in agents}
    per_agent = joint_policy(still, agents)  # type: ignore[arg-type]
    per_agent.reset(4)  # type: ignore[attr-defined]
    assert all(p.seeds == [4] for p in still.values())
    obs, *_ = env.step(per_agent(obs))
    assert set(obs) <= set(agents)
    with pytest.raises(InputError, match="missing"):
        joint_policy({agents[0]: Still()}, agents)
    env.close()


def test_paired_ratio_and_verdict_from_known_records():
    r, lo, hi = paired_ratio([2.0, 4.0, 6.0], [1.0, 2.0, 3.0])
    assert r == 2.0 and lo == pytest.approx(2.0) and hi == pytest.approx(2.0)  # every resample has ratio 2
    r, lo, hi = paired_ratio([1.0, 3.0, 2.0, 5.0], [2.0, 2.0, 2.0, 2.0])
    assert r == pytest.approx(11 / 8) and lo < r < hi
    assert math.isnan(paired_ratio([1.0], [0.0])[0])
    records = []
    for seed in range(4):
        records.append({"planner": "a", "seed": seed, "success": True, "time_to_goal": 20.0, "psi_personal": 5.0})
        records.append({"planner": "b", "seed": seed, "success": seed != 3, "time_to_goal": 10.0, "psi_personal": 20.0})
    text = verdict(records, "a", "b")
    assert text.startswith("a vs b on 4 seeds: success 4 vs 3, collisions 0 vs 0")
    assert "over the 3 seeds both reached the goal" in text
    assert "2.00x time to goal [2.00x, 2.00x]" in text and "75% less personal-zone time, centres [75% less]" in text


def test_headline_has_units_and_intervals_within_bounds():
    records = [
        {"planner": "a", "seed": s, "success": s < 2, "outcome": "success", "psi_personal": v}
        for s, v in enumerate([0.0, 0.0, 0.5])
    ]
    row = summarise(records)[0]
    assert row["psi_personal_lo"] == 0.0  # the t interval would go below 0 %
    assert row["success_lo"] >= 0.0 and row["success_hi"] <= 1.0
    text = headline_markdown([row])
    for m in HEADLINE:
        assert METRICS[m].label in text
    assert "time to goal (s)" in text and "67% [21%, 94%]" in text and "0.2 [0.0, " in text


def test_metrics_png_is_a_grid_of_at_most_five_columns(tmp_path):
    from PIL import Image

    cfg = EvalConfig(scenario=SCENE, planners=["astar", "social"], episodes=2, out=tmp_path, workers=1)
    run_evaluation(cfg, progress=False)
    width, height = Image.open(tmp_path / "metrics.png").size
    assert width <= 1500 and height > 400  # five 2.9-inch panels per row at 100 dpi, four rows
    summary = (tmp_path / "summary.md").read_text()
    assert summary.index("social vs astar") < summary.index("## All metrics")
