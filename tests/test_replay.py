"""Recorded crowds from Python: the docs page's example and its ETH/UCY converter run as written,
a replayed person is where the file says in the MuJoCo scene, absent people are parked far away,
and a bad track file is a ScenarioError naming the file, line and column."""

from __future__ import annotations

import re
from pathlib import Path

import numpy as np
import pytest

from proxemic import _core
from proxemic.env import ProxemicEnv
from proxemic.errors import ScenarioError

ROOT = Path(__file__).resolve().parent.parent
PAGE = ROOT / "docs" / "recorded-crowds.md"


def _blocks() -> list[str]:
    return re.findall(r"```python[^\n]*\n(.*?)```", PAGE.read_text(), flags=re.S)


def test_the_docs_example_runs(monkeypatch, capsys, tmp_path):
    # The example writes its track file and scene into the working directory: a temporary one.
    monkeypatch.chdir(tmp_path)
    exec(compile(_blocks()[0], str(PAGE), "exec"), {})
    out = capsys.readouterr().out.split()
    assert out[0] in {"success", "collision", "timeout"}
    assert float(out[1]) > 0.0


SCENE = """
[scene]
name = "converted"
bounds = [-10, -10, 20, 20]

[[robot]]
start = [-9, -9, 0]
goal = [-9, 9]

[[replay]]
file = "tracks.csv"
t0 = {t0}
"""


def test_the_docs_converter_turns_a_social_gan_file_into_a_replay(tmp_path):
    namespace: dict[str, object] = {"__name__": "converter"}
    exec(compile(_blocks()[1], str(PAGE), "exec"), namespace)
    # Social-GAN's format: frame, ped, x, y, tab-separated, one annotation every 10 frames.
    src = tmp_path / "crowds.txt"
    src.write_text(
        "780\t1.0\t8.46\t3.59\n780\t2.0\t9.57\t3.79\n790\t1.0\t9.05\t3.55\n790\t2.0\t9.90\t3.70\n800\t1.0\t9.60\t3.50\n"
    )
    namespace["convert"](str(src), str(tmp_path / "tracks.csv"))  # type: ignore[operator]
    (tmp_path / "scene.toml").write_text(SCENE.format(t0=31.2))
    env = ProxemicEnv(scenario=str(tmp_path / "scene.toml"))
    try:
        env.reset(seed=0)
        persons = env.scenario["persons"]
        assert [p["behaviour"] for p in persons] == ["replay", "replay"]
        np.testing.assert_allclose(
            persons[0]["track"], [[0.0, 8.46, 3.59], [0.4, 9.05, 3.55], [0.8, 9.60, 3.50]], atol=1e-9
        )
        sim = env.unwrapped.ws.sim

        def body(i: int) -> np.ndarray:
            return np.asarray(sim.data.mocap_pos[sim.model.body_mocapid[sim.model.body(f"person_{i}/root").id]])

        ws = env.unwrapped.ws

        def buffer(i: int) -> np.ndarray:
            return np.asarray(ws.people).reshape(-1, _core.PERSON_OUT)[i, :2]

        # Four control steps (0.4 s) later both are at their second sample in the core's people
        # buffer; the physics poses its bodies from that buffer during the next step.
        for _ in range(4):
            env.step(np.zeros(3))
        np.testing.assert_allclose(buffer(0), [9.05, 3.55], atol=1e-9)
        np.testing.assert_allclose(buffer(1), [9.90, 3.70], atol=1e-9)
        env.step(np.zeros(3))
        np.testing.assert_allclose(body(0)[:2], [9.05, 3.55], atol=1e-9)
        np.testing.assert_allclose(body(1)[:2], [9.90, 3.70], atol=1e-9)
        # Person 2's track ends at 0.4 s: at 0.5 s it is parked far away, and its body too a step later.
        np.testing.assert_allclose(buffer(0), [9.05 + 0.55 * 0.25, 3.55 - 0.05 * 0.25], atol=1e-9)
        assert np.linalg.norm(buffer(1)) > 1000.0
        env.step(np.zeros(3))
        assert np.linalg.norm(body(1)[:2]) > 1000.0
    finally:
        env.close()


def test_a_bad_track_file_names_the_file_line_and_column(tmp_path):
    (tmp_path / "tracks.csv").write_text("t,id,x,y\n0,a,0,0\n1,a,1,0\n0.5,a,2,0\n")
    (tmp_path / "scene.toml").write_text(SCENE.format(t0=0))
    with pytest.raises(ScenarioError) as e:
        ProxemicEnv(scenario=str(tmp_path / "scene.toml"))
    assert e.value.file.endswith("tracks.csv")
    assert e.value.field == "replay[0].file line 4, column 1 (t)"
