"""Video export (mp4) of proxemic episodes: frames from any view, written with imageio + ffmpeg.

Example::

    from proxemic.viz.video import record_episode

    record_episode("museum", "social_astar", seed=0, path="museum.mp4", view="topdown",
                   overlays=("zones", "groups", "object_spaces", "path"))

Frames come from :func:`render_frame`: the numpy top-down view (``"topdown"``, with the chosen
overlays) or MuJoCo offscreen from the top camera (``"top"``) or the camera following the robot
(``"follow"``). The episode is the one ``proxemic eval`` runs for the same scenario, planner and
seed (the robot's built-in planner drives; the same seed gives the same episode, bit for bit).
Writing needs ``imageio`` and ``imageio-ffmpeg`` (``pip install "proxemic[video]"``).
"""

from __future__ import annotations

import os
from collections.abc import Iterable, Iterator
from pathlib import Path
from typing import TYPE_CHECKING, Any

import numpy as np

from proxemic.errors import InputError, input_error, require_extra
from proxemic.viz.topdown import FRAME_SIZE

if TYPE_CHECKING:
    from proxemic.env import ProxemicEnv

__all__ = ["VIEWS", "check_video_path", "record_episode", "render_frame", "write_video"]

#: The views a frame can be rendered from.
VIEWS: tuple[str, ...] = ("topdown", "top", "follow")


def _imageio() -> Any:
    """Import ``imageio`` with its ffmpeg plugin, or raise a clear ImportError."""
    iio = require_extra("imageio.v2", "video", "video export")
    require_extra("imageio_ffmpeg", "video", "video export")  # the ffmpeg binary imageio's writer uses
    return iio


def check_video_path(path: str | os.PathLike[str], field: str = "out") -> Path:
    """`path` as the :class:`Path` of a video file that can be written, or an :class:`InputError`.

    Checked before any frame is made (ffmpeg would otherwise fail after the episode with
    ``[Errno 32] Broken pipe``): a suffix ffmpeg writes (imageio's list: ``.mp4``, ``.mkv``...),
    not a directory, its folder created and the file creatable. `field` is the argument named
    in the message (``--out`` for the CLI).

    Raises:
        InputError: Naming `field`, what was expected and the path that arrived.
        MissingExtraError: imageio or imageio-ffmpeg is not installed.
    """
    _imageio()
    from imageio.config import extension_list

    suffixes = sorted(e.extension for e in extension_list if "FFMPEG" in e.priority)
    out = Path(path)
    expected = f"the path of a video file to write ({', '.join(suffixes)})"
    if out.is_dir():
        raise input_error(field, expected, f"{os.fspath(path)!r}, a directory")
    if out.suffix.lower() not in suffixes:
        raise input_error(field, expected, f"{os.fspath(path)!r}, a {out.suffix or 'missing'} suffix")
    try:
        out.parent.mkdir(parents=True, exist_ok=True)
        out.open("wb").close()
    except OSError as e:
        raise input_error(field, expected + " that can be written", f"{os.fspath(path)!r} ({e.strerror or e})") from e
    return out


def _check_view(view: str) -> None:
    if view not in VIEWS:
        raise input_error("view", f"one of {list(VIEWS)}", view)


def render_frame(env: Any, view: str = "topdown", overlays: Iterable[str] | None = None) -> np.ndarray:
    """Render the current state of a proxemic env from `view`, whatever its ``render_mode``.

    Args:
        env: A :class:`proxemic.env.ProxemicEnv` (or a gymnasium wrapper of one) after ``reset``.
        view: ``"topdown"`` (numpy 2D view), ``"top"`` (MuJoCo top camera) or ``"follow"``
            (MuJoCo camera following the robot).
        overlays: For the top-down view: overlays to draw (see
            :meth:`proxemic.env.ProxemicEnv.set_overlays`); default the env's.

    Returns:
        A ``(env.height, env.width, 3)`` uint8 RGB image.

    Raises:
        InputError: An unknown view.
    """
    _check_view(view)
    base: ProxemicEnv = env.unwrapped
    if view == "topdown":
        return base.render_topdown(overlays)
    from proxemic.sim import ensure_gl_backend

    ensure_gl_backend()
    camera = "top" if view == "top" else "robot_0/follow"
    return base.sim.render(base.width, base.height, camera)


