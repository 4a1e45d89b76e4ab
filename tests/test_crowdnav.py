"""CrowdNav's protocol: the scenes, the reference data and the agreement with CrowdNav's own run."""

from __future__ import annotations

import json

import pytest

from proxemic import _core, crowdnav, splits

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
        crowdnav.episodes(crowdnav.SETTINGS[0], [0], "social")


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


def test_suite_table_prints_ours_beside_crowdnavs_and_the_literature() -> None:
    rows = crowdnav.run_suite(episodes_per_setting=4)
    assert len(rows) == len(crowdnav.SETTINGS) * len(crowdnav.PLANNERS)
    text = crowdnav.table_text(rows)
    assert "circle 20, robot invisible" in text and "CrowdNav++ (learned)" in text and "0.92" in text
    assert "Remaining setup differences" in text
