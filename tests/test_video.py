"""Video export: mp4 files that decode to the expected frames, from Python and from the CLI."""

from __future__ import annotations

from pathlib import Path

import imageio.v3 as iio
import numpy as np
import pytest

from proxemic.cli import main
from proxemic.env import ProxemicEnv
from proxemic.errors import InputError
from proxemic.viz.video import episode_frames, record_episode, write_video


def _decode(path: Path) -> np.ndarray:
    return np.asarray(iio.imread(path, plugin="FFMPEG", index=None))


@pytest.mark.parametrize("view", ["topdown", "top"])
def test_record_episode_decodes_to_the_expected_frames(tmp_path: Path, view: str) -> None:
    steps = 30 if view == "topdown" else 10
    out = record_episode(
        "proxemic/Museum-v5",
        "social_astar",
        seed=0,
        path=tmp_path / f"{view}.mp4",
        view=view,
        max_steps=steps,
        width=160,
        height=120,
        overlays=("zones", "groups", "object_spaces", "path"),
    )
    assert out.exists() and out.stat().st_size > 0
    frames = _decode(out)
    assert frames.shape == (steps + 1, 120, 160, 3) and frames.dtype == np.uint8
    assert frames[0].std() > 5.0  # a picture, not a blank frame
    # people walk and the robot drives: the picture changes over time
    assert np.abs(frames[0].astype(int) - frames[-1].astype(int)).mean() > 0.5


def test_a_clip_from_start_step_is_the_same_episode_from_that_step(tmp_path: Path) -> None:
    env = ProxemicEnv("museum", autopilot=True, planner="social", width=96, height=64)
    try:
        whole = list(episode_frames(env, 3, max_steps=8))
        clip = list(episode_frames(env, 3, max_steps=8, start_step=5))
        assert len(whole) == 9 and len(clip) == 4
        assert all(np.array_equal(a, b) for a, b in zip(whole[5:], clip, strict=True))
        with pytest.raises(InputError, match=r"start_step.*ended after 2 steps"):
            list(episode_frames(env, 3, max_steps=2, start_step=5))
    finally:
        env.close()
    out = record_episode(
        "museum", "social", seed=3, path=tmp_path / "clip.mp4", max_steps=8, start_step=5, width=96, height=64
    )
    assert _decode(out).shape == (4, 64, 96, 3)
    for bad, match in ((-1, ">= 0"), (2.5, "whole"), (9, r"<= max_steps \(8\)")):
        with pytest.raises(InputError, match=match):
            record_episode("museum", path=tmp_path / "bad.mp4", max_steps=8, start_step=bad)  # type: ignore[arg-type]
    with pytest.raises(InputError, match="episode's limit"):
        record_episode("museum", path=tmp_path / "bad.mp4", start_step=10**6)
    assert not (tmp_path / "bad.mp4").exists()


def test_write_video_round_trip_and_bad_input(tmp_path: Path) -> None:
    rng = np.random.default_rng(0)
    frames = [np.full((64, 96, 3), v, np.uint8) for v in (0, 128, 255)]
    out = write_video(frames, tmp_path / "a" / "b.mp4", fps=5)
    back = _decode(out)
    assert back.shape == (3, 64, 96, 3)
    # lossy, but flat grey levels come back within a few levels
    assert np.allclose(back.reshape(3, -1).mean(axis=1), [0, 128, 255], atol=4)
    with pytest.raises(InputError, match="even"):
        write_video([np.zeros((63, 96, 3), np.uint8)], tmp_path / "odd.mp4")
    with pytest.raises(InputError, match=r"frames\[1\]"):
        write_video([frames[0], rng.integers(0, 255, (32, 32, 3), dtype=np.uint8)], tmp_path / "mixed.mp4")
    with pytest.raises(InputError, match="at least one frame"):
        write_video([], tmp_path / "empty.mp4")
    with pytest.raises(InputError, match="fps"):
        write_video(frames, tmp_path / "fps.mp4", fps=0)
    with pytest.raises(InputError, match="view"):
        record_episode("museum", path=tmp_path / "v.mp4", view="side")
    with pytest.raises(InputError, match="width"):
        record_episode("museum", path=tmp_path / "v.mp4", width=161)


def test_cli_video_and_eval_video(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    mp4 = tmp_path / "clip.mp4"
    argv = ["video", "--scenario", "museum", "--planner", "social_astar", "--seed", "1", "--out", str(mp4)]
    assert main([*argv, "--max-steps", "5", "--width", "96", "--height", "64", "--overlay", "zones"]) == 0
    assert _decode(mp4).shape == (6, 64, 96, 3)
    assert main([*argv, "--max-steps", "5", "--start-step", "3", "--width", "96", "--height", "64"]) == 0
    assert _decode(mp4).shape == (3, 64, 96, 3)
    out = tmp_path / "eval"
    argv = [
        "eval",
        "--scenario",
        "daza2021_path1",
        "--planner",
        "astar",
        "--episodes",
        "2",
        "--workers",
        "1",
        "--out",
        str(out),
    ]
    assert main([*argv, "--video", "1"]) == 0
    videos = sorted((out / "videos").iterdir())
    assert [v.name for v in videos] == ["astar_seed0.mp4"]
    # the whole episode: one frame per control step plus the start, as many as the recorded steps
    frames = _decode(videos[0])
    rows = (out / "episodes.csv").read_text().splitlines()
    header = rows[0].split(",")
    steps = int(float(rows[1].split(",")[header.index("steps")]))
    assert frames.shape[0] == steps + 1
    assert main(["eval", "--scenario", "daza2021_path1", "--video", "-1"]) == 2
    assert "--video" in capsys.readouterr().err
