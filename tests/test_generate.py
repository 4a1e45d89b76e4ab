"""Generated scenes from Python: proxemic.generate, scenario names, gym.make, parallel_env, the CLI."""

from __future__ import annotations

import json
import subprocess
import sys

import gymnasium as gym
import pytest

import proxemic
from proxemic import _core, scenarios
from proxemic.errors import InputError, ScenarioError, UnknownNameError


def _desc(core: proxemic.Scenario) -> dict:
    d = json.loads(core.to_json())
    d.pop("source", None)
    return d


@pytest.mark.parametrize("seed", range(12))
def test_generated_scene_round_trips_through_its_file(seed: int, tmp_path) -> None:
    params = {"robots": 1 + seed % 3, "density": 1.0 + seed % 4, "encounters": seed % 2}
    core = proxemic.generate(seed, **params)
    path = tmp_path / "scene.toml"
    path.write_text(scenarios.generate_toml(seed, **params))
    back, _ = scenarios.load(str(path))
    assert _desc(back) == _desc(core)
    assert core.num_robots == params["robots"]


def test_same_seed_same_scene() -> None:
    assert scenarios.generate_toml(5) == scenarios.generate_toml(5)
    assert scenarios.generate_toml(5) != scenarios.generate_toml(6)
    assert _desc(proxemic.generate(5)) == _desc(scenarios.load("generated/5")[0])


def test_bad_parameters_are_typed_errors() -> None:
    with pytest.raises(ScenarioError, match="robots"):
        proxemic.generate(0, robots=0)
    with pytest.raises(ScenarioError, match="density"):
        proxemic.generate(0, density=99)
    with pytest.raises(UnknownNameError, match="colour"):
        proxemic.generate(0, colour=1)
    with pytest.raises(InputError, match="seed"):
        proxemic.generate(-1)
    with pytest.raises(ScenarioError, match="seed"):
        scenarios.load("generated/abc")
    with pytest.raises(ScenarioError, match="width"):
        _core.generate("generated/1?width=wide")


def test_generated_scenes_run_in_gym_parallel_env_and_eval() -> None:
    env = gym.make("proxemic/Generated-v5", scenario="generated/3?robots=2")
    obs, _ = env.reset(seed=0)
    obs2, *_ = env.step(env.action_space.sample())
    assert set(obs) == set(obs2)
    env.close()
    penv = proxemic.parallel_env("generated/4?robots=3")
    obs, _ = penv.reset(seed=0)
    assert sorted(obs) == ["robot_0", "robot_1", "robot_2"]
    penv.close()
    res = proxemic.evaluate(scenario="generated/2", planners=["astar"], episodes=1, workers=1)
    assert len(res.records) == 1


def test_parallel_env_samples_extra_robots_in_a_bundled_scene() -> None:
    """The museum has one robot in its file; 4 robots get sampled starts and goals (the same every time)."""
    env = proxemic.parallel_env("museum", robots=4)
    obs, _ = env.reset(seed=0)
    assert len(obs) == 4
    env.close()
    a = json.loads(scenarios.load("museum")[0].with_robots(4).to_json())["robots"]
    b = json.loads(scenarios.load("museum")[0].with_robots(4).to_json())["robots"]
    assert [(r["start"], r["goal"]) for r in a] == [(r["start"], r["goal"]) for r in b]
    with pytest.raises(ScenarioError, match="robots"):
        proxemic.parallel_env("museum", robots=9)


def test_cli_generate_writes_a_loadable_scene(tmp_path) -> None:
    out = tmp_path / "scene.toml"
    cmd = [sys.executable, "-m", "proxemic.cli", "generate", "--seed", "7", "--robots", "2", "--out", str(out)]
    done = subprocess.run(cmd, capture_output=True, text=True, check=False)
    assert done.returncode == 0, done.stderr
    core, _ = scenarios.load(str(out))
    assert core.num_robots == 2
    assert _desc(core) == _desc(proxemic.generate(7, robots=2))
    bad = subprocess.run([*cmd[:-2], "--density", "50", "--out", str(out)], capture_output=True, text=True, check=False)
    assert bad.returncode == 2 and "density" in bad.stderr


def _docs_params() -> dict[str, tuple[float, float, float]]:
    """The parameter table of docs/generated.md: name -> (default, low, high)."""
    import re
    from pathlib import Path

    text = (Path(__file__).resolve().parents[1] / "docs" / "generated.md").read_text()
    rows = re.findall(r"^\| `(\w+)` \| [^|]+ \| ([\d.]+) \| \[([\d.]+), ([\d.]+)\] \|", text, flags=re.M)
    return {name: (float(d), float(lo), float(hi)) for name, d, lo, hi in rows}