def write_video(
    frames: Iterable[np.ndarray],
    path: str | os.PathLike[str],
    fps: float = 10.0,
    *,
    total: int | None = None,
    progress: bool = False,
    field: str = "out",
) -> Path:
    """Write RGB frames to an H.264 mp4 file, streaming (frames are not kept in memory).

    Args:
        frames: ``(H, W, 3)`` uint8 images, all the same size; H and W must be even (yuv420p).
        path: The output file (``.mp4``, or another suffix ffmpeg writes); parent folders are created.
        fps: Frames per second of the video (> 0).
        total: The number of frames, if known (for the progress bar).
        progress: Show a tqdm progress bar on stderr.
        field: The name of `path` in error messages (``--out`` for the CLI).

    Returns:
        The path written.

    Raises:
        InputError: A non-positive fps; a path (named `field`) that is a directory, has no video
            suffix, cannot be created or that ffmpeg fails to write; no frames, or a frame of the
            wrong shape, dtype or size.
        ImportError: imageio or imageio-ffmpeg is not installed.
    """
    if not (fps > 0 and np.isfinite(fps)):
        raise input_error("fps", "a positive number", fps)
    out = check_video_path(path, field)
    iio = _imageio()

    def ffmpeg_failed(e: Exception) -> InputError:
        return input_error(field, "the path of a video file ffmpeg can write", f"{os.fspath(path)!r} ({e})")

    bar = None
    if progress:
        from tqdm import tqdm

        bar = tqdm(total=total, desc=out.name, unit="frame")
    writer = None
    shape: tuple[int, ...] | None = None
    count = 0
    try:
        for frame in frames:
            a = np.asarray(frame)
            if shape is None:
                if a.ndim != 3 or a.shape[2] != 3 or a.dtype != np.uint8 or a.shape[0] % 2 or a.shape[1] % 2:
                    raise input_error(
                        "frames[0]", "an (H, W, 3) uint8 image with even H and W", f"shape {a.shape} dtype {a.dtype}"
                    )
                shape = a.shape
                try:
                    writer = iio.get_writer(
                        str(out), format="FFMPEG", mode="I", fps=fps, codec="libx264", macro_block_size=1, quality=7
                    )
                except (OSError, RuntimeError, ValueError) as e:
                    raise ffmpeg_failed(e) from e
            elif a.shape != shape or a.dtype != np.uint8:
                raise input_error(
                    f"frames[{count}]", f"{shape} uint8 like the first frame", f"shape {a.shape} dtype {a.dtype}"
                )
            if writer is not None:
                try:
                    writer.append_data(a)
                except (OSError, RuntimeError, ValueError) as e:  # ffmpeg died (a full disk: Broken pipe)
                    raise ffmpeg_failed(e) from e
            count += 1
            if bar is not None:
                bar.update(1)
    finally:
        if writer is not None:
            try:
                writer.close()
            except (OSError, RuntimeError, ValueError) as e:
                raise ffmpeg_failed(e) from e
        if bar is not None:  # the episode may end before `total`: the bar ends where it did
            bar.total = count
            bar.refresh()
            bar.close()
    if count == 0:
        raise input_error("frames", "at least one frame", "none")
    return out


def episode_frames(
    env: Any,
    seed: int,
    *,
    view: str = "topdown",
    max_steps: int | None = None,
    overlays: Iterable[str] | None = None,
    metrics: dict[str, Any] | None = None,
    start_step: int = 0,
) -> Iterator[np.ndarray]:
    """Yield the frames of one autopilot episode: after ``reset(seed)``, then after every step.

    The episode runs until it terminates, is truncated, or `max_steps` steps were taken, so it
    yields at most ``max_steps + 1`` frames. Frames before step `start_step` are neither rendered
    nor yielded (the episode itself still runs from its reset, so it is the same episode). `metrics`,
    if given, is filled with the robot's metrics when the last frame has been yielded (``outcome``
    is ``running`` if `max_steps` stopped it first).

    Raises:
        InputError: The episode ended before `start_step` (named ``start_step``, with its length).
    """
    _check_view(view)
    base: ProxemicEnv = env.unwrapped
    base.reset(seed=seed)
    if start_step == 0:
        yield render_frame(base, view, overlays)
    action = np.zeros(3, dtype=np.float32)
    steps = 0
    while max_steps is None or steps < max_steps:
        _, _, terminated, truncated, _ = base.step(action)
        steps += 1
        if steps >= start_step:
            yield render_frame(base, view, overlays)
        if terminated or truncated:
            break
    if steps < start_step:
        raise input_error("start_step", f"a step the episode reaches (it ended after {steps} steps)", start_step)
    if metrics is not None:
        metrics.update(base.metrics())


