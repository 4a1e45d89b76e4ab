"""The CLI's names: planners listed in --help, env ids accepted wherever a scenario is, "did you
mean" for a misspelt scenario or planner, "file not found" for a missing scenario file."""

from __future__ import annotations

import csv

import pytest

import proxemic
from proxemic import scenarios
from proxemic.cli import main
from proxemic.errors import ScenarioError, UnknownNameError
from proxemic.evaluation import BASELINE_PLANNERS
from proxemic.tuning import TUNABLE_PLANNERS


@pytest.mark.parametrize("command", ["eval", "demo", "video", "tune"])
def test_help_lists_every_planner(command, capsys):
    with pytest.raises(SystemExit) as info:
        main([command, "--help"])
    assert info.value.code == 0
    text = " ".join(capsys.readouterr().out.split())  # argparse wraps the help text
    # tune takes only the planners with tunable gains (an elastic band)
    listed = TUNABLE_PLANNERS if command == "tune" else proxemic.PLANNERS
    for planner in listed:
        assert planner in text, f"{command} --help does not list {planner}"
    assert "proxemic/Museum-v5" in text  # env ids are accepted


def test_new_planners_show_up_in_help(monkeypatch, capsys):
    """The list is read from proxemic.PLANNERS when the parser is built, not typed in."""
    monkeypatch.setattr(proxemic, "PLANNERS", [*proxemic.PLANNERS, "brand_new_planner"])
    with pytest.raises(SystemExit):
        main(["eval", "--help"])
    assert "brand_new_planner" in capsys.readouterr().out


@pytest.mark.parametrize(("env_id", "name"), sorted(proxemic.ENV_IDS.items()))
def test_every_env_id_resolves_to_its_bundled_file(env_id, name):
    assert scenarios.resolve(env_id) == scenarios.resolve(name)


def test_eval_accepts_an_env_id(tmp_path, capsys):
    out = tmp_path / "e"
    args = ["eval", "--scenario", "proxemic/Daza2021Path1-v4", "--episodes", "1", "--workers", "1", "--out", str(out)]
    assert main(args) == 0, capsys.readouterr().err
    with (out / "episodes.csv").open() as fh:
        rows = list(csv.DictReader(fh))
    # eval's default planners are the non-social baselines
    assert [(r["scenario"], r["planner"], r["robot"]) for r in rows] == [
        ("daza2021_path1", p, "0") for p in BASELINE_PLANNERS
    ]
    assert list(BASELINE_PLANNERS) == ["astar", "astar_orca", "astar_stop"]


def test_tune_and_video_accept_an_env_id():
    from proxemic.tuning import TuneConfig

    TuneConfig(targets=["proxemic/CalderitaExp1-v6"], planner="eband").check()  # no error
    env = proxemic.ProxemicEnv("proxemic/CalderitaExp1-v6")
    assert env.scenario["scene"]["name"] == "calderita_exp1"
    env.close()


@pytest.mark.parametrize(
    ("given", "suggested"),
    [("musuem", "museum"), ("care_centre", "care_center"), ("proxemic/Musem-v4", "proxemic/Museum-v5")],
)
def test_a_misspelt_scenario_gets_did_you_mean(given, suggested, capsys):
    assert main(["eval", "--scenario", given, "--episodes", "1"]) == 2
    err = capsys.readouterr().err
    assert f"unknown scenario {given!r} (did you mean {suggested!r}?)" in err
    assert "Traceback" not in err
    with pytest.raises(UnknownNameError, match="did you mean"):
        scenarios.resolve(given)


def test_a_misspelt_planner_gets_did_you_mean(capsys):
    assert main(["eval", "--planner", "socail", "--episodes", "1"]) == 2
    err = capsys.readouterr().err
    assert "planner: expected one of" in err and "got \"socail\" (did you mean 'social'?)" in err
    assert main(["video", "--planner", "astra"]) == 2
    assert "(did you mean 'astar'?)" in capsys.readouterr().err
    with pytest.raises(ScenarioError, match="did you mean 'eband'"):
        proxemic.ProxemicEnv("museum", planner="ebnad")


def test_a_missing_scenario_file_is_file_not_found(tmp_path, capsys):
    missing = tmp_path / "nope.toml"
    assert main(["eval", "--scenario", str(missing), "--episodes", "1"]) == 2
    err = capsys.readouterr().err
    assert f"file not found: {missing}" in err and "unknown scenario" not in err
    assert main(["video", "--scenario", str(tmp_path / "scenes" / "mine")]) == 2
    assert f"file not found: {tmp_path / 'scenes' / 'mine'}" in capsys.readouterr().err
    with pytest.raises(ScenarioError, match="file not found"):
        proxemic.ProxemicEnv(missing)