def test_the_docs_parameter_table_is_the_cores() -> None:
    """docs/generated.md lists every generator parameter with the core's default and range."""
    table = _docs_params()
    assert list(table) == [k for k in scenarios.GENERATE_PARAMS if k not in ("reaction", "drive")]
    default_toml = scenarios.generate_toml(3)
    for name, row in table.items():
        integer = name in ("objects_per_room", "robots", "encounters")
        default, low, high = (int(v) for v in row) if integer else row
        step = 1 if integer else 0.01
        assert scenarios.generate_toml(3, **{name: default}) == default_toml, f"{name}: default {default}"
        # the two shares of the non-group people sum to at most 1: each bound with the other at 0
        others = {"walker_share": 0.0} if name == "seated_share" else {}
        others = {"seated_share": 0.0} if name == "walker_share" else others
        for ok in (low, high):
            scenarios.generate_toml(3, **{name: ok}, **others)
        for bad in (low - step, high + step):
            if bad < 0:
                continue
            with pytest.raises(ScenarioError, match=name):
                scenarios.generate_toml(3, **{name: bad}, **others)


def test_the_reaction_parameter_is_a_name_documented_with_its_values() -> None:
    """``reaction`` takes the names of docs/generated.md's row; others are errors."""
    import re
    from pathlib import Path

    text = (Path(__file__).resolve().parents[1] / "docs" / "generated.md").read_text()
    row = re.search(r"^\| `reaction` \| name \| `aware` \| ([^|]+) \|", text, flags=re.M)
    assert row is not None
    names = re.findall(r"`(\w+)`", row.group(1))
    assert names == ["ignore", "aware", "yield", "curious", "cautious"]
    assert scenarios.generate_toml(3, reaction="aware") == scenarios.generate_toml(3)
    for name in names:
        scene = proxemic.generate(3, reaction=name)
        assert {p["reaction"] for p in json.loads(scene.to_json())["persons"]} == {name}
    with pytest.raises(ScenarioError, match="reaction"):
        proxemic.generate(3, reaction="shy")
    with pytest.raises(InputError, match="reaction"):
        proxemic.generate(3, reaction=1.0)


def test_the_docs_example_runs(capsys) -> None:
    import re
    from pathlib import Path

    text = (Path(__file__).resolve().parents[1] / "docs" / "generated.md").read_text()
    (block,) = re.findall(r"```python\n(.*?)```", text, flags=re.S)
    exec(compile(block, "docs/generated.md", "exec"), {})
    assert capsys.readouterr().out.count(" ran\n") == 3


def test_the_drive_parameter_is_a_name_documented_with_its_values() -> None:
    """``drive`` takes the names of docs/generated.md's row, on every family's scene name; others are errors."""
    import re
    from pathlib import Path

    from proxemic import francis2023

    text = (Path(__file__).resolve().parents[1] / "docs" / "generated.md").read_text()
    row = re.search(r"^\| `drive` \| name \| `holonomic` \| ([^|]+) \|", text, flags=re.M)
    assert row is not None
    names = re.findall(r"`(\w+)`", row.group(1))
    assert names == ["holonomic", "differential"]
    assert scenarios.generate_toml(3, drive="holonomic") == scenarios.generate_toml(3)
    for name in names:
        scene = proxemic.generate(3, drive=name, robots=2)
        assert {r.get("drive", "holonomic") for r in json.loads(scene.to_json())["robots"]} == {name}
    francis = francis2023.scenario_name("crossing_90", 3, drive="differential")
    assert francis == "francis2023/crossing_90?seed=3&drive=differential"
    crowdnav = "crowdnav/square_crossing?seed=3&drive=differential"
    for name in (francis, crowdnav):
        _core_scene, desc = scenarios.load(name)
        assert [r["drive"] for r in desc["robots"]] == ["differential"], name
    with pytest.raises(ScenarioError, match="drive"):
        proxemic.generate(3, drive="tank")
    with pytest.raises(ScenarioError, match="drive"):
        scenarios.load("crowdnav/square_crossing?drive=differential&drive=differential")
    with pytest.raises(InputError, match="drive"):
        proxemic.generate(3, drive=1.0)
    with pytest.raises(InputError, match="drive"):
        francis2023.scenario_name("crossing_90", drive=1)  # type: ignore[arg-type]
