"""CrowdNav's protocol: the scenes, the reference data and the agreement with CrowdNav's own run."""

from __future__ import annotations

import json
import os
import subprocess
import sys
from pathlib import Path

import pytest

from proxemic import _core, crowdnav, splits
from proxemic.errors import InputError
from proxemic.policy import PolicyRef

ROOT = Path(__file__).resolve().parents[1]

#: Scene seeds of the agreement check: the test split's first generated scene seed on. Nothing of the
#: family was tuned (its constants are CrowdNav's); these seeds were not looked at before the check.
SEEDS = range(crowdnav.TEST_SEED, crowdnav.TEST_SEED + crowdnav.EPISODES)


def test_reference_is_measured_data_with_provenance() -> None:
    ref = crowdnav.reference()
    prov = ref["provenance"]
    assert len(prov["crowdnav_commit"]) == 40 and len(prov["python_rvo2_commit"]) == 40
    assert prov["command"] and prov["date"]
    for s in crowdnav.SETTINGS:
        m = ref["measured"][s.key]
        assert (m["humans"], m["robot_visible"], m["rule"]) == (s.humans, s.visible, s.family)
        assert m["success"] + m["collision"] + m["timeout"] == m["episodes"] == prov["episodes_per_setting"]
        # CrowdNav's explorer line, kept verbatim, says the same rates.
        assert f"success rate: {m['success'] / m['episodes']:.2f}" in m["explorer_log"][0]


def test_scenes_are_named_and_generated_by_the_core() -> None:
    _scenario, toml = _core.generate("crowdnav/circle_crossing?humans=7&visible=true&seed=3")
    assert toml.count("[[person]]") == 7 and 'reaction = "aware"' in toml
    assert "control_hz = 4.0" in toml and "max_time = 25.0" in toml
    with pytest.raises(Exception, match="humans"):
        _core.generate("crowdnav/circle_crossing?humans=0")


def test_suite_seeds_are_outside_the_tuning_split() -> None:
    assert not set(SEEDS) & set(splits.TUNING_SCENE_SEEDS)


def test_unknown_planner_is_named() -> None:
    with pytest.raises(Exception, match="planner"):
        crowdnav.episodes(crowdnav.SETTINGS[0], [0], "rrt")
    with pytest.raises(InputError, match="planner"):
        crowdnav.run_suite(["astar", "rrt"], 1)


@pytest.mark.parametrize("setting", crowdnav.SETTINGS, ids=lambda s: s.key)
def test_astar_orca_agrees_with_crowdnavs_orca_robot(setting: crowdnav.Setting) -> None:
    """Success and collision rates within 0.06 of CrowdNav's measured run, mean navigation time of
    successes within 10%, over 500 test seeds (the kinematic episodes take a fraction of a second)."""
    ours = crowdnav.summarise(crowdnav.episodes(setting, SEEDS))
    theirs = crowdnav.measured(setting.key)
    ok = crowdnav.agreement(ours, theirs)
    figures = json.dumps({k: ours[k] for k in ("success_rate", "collision_rate", "mean_nav_time_s")})
    assert all(ok.values()), f"{setting.key}: ours {figures}, CrowdNav's {theirs['success_rate']:.3f} / " + (
        f"{theirs['collision_rate']:.3f} / {theirs['mean_nav_time_s']:.2f}: {ok}"
    )


def test_every_built_in_planner_runs_the_suite() -> None:
    """Every planner of eval's list drives the protocol's episodes, counted as CrowdNav counts them."""
    assert set(crowdnav.PLANNERS) == set(_core.PLANNERS)
    rows = crowdnav.run_suite(episodes_per_setting=3)
    assert len(rows) == len(crowdnav.SETTINGS) * len(crowdnav.DRIVES) * len(crowdnav.PLANNERS)
    for r in rows:
        assert r["success"] + r["collision"] + r["timeout"] == r["episodes"] == 3, r
        assert r["seeds"] == "10000-10002"
        assert r["drive"] in crowdnav.DRIVES
    # The planners are not one another: their episodes differ.
    circle20 = {
        r["planner"]: (r["success"], r["collision"], r["mean_nav_time_s"])
        for r in rows
        if r["setting"] == "circle20_invisible" and r["drive"] == "holonomic"
    }
    assert len(set(circle20.values())) > 3, circle20
    # Deterministic: the same seeds give the same records.
    setting = crowdnav.SETTINGS[2]
    for planner in ("social", "learned", "calderita"):
        assert crowdnav.episodes(setting, range(10000, 10003), planner) == crowdnav.episodes(
            setting, range(10000, 10003), planner
        )


