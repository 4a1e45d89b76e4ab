"""Optional extras: a missing package is an error naming the extra that installs it."""

from __future__ import annotations

import runpy
import sys
from pathlib import Path

import pytest

from proxemic.errors import EXTRAS, MissingExtraError, require_extra

ROOT = Path(__file__).resolve().parents[1]


def test_every_extra_in_pyproject_is_named_and_pettingzoo_is_a_core_dependency():
    import tomllib

    project = tomllib.loads((ROOT / "pyproject.toml").read_text())["project"]
    extras = set(project["optional-dependencies"]) - {"dev"}
    assert extras == set(EXTRAS)
    assert any(dep.startswith("pettingzoo") for dep in project["dependencies"])
    assert not any("pettingzoo" in dep for deps in project["optional-dependencies"].values() for dep in deps)


def test_require_extra_names_the_extra_the_feature_and_the_missing_module(monkeypatch):
    monkeypatch.setitem(sys.modules, "imageio_ffmpeg", None)
    with pytest.raises(MissingExtraError) as info:
        require_extra("imageio_ffmpeg", "video", "video export")
    err = info.value
    assert isinstance(err, ImportError)
    assert "pip install 'proxemic[video]'" in str(err) and "video export" in str(err)
    assert (err.field, err.expected, err.found) == ("video export", "pip install 'proxemic[video]'", "imageio_ffmpeg")


def test_video_export_without_imageio_names_the_video_extra(monkeypatch, tmp_path):
    from proxemic.viz import video

    monkeypatch.setitem(sys.modules, "imageio.v2", None)
    with pytest.raises(MissingExtraError, match=r"proxemic\[video\]"):
        video.write_video([], tmp_path / "x.mp4")


def test_ppo_example_without_stable_baselines3_names_the_rl_extra(monkeypatch, tmp_path):
    monkeypatch.setitem(sys.modules, "stable_baselines3", None)
    ns = runpy.run_path(str(ROOT / "examples" / "train_ppo.py"), run_name="example")
    with pytest.raises(MissingExtraError, match=r"proxemic\[rl\]"):
        ns["train"]("daza2021_path3", 10, tmp_path)


def test_supersuit_example_without_supersuit_names_the_multi_extra(monkeypatch):
    monkeypatch.setitem(sys.modules, "supersuit", None)
    with pytest.raises(MissingExtraError, match=r"proxemic\[multi\]"):
        runpy.run_path(str(ROOT / "examples" / "parallel_vec_env.py"), run_name="example")
