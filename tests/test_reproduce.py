"""`proxemic reproduce`: published numbers come from the data file, ours from the episodes run."""

from __future__ import annotations

import csv
import json
import math

import pytest

from proxemic import _core, scenarios
from proxemic.cli import main
from proxemic.errors import InputError
from proxemic.reproduce import experiments, published, reproduce


def test_daza2021_report_puts_published_beside_measured(tmp_path):
    out = tmp_path / "daza"
    report = reproduce("daza2021", out, episodes=1, seed=3)
    assert (out / "report.md").read_text() == report
    with (out / "episodes.csv").open() as fh:
        rows = list(csv.DictReader(fh))
    assert len(rows) == 10  # 5 paths x (social, astar)
    for k, exp in enumerate(experiments("daza2021"), start=1):
        assert (out / f"{k}_{exp.scene}.png").stat().st_size > 0
        social = next(r for r in rows if r["experiment"] == exp.name and r["planner"] == "social")
        assert social["seed"] == "3"
        # the report's row holds the published value from the data file and our measured value
        ours = f"{float(social['l_ratio']):.2f}" if social["l_ratio"] else "n/a"
        assert any(
            line.startswith(f"| l_ratio | {exp.published['l_ratio']:g} | {ours}") for line in report.splitlines()
        ), exp.name
    assert published()["daza2021"]["average"] == {"l_ratio": 0.84, "smooth": 0.43}
    assert "## Why ours differ" in report


def test_calderita_start_time_override_changes_the_scene(tmp_path):
    exp = experiments("calderita")[0]
    assert exp.start_time == "09:05"
    from proxemic.reproduce import scene_of

    _, own = scenarios.load(exp.scene)
    scene = scene_of(exp)
    _core_scenario, desc = scenarios.load(scene)
    assert math.isclose(desc["scene"]["start_time"], 9 * 3600 + 5 * 60)
    assert not math.isclose(own["scene"]["start_time"], desc["scene"]["start_time"])


def test_unknown_paper_is_a_clear_error(tmp_path, capsys):
    with pytest.raises(InputError, match="paper: expected one of daza2021"):
        experiments("nobody2020")
    with pytest.raises(SystemExit) as e:
        main(["reproduce", "nobody2020", "--out", str(tmp_path)])
    assert e.value.code == 2
    assert "invalid choice" in capsys.readouterr().err


def test_episode_metrics_before_reset_is_an_input_error():
    core, _ = scenarios.load("museum")
    world = _core.World(core)
    with pytest.raises(InputError, match="episode_metrics"):
        world.episode_metrics()


def test_published_data_cites_its_sources():
    data = published()
    for paper in ("daza2021", "sousa2022", "calderita"):
        assert data[paper]["source"]
        assert json.dumps(data[paper]["experiment"])