def test_suite_table_prints_ours_beside_crowdnavs_and_the_literature() -> None:
    rows = crowdnav.run_suite(["astar_orca", "social"], episodes_per_setting=4)
    text = crowdnav.table_text(rows)
    assert "circle 20, robot invisible" in text and "CrowdNav++ (learned)" in text and "0.92" in text
    assert "CrowdNav's ORCA robot (its code)" in text and "| social |" in text
    assert "Agreement of astar_orca" in text and "Remaining setup differences" in text
    # CrowdNav's ORCA robot has no unicycle: its row is beside the holonomic settings only, and
    # the agreement check compares the holonomic astar_orca alone.
    assert text.count("| CrowdNav's ORCA robot (its code) |") == len(crowdnav.SETTINGS)
    assert text.count("circle 20, robot invisible, unicycle | astar_orca |") == 1
    agreement = text.split("Agreement of astar_orca")[1].split("Literature")[0]
    assert agreement.count("| circle") == 3 and "unicycle" not in agreement


def test_the_unicycle_robot_runs_every_setting_and_is_not_the_holonomic_one() -> None:
    """drive=differential is in each setting's scene name and changes the episodes: a robot that
    turns at most π/4 a step and never moves sideways does not drive the holonomic robot's paths."""
    setting = crowdnav.SETTINGS[0].with_drive("differential")
    assert setting.spec(10_001).endswith("&seed=10001&drive=differential")
    assert "unicycle" in setting.label and "unicycle" not in crowdnav.SETTINGS[0].label
    seeds = range(10_000, 10_020)
    for planner in ("astar_orca", "social"):
        uni = crowdnav.episodes(setting, seeds, planner)
        holo = crowdnav.episodes(crowdnav.SETTINGS[0], seeds, planner)
        assert all(r["spec"].endswith(f"seed={s}&drive=differential") for r, s in zip(uni, seeds, strict=True))
        assert [(r["outcome"], r["time"]) for r in uni] != [(r["outcome"], r["time"]) for r in holo], planner
        assert any(r["outcome"] == "success" for r in uni), planner
    with pytest.raises(InputError, match="drive"):
        crowdnav.SETTINGS[0].with_drive("tracked")
    with pytest.raises(InputError, match="drive"):
        crowdnav.run_suite(["astar"], 1, drives=["holonomic", "tracked"])


def _policy(target: str) -> PolicyRef:
    return PolicyRef(target.rpartition(":")[2], target, str(ROOT))


def test_a_users_policy_drives_the_protocols_episodes() -> None:
    """The policy sees the env's observation, is reset with each scene seed, and its action is
    applied at once: full speed straight at the goal arrives on the 31st step (8 m less the 0.3 m
    radius at 0.25 m a step) on square crossing with one person, unless it hits the person first."""
    import tests.crowdnav_policy as pol

    pol.RESETS.clear()
    setting = crowdnav.Setting("square1", "square_crossing", 1, False)
    seeds = range(10000, 10010)
    records = crowdnav.policy_episodes(setting, seeds, _policy("tests.crowdnav_policy:make"))
    assert pol.RESETS == list(seeds)
    assert {r["outcome"] for r in records} <= {"success", "collision"}
    successes = [r["time"] for r in records if r["outcome"] == "success"]
    assert successes and all(t == 31 * 0.25 for t in successes), records
    again = crowdnav.policy_episodes(setting, seeds, _policy("tests.crowdnav_policy:make"))
    assert again == records
    # The unicycle: the policy gets the differential action space, turns to the goal, then drives.
    uni = crowdnav.policy_episodes(setting.with_drive("differential"), seeds, _policy("tests.crowdnav_policy:make"))
    assert {r["outcome"] for r in uni} <= {"success", "collision"}
    assert [r["time"] for r in uni if r["outcome"] == "success"] == successes, uni
    # A sideways action is refused for the unicycle, by name.
    with pytest.raises(InputError, match=r"action\[0\]\[1\]"):
        crowdnav.policy_episodes(setting.with_drive("differential"), seeds, _policy("tests.crowdnav_policy:sideways"))