def record_episode(
    scenario: str | os.PathLike[str],
    planner: str | None = None,
    seed: int = 0,
    path: str | os.PathLike[str] = "episode.mp4",
    *,
    view: str = "topdown",
    fps: float | None = None,
    max_steps: int | None = None,
    width: int = FRAME_SIZE[0],
    height: int = FRAME_SIZE[1],
    overlays: Iterable[str] = ("path",),
    progress: bool = False,
    metrics: dict[str, Any] | None = None,
    field: str = "out",
    drive: str | None = None,
    start_step: int = 0,
) -> Path:
    """Record one seeded episode with the robot's built-in planner driving, as an mp4.

    Args:
        scenario: A bundled scenario name, a scenario TOML path or a registered env id
            (``"proxemic/Museum-v5"``).
        planner: The robot's planner (one of ``proxemic._core.PLANNERS``); default the scenario's.
        seed: The episode seed (the same episode as ``proxemic eval`` runs with this seed).
        path: The output file.
        view: ``"topdown"``, ``"top"`` or ``"follow"`` (see :func:`render_frame`).
        fps: Frames per second; default the control rate (real time).
        max_steps: Stop after this many steps (default: the end of the episode).
        width: Frame width in pixels (even).
        height: Frame height in pixels (even).
        overlays: Overlays of the top-down view (see :meth:`proxemic.env.ProxemicEnv.set_overlays`).
        progress: Show a progress bar (it ends at the episode's last frame).
        metrics: Filled with the episode's metrics (``outcome``, ``time_to_goal`` ...) once recorded.
        field: The name of `path` in error messages (``--out`` for the CLI).
        drive: Every robot's drive (``"holonomic"`` or ``"differential"``); default the scenario's.
        start_step: The first step recorded (default 0, the reset): a clip of the episode from
            ``start_step`` to its end or to `max_steps`, e.g. one encounter. The episode still runs
            from its reset, so the clip shows the same episode as ``proxemic eval``'s.

    Returns:
        The path written. The video has one frame per control step from `start_step` to the last,
        both included (with the default `start_step` 0: every step plus the starting frame).

    Raises:
        InputError: A bad view, size, fps, max_steps or start_step (negative, beyond `max_steps` or
            beyond the episode's end), or a path that cannot be written (named
            `field`, checked before the episode runs); ScenarioError / UnknownNameError for a bad
            scenario or planner.
        ImportError: imageio or imageio-ffmpeg is not installed.
    """
    from proxemic.env import ProxemicEnv
    from proxemic.registration import ENV_IDS
    from proxemic.world import check_frame_size

    _check_view(view)
    if max_steps is not None and max_steps < 0:
        raise input_error("max_steps", "a number >= 0", max_steps)
    if isinstance(start_step, bool) or not isinstance(start_step, int | np.integer) or start_step < 0:
        raise input_error("start_step", "a whole step number >= 0", start_step)
    if max_steps is not None and start_step > max_steps:
        raise input_error("start_step", f"a step number <= max_steps ({max_steps})", start_step)
    check_frame_size(width, height)
    for side, value in (("width", width), ("height", height)):
        if value < 2 or value % 2:
            raise input_error(side, "an even number of pixels >= 2 (H.264 in yuv420p)", value)
    out = check_video_path(path, field)
    try:
        name: str | Path = ENV_IDS.get(str(scenario), str(scenario)) if isinstance(scenario, str) else Path(scenario)
        env = ProxemicEnv(
            name, autopilot=True, planner=planner, width=width, height=height, overlays=overlays, drive=drive
        )
        try:
            episode_steps = int(env.core_scenario.max_steps)
            steps = episode_steps if max_steps is None else min(max_steps, episode_steps)
            if start_step > episode_steps:
                raise input_error(
                    "start_step", f"a step number <= the episode's limit ({episode_steps} steps)", start_step
                )
            frames = episode_frames(env, seed, view=view, max_steps=max_steps, metrics=metrics, start_step=start_step)
            rate = float(env.metadata["render_fps"]) if fps is None else fps
            return write_video(frames, out, rate, total=steps + 1 - start_step, progress=progress, field=field)
        finally:
            env.close()
    except BaseException:
        if out.is_file() and out.stat().st_size == 0:  # made by check_video_path; no frame was written
            out.unlink()
        raise