def test_bad_policies_are_named() -> None:
    setting = crowdnav.SETTINGS[0]
    with pytest.raises(InputError, match="action"):
        crowdnav.policy_episodes(setting, [10000], _policy("tests/crowdnav_policy.py:nan_action"))
    with pytest.raises(InputError, match="policy"):
        crowdnav.policy_episodes(setting, [10000], _policy("no_such_module:make"))


def _cli(*argv: str) -> subprocess.CompletedProcess[str]:
    env = {**os.environ, "PYTHONPATH": str(ROOT)}
    return subprocess.run(
        [sys.executable, "-m", "proxemic.cli", "eval", "--suite", "crowdnav", *argv],
        capture_output=True,
        text=True,
        timeout=600,
        cwd=ROOT,
        env=env,
    )


def test_cli_runs_planners_and_a_policy_and_names_bad_ones() -> None:
    ok = _cli("--planner", "social", "--policy", "tests/crowdnav_policy.py:make", "--episodes", "2")
    assert ok.returncode == 0, ok.stderr[-2000:]
    assert "| social |" in ok.stdout and "| crowdnav_policy |" in ok.stdout, ok.stdout
    bad = _cli("--planner", "rrt", "--episodes", "1")
    assert bad.returncode == 2 and "--planner 'rrt'" in bad.stderr, bad.stderr
    bad = _cli("--policy", "no_such_module:make", "--episodes", "1")
    assert bad.returncode != 0 and "policy" in bad.stderr, bad.stderr


def test_docs_table_is_what_the_code_gives() -> None:
    """docs/crowdnav.md's generated table (every planner, 500 test seeds per setting) has the rows
    a fresh run gives for astar_orca (CrowdNav's ORCA robot) and learned (the shipped policy)."""
    docs = (ROOT / "docs" / "crowdnav.md").read_text(encoding="utf-8")
    block = docs.partition(crowdnav.DOCS_BEGIN)[2].partition(crowdnav.DOCS_END)[0]
    for planner in crowdnav.PLANNERS:
        assert block.count(f"| {planner} | {crowdnav.EPISODES} |") == len(crowdnav.SETTINGS) * len(crowdnav.DRIVES)
    fresh = crowdnav.table_text(crowdnav.run_suite(["astar_orca", "learned"], crowdnav.EPISODES))
    rows = [line for line in fresh.splitlines() if "| astar_orca |" in line or "| learned |" in line]
    assert len(rows) == 2 * len(crowdnav.SETTINGS) * len(crowdnav.DRIVES)
    for line in rows:
        assert line in block, line


@pytest.mark.full
def test_docs_table_is_what_a_fresh_run_gives_for_every_planner() -> None:
    """Every planner's rows rerun (about 2 minutes): the fast test above checks two planners only,
    and once let the Daza family's rows go stale after their planner changed."""
    docs = (ROOT / "docs" / "crowdnav.md").read_text(encoding="utf-8")
    block = docs.partition(crowdnav.DOCS_BEGIN)[2].partition(crowdnav.DOCS_END)[0]
    fresh = crowdnav.table_text(crowdnav.run_suite(list(crowdnav.PLANNERS), crowdnav.EPISODES))
    rows = [line for line in fresh.splitlines() if any(f"| {p} |" in line for p in crowdnav.PLANNERS)]
    assert len(rows) == len(crowdnav.PLANNERS) * len(crowdnav.SETTINGS) * len(crowdnav.DRIVES)
    for line in rows:
        assert line in block, line
