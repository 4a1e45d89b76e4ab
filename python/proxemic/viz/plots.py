"""Matplotlib figures for proxemic: episode trajectories on the map, metric bar charts, tables.

Figures are built on :class:`matplotlib.figure.Figure` with an explicit Agg canvas, so nothing here
touches pyplot's global state or needs a display.
"""

from __future__ import annotations

import math
import os
import pathlib
from collections.abc import Mapping, Sequence
from typing import Any

import numpy as np
from matplotlib import colormaps
from matplotlib.axes import Axes
from matplotlib.backends.backend_agg import FigureCanvasAgg
from matplotlib.figure import Figure
from matplotlib.lines import Line2D
from matplotlib.patches import Patch
from matplotlib.patches import Polygon as PolygonPatch
from matplotlib.ticker import MaxNLocator

from proxemic import markdown
from proxemic.errors import input_error
from proxemic.palette import DEFAULT_OBJECT_COLOR, FLOOR_COLOR, INTERACTION_COLOR, OBJECT_COLORS, WALL_COLOR
from proxemic.viz.geometry import interaction_polygon, object_polygon, scene_bounds, wall_polygon

__all__ = [
    "format_table",
    "plot_episodes",
    "plot_metrics_grid",
    "plot_social_map",
    "plot_tune",
]

#: End-of-trajectory marker per episode outcome.
OUTCOME_MARKERS: Mapping[str, str] = {"success": "*", "collision": "X", "timeout": "s"}
_UNKNOWN_OUTCOME_MARKER = "o"
_PEOPLE_COLOR = "0.55"
_DPI = 120


def _rgb(color: Sequence[int]) -> tuple[float, float, float]:
    """Convert a 0-255 RGB tuple to matplotlib's 0-1 floats."""
    r, g, b = (c / 255.0 for c in color)
    return (r, g, b)


def _darker(color: Sequence[int], amount: float = 0.45) -> tuple[float, float, float]:
    """Return ``color`` darkened towards black by ``amount`` (0-1), as 0-1 floats."""
    r, g, b = ((1.0 - amount) * c / 255.0 for c in color)
    return (r, g, b)


def _episode_colors(n: int) -> list[tuple[float, float, float]]:
    """Return ``n`` categorical colours (tab10, cycled)."""
    base = np.asarray(colormaps["tab10"](np.arange(10)), dtype=np.float64)[:, :3]  # its 10 colours, exactly
    out: list[tuple[float, float, float]] = []
    for i in range(n):
        r, g, b = (float(v) for v in base[i % len(base)])
        out.append((r, g, b))
    return out


def _draw_map(ax: Axes, scenario: Mapping[str, Any]) -> list[Any]:
    """Draw floor, interaction spaces, objects and walls; return legend proxies for what was drawn."""
    xmin, ymin, xmax, ymax = scene_bounds(scenario)
    ax.add_patch(
        PolygonPatch(
            [(xmin, ymin), (xmax, ymin), (xmax, ymax), (xmin, ymax)],
            closed=True,
            facecolor=_rgb(FLOOR_COLOR),
            edgecolor="none",
            zorder=0,
        )
    )
    handles: list[Any] = []
    objects = list(scenario.get("objects", []))
    space_color = _rgb(INTERACTION_COLOR)
    any_space = False
    for obj in objects:
        space = interaction_polygon(obj)
        if space is None:
            continue
        any_space = True
        ax.add_patch(PolygonPatch(space, closed=True, facecolor=(*space_color, 0.25), edgecolor="none", zorder=1))
        ax.add_patch(
            PolygonPatch(
                space,
                closed=True,
                fill=False,
                hatch="///",
                edgecolor=_darker(INTERACTION_COLOR, 0.25),
                linewidth=0.6,
                zorder=1,
            )
        )
    if any_space:
        handles.append(
            Patch(
                facecolor=(*space_color, 0.25),
                hatch="///",
                edgecolor=_darker(INTERACTION_COLOR, 0.25),
                label="interaction space",
            )
        )
    kinds_seen: list[str] = []
    for obj in objects:
        kind = str(obj.get("kind", "object"))
        color = OBJECT_COLORS.get(kind, DEFAULT_OBJECT_COLOR)
        alpha = 1.0 if obj.get("solid", True) else 0.5
        ax.add_patch(
            PolygonPatch(
                object_polygon(obj),
                closed=True,
                facecolor=(*_rgb(color), alpha),
                edgecolor=_darker(color),
                linewidth=0.8,
                zorder=2,
            )
        )
        if kind not in kinds_seen:
            kinds_seen.append(kind)
            handles.append(Patch(facecolor=_rgb(color), edgecolor=_darker(color), label=kind.replace("_", " ")))
    walls = list(scenario.get("walls", []))
    for wall in walls:
        ax.add_patch(
            PolygonPatch(wall_polygon(wall), closed=True, facecolor=_rgb(WALL_COLOR), edgecolor="none", zorder=3)
        )
    if walls:
        handles.insert(0, Patch(facecolor=_rgb(WALL_COLOR), label="wall"))
    return handles


def _episode_goal(scenario: Mapping[str, Any], episode: Mapping[str, Any]) -> np.ndarray | None:
    """The episode's goal: its own ``goal`` key, else the goal of scenario robot ``robot_index``."""
    goal = episode.get("goal")
    if goal is None:
        robots = scenario.get("robots", [])
        idx = int(episode.get("robot_index", 0))
        if 0 <= idx < len(robots):
            goal = robots[idx].get("goal")
    if goal is None:
        return None
    return np.asarray(goal, dtype=np.float64)[:2]


def plot_episodes(
    scenario: Mapping[str, Any],
    episodes: Sequence[Mapping[str, Any]],
    out_png: str | os.PathLike[str],
    *,
    title: str | None = None,
) -> pathlib.Path:
    """Plot robot (and people) trajectories of several episodes over the scenario map.

    The map shows the floor, walls, objects coloured by kind and hatched interaction spaces. Each
    episode's robot trajectory is a solid line in the episode's colour with a circle at the start and
    an outcome marker at the end (star: success, X: collision, square: timeout, circle: anything
    else); its planned path is dashed in the same colour and its goal is a hollow diamond. People's
    trajectories are thin grey lines with a dot at their last position.

    Args:
        scenario: The scenario dict.
        episodes: Episode dicts with keys ``label`` (str), ``robot`` (``(T, 3)`` x, y, theta),
            ``people`` (``(T, P, 2)``, P may be 0, or None), ``path`` (``(K, 2)`` or None),
            ``outcome`` (``"success"``, ``"collision"`` or ``"timeout"``) and optionally ``color``
            (any matplotlib colour; default tab10 by episode index), ``goal`` (``[x, y]``; default
            the goal of scenario robot ``robot_index``, itself default 0).
        out_png: Output PNG path; parent directories are created.
        title: Figure title; defaults to the scene name.

    Returns:
        The path written.

    Raises:
        InputError: If an episode's ``robot`` or ``people`` array has the wrong shape.

    """
    out = pathlib.Path(out_png)
    xmin, ymin, xmax, ymax = scene_bounds(scenario)
    span_x, span_y = max(xmax - xmin, 1e-6), max(ymax - ymin, 1e-6)
    fig_w = 8.0
    fig_h = float(np.clip(fig_w * span_y / span_x, 3.0, 14.0)) + 0.8
    fig = Figure(figsize=(fig_w, fig_h), dpi=_DPI)
    FigureCanvasAgg(fig)
    ax = fig.add_subplot()
    map_handles = _draw_map(ax, scenario)

    defaults = _episode_colors(len(episodes))
    episode_handles: list[Any] = []
    any_path = False
    any_people = False
    for i, ep in enumerate(episodes):
        color = ep.get("color") or defaults[i]
        label = str(ep.get("label", f"episode {i}"))
        robot = np.asarray(ep.get("robot", np.zeros((0, 3))), dtype=np.float64)
        if robot.size == 0:
            robot = np.zeros((0, 3))
        if robot.ndim != 2 or robot.shape[1] < 2:
            raise input_error(f"episodes[{i}].robot", f"shape (T, 3) (episode {label!r})", f"shape {robot.shape}")

        people_raw = ep.get("people")
        people = np.zeros((0, 0, 2)) if people_raw is None else np.asarray(people_raw, dtype=np.float64)
        if people.size > 0:
            if people.ndim != 3 or people.shape[2] < 2:
                raise input_error(
                    f"episodes[{i}].people", f"shape (T, P, 2) (episode {label!r})", f"shape {people.shape}"
                )
            any_people = True
            for p in range(people.shape[1]):
                traj = people[:, p, :2]
                ax.plot(traj[:, 0], traj[:, 1], color=_PEOPLE_COLOR, linewidth=0.7, alpha=0.8, zorder=4)
                finite = np.nonzero(np.all(np.isfinite(traj), axis=1))[0]
                if len(finite):
                    last = traj[finite[-1]]
                    ax.plot([last[0]], [last[1]], "o", color=_PEOPLE_COLOR, markersize=4, zorder=4)

        path = ep.get("path")
        if path is not None:
            path_a = np.asarray(path, dtype=np.float64)
            if path_a.ndim == 2 and path_a.shape[0] >= 2 and path_a.shape[1] >= 2:
                any_path = True
                ax.plot(
                    path_a[:, 0],
                    path_a[:, 1],
                    linestyle="--",
                    color=color,
                    linewidth=1.2,
                    alpha=0.8,
                    zorder=5,
                )

        (line,) = ax.plot(robot[:, 0], robot[:, 1], color=color, linewidth=2.0, label=label, zorder=6)
        episode_handles.append(line)
        if len(robot):
            ax.plot(
                [robot[0, 0]],
                [robot[0, 1]],
                "o",
                color=color,
                markeredgecolor="black",
                markersize=7,
                zorder=7,
            )
            marker = OUTCOME_MARKERS.get(str(ep.get("outcome")), _UNKNOWN_OUTCOME_MARKER)
            ax.plot(
                [robot[-1, 0]],
                [robot[-1, 1]],
                marker,
                color=color,
                markeredgecolor="black",
                markersize=13 if marker == "*" else 10,
                zorder=8,
            )
        goal = _episode_goal(scenario, ep)
        if goal is not None:
            ax.plot(
                [goal[0]],
                [goal[1]],
                "D",
                markerfacecolor="none",
                markeredgecolor=color,
                markeredgewidth=2.0,
                markersize=9,
                zorder=7,
            )

    marker_handles: list[Any] = [
        Line2D([], [], linestyle="none", marker="o", color="0.6", markeredgecolor="black", label="start"),
        Line2D(
            [],
            [],
            linestyle="none",
            marker="D",
            markerfacecolor="none",
            markeredgecolor="black",
            label="goal",
        ),
        Line2D(
            [],
            [],
            linestyle="none",
            marker="*",
            markersize=11,
            color="0.6",
            markeredgecolor="black",
            label="success",
        ),
        Line2D([], [], linestyle="none", marker="X", color="0.6", markeredgecolor="black", label="collision"),
        Line2D([], [], linestyle="none", marker="s", color="0.6", markeredgecolor="black", label="timeout"),
    ]
    if any_path:
        marker_handles.append(Line2D([], [], linestyle="--", color="0.3", label="planned path"))
    if any_people:
        marker_handles.append(Line2D([], [], color=_PEOPLE_COLOR, marker="o", markersize=4, label="people"))
    ax.legend(
        handles=episode_handles + marker_handles + map_handles,
        loc="upper left",
        bbox_to_anchor=(1.01, 1.0),
        fontsize=8,
        frameon=False,
    )

    pad = 0.3
    ax.set_xlim(xmin - pad, xmax + pad)
    ax.set_ylim(ymin - pad, ymax + pad)
    ax.set_aspect("equal")
    ax.set_xlabel("x [m]")
    ax.set_ylabel("y [m]")
    ax.set_title(title if title is not None else str(scenario.get("scene", {}).get("name", "")))
    ax.grid(True, linewidth=0.3, alpha=0.5)
    ax.set_axisbelow(True)

    out.parent.mkdir(parents=True, exist_ok=True)
    fig.savefig(out, format="png", bbox_inches="tight", metadata={"Software": None})
    return out


def _as_float(value: Any) -> float:
    """Convert a table cell to float, mapping None and non-numbers to NaN."""
    if value is None or isinstance(value, (bool, np.bool_)):
        return math.nan
    try:
        return float(value)
    except (TypeError, ValueError):
        return math.nan


#: Panels per row of :func:`plot_metrics_grid`.
GRID_COLUMNS = 5


def plot_metrics_grid(
    table: Sequence[Mapping[str, Any]],
    groups: Sequence[tuple[str, Sequence[tuple[str, str, str]]]],
    out_png: str | os.PathLike[str],
    *,
    group_key: str = "planner",
    title: str | None = None,
) -> pathlib.Path:
    """Small multiples of aggregated metrics: one row of panels per group, one bar per planner.

    Each panel is a horizontal bar chart (planners on the y axis, the same colour in every panel)
    with a whisker from ``<metric>_lo`` to ``<metric>_hi`` (the 95% interval, already clipped to
    the metric's bounds) and the value written beside it. A metric with unit ``"%"`` and values
    ``"rate"`` (a fraction of episodes in [0, 1]) is drawn as a percentage on a 0-100 axis.

    Args:
        table: One row per planner with ``<metric>``, ``<metric>_lo`` and ``<metric>_hi``.
        groups: ``(group name, [(metric, label, unit), ...])`` in row order; a group of more than
            :data:`GRID_COLUMNS` metrics wraps onto further rows.
        out_png: Output PNG path; parent directories are created.
        group_key: The row key naming the planner.
        title: Figure title.

    Returns:
        The path written.

    Raises:
        InputError: If `groups` has no metric.
    """
    rows_of_panels: list[tuple[str, list[tuple[str, str, str]]]] = []
    for name, metrics in groups:
        metrics = list(metrics)
        for k in range(0, len(metrics), GRID_COLUMNS):
            rows_of_panels.append((name if k == 0 else f"{name} (cont.)", metrics[k : k + GRID_COLUMNS]))
    if not rows_of_panels:
        raise input_error("groups", "at least one metric name", "none")
    out = pathlib.Path(out_png)
    names = [str(row.get(group_key, "?")) for row in table]
    colors = _episode_colors(len(names))
    n = len(names)
    panel_h = 0.9 + 0.32 * n
    fig = Figure(figsize=(2.9 * GRID_COLUMNS, panel_h * len(rows_of_panels) + 0.9), dpi=100, layout="constrained")
    FigureCanvasAgg(fig)
    subfigs = fig.subfigures(len(rows_of_panels), 1, squeeze=False)[:, 0]
    y = np.arange(n, dtype=np.float64)[::-1]
    for subfig, (group, metrics) in zip(subfigs, rows_of_panels, strict=True):
        subfig.suptitle(group, x=0.0, ha="left", fontsize=11, fontweight="bold")
        axes = subfig.subplots(1, GRID_COLUMNS, squeeze=False)[0]
        for k, ax in enumerate(axes):
            if k >= len(metrics):
                ax.set_visible(False)
                continue
            metric, label, unit = metrics[k]
            values = np.array([_as_float(row.get(metric)) for row in table])
            lo = np.array([_as_float(row.get(f"{metric}_lo")) for row in table])
            hi = np.array([_as_float(row.get(f"{metric}_hi")) for row in table])
            pct = unit == "rate"
            scale = 100.0 if pct else 1.0
            values, lo, hi = values * scale, lo * scale, hi * scale
            ax.barh(y, np.nan_to_num(values), color=colors, edgecolor="black", linewidth=0.5, height=0.7)
            whisker = np.isfinite(values) & np.isfinite(lo) & np.isfinite(hi)
            if np.any(whisker):
                err = np.vstack([values - lo, hi - values])[:, whisker]
                ax.errorbar(
                    values[whisker],
                    y[whisker],
                    xerr=np.clip(err, 0.0, None),
                    fmt="none",
                    ecolor="black",
                    elinewidth=1.0,
                    capsize=3,
                )
            finite = values[np.isfinite(values)]
            reach = np.where(whisker, hi, values)
            span = float(np.nanmax(np.abs(np.r_[reach, finite, 0.0])))
            span = span if span > 1e-9 else 1.0  # all zero: a plain 0-1 axis
            for yi, v, r in zip(y, values, reach, strict=True):
                text = "n/a" if not np.isfinite(v) else (f"{v:.0f}%" if pct else f"{v:.3g}")
                x0 = r if np.isfinite(r) else 0.0
                ax.text(x0 + 0.03 * span, yi, text, va="center", ha="left", fontsize=8)
            ax.set_xlim(min(0.0, float(np.nanmin(np.r_[lo, finite, 0.0]))) * 1.15, span * 1.35)
            if pct:
                ax.set_xticks([0, 25, 50, 75, 100])
            else:
                ax.xaxis.set_major_locator(MaxNLocator(nbins=4))
            ax.set_yticks(y, names if k == 0 else [""] * n, fontsize=9)
            ax.tick_params(axis="x", labelsize=8)
            unit_text = "%" if pct else unit
            ax.set_title(f"{label}" + (f" ({unit_text})" if unit_text else ""), fontsize=9)
            ax.grid(True, axis="x", linewidth=0.3, alpha=0.6)
            ax.set_axisbelow(True)
            ax.set_ylim(-0.6, n - 0.4)
    if title:
        fig.suptitle(title, fontsize=10)
    out.parent.mkdir(parents=True, exist_ok=True)
    fig.savefig(out, format="png", metadata={"Software": None})
    return out


def _format_cell(value: Any, floatfmt: str) -> str:
    """Format one markdown table cell."""
    if value is None:
        return "\u2013"
    if isinstance(value, (bool, np.bool_)):
        return "yes" if value else "no"
    if isinstance(value, (float, np.floating)):
        return format(float(value), floatfmt)
    if isinstance(value, (int, np.integer)):
        return str(int(value))
    return str(value).replace("|", "\\|").replace("\n", " ")


def format_table(rows: Sequence[Mapping[str, Any]], columns: Sequence[str], *, floatfmt: str = ".3f") -> str:
    """Format rows as a markdown table.

    Args:
        rows: Row dicts; a column missing from a row is rendered like None.
        columns: Column keys, in order; they are also the header.
        floatfmt: Format spec for floats (``format(value, floatfmt)``).

    Returns:
        The table: a header row, a ``---`` separator row and one row per dict, each line written as
        ``| a | b |`` and joined with newlines (no trailing newline). None is rendered as an en dash
        (U+2013), bools as ``yes``/``no``, ints as is and ``|`` in text escaped.

    """
    return markdown.table(
        [str(c) for c in columns], ([_format_cell(row.get(c), floatfmt) for c in columns] for row in rows)
    )


def plot_social_map(
    scenario: Mapping[str, Any],
    people_factor: np.ndarray,
    object_factor: np.ndarray,
    grid: tuple[float, float, float],
    out_png: str | os.PathLike[str],
    *,
    paths: Mapping[str, np.ndarray] | None = None,
    people: np.ndarray | None = None,
    groups: Sequence[Sequence[int]] | None = None,
    title: str | None = None,
    outcomes: Mapping[str, str] | None = None,
) -> pathlib.Path:
    """Draw the social cost map: people's zones, object spaces coloured by R(t), paths.

    Args:
        scenario: The validated scenario dict.
        people_factor: (H, W) traversal factors of the people layer (1 free, inf forbidden).
        object_factor: (H, W) traversal factors of the object layer (R(t) inside interaction spaces).
        grid: (origin_x, origin_y, resolution) of the layers; row 0 is the lowest y.
        out_png: Where to write the figure.
        paths: Label -> (K, 2) path, e.g. ``{"plain A*": ..., "social A*": ...}``.
        people: (P, 3) x, y, heading of the people, drawn with a heading tick.
        groups: Member index lists of detected groups, outlined together.
        title: Figure title.
        outcomes: Label -> episode outcome of an executed path: its end gets the outcome's marker
            (:data:`OUTCOME_MARKERS`, as in :func:`plot_episodes`). Paths without one (planned
            paths) end with a hollow diamond.

    Returns:
        The path written.
    """
    out = pathlib.Path(out_png)
    out.parent.mkdir(parents=True, exist_ok=True)
    fig = Figure(figsize=(10.0, 6.4))
    FigureCanvasAgg(fig)
    ax = fig.add_subplot(1, 1, 1)
    handles = _draw_map(ax, scenario)
    ox, oy, res = grid
    h, w = people_factor.shape
    extent = (ox, ox + w * res, oy, oy + h * res)

    def overlay(layer: np.ma.MaskedArray, cmap: str, vmin: float, vmax: float, alpha: float, zorder: float) -> Any:
        return ax.imshow(
            layer,
            origin="lower",
            extent=extent,
            cmap=cmap,
            vmin=vmin,
            vmax=vmax,
            alpha=alpha,
            zorder=zorder,
            interpolation="nearest",
        )

    objects = np.ma.masked_where(object_factor <= 1.0, object_factor)
    if objects.count():
        im = overlay(objects, "YlOrRd", 1.0, 4.0, 0.75, 1.5)
        cb = fig.colorbar(im, ax=ax, fraction=0.03, pad=0.01)
        cb.set_label("object space cost R(t)")
    finite = np.where(np.isfinite(people_factor), people_factor, np.nan)
    zones = np.ma.masked_where(~(people_factor > 1.0), finite)
    if zones.count():
        overlay(zones, "Blues", 1.0, 5.0, 0.6, 1.6)
        handles.append(Patch(facecolor=(0.4, 0.6, 0.85, 0.6), label="personal / social zones"))
    lethal = np.ma.masked_where(~np.isinf(people_factor), np.ones_like(people_factor))
    if lethal.count():
        overlay(lethal, "Greys", 0.0, 1.2, 0.85, 1.7)
        handles.append(Patch(facecolor="0.2", label="intimate zone (forbidden)"))
    if people is not None and len(people):
        ax.scatter(people[:, 0], people[:, 1], s=28, color="0.15", zorder=5)
        tick = 0.45
        for x, y, th in people[:, :3]:
            ax.plot([x, x + tick * math.cos(th)], [y, y + tick * math.sin(th)], color="0.15", lw=1.2, zorder=5)
        handles.append(Line2D([], [], marker="o", color="0.15", ls="", label="person (facing)"))
    if groups and people is not None:
        for members in groups:
            if len(members) < 2:
                continue
            pts = people[list(members), :2]
            c = pts.mean(axis=0)
            r = float(np.max(np.linalg.norm(pts - c, axis=1))) + 0.4
            ax.add_patch(
                PolygonPatch(
                    [(c[0] + r * math.cos(a), c[1] + r * math.sin(a)) for a in np.linspace(0, 2 * math.pi, 40)],
                    closed=True,
                    fill=False,
                    edgecolor="purple",
                    linestyle="--",
                    lw=1.2,
                    zorder=5,
                )
            )
        handles.append(Line2D([], [], color="purple", ls="--", label="detected group"))
    colors = _episode_colors(len(paths or {}))
    for (label, path), color in zip((paths or {}).items(), colors, strict=True):
        if path is None or len(path) == 0:
            continue
        ax.plot(path[:, 0], path[:, 1], color=color, lw=2.2, zorder=6)
        ax.plot(path[0, 0], path[0, 1], "o", color=color, zorder=6)
        outcome = (outcomes or {}).get(label)
        if outcome is None:
            ax.plot(path[-1, 0], path[-1, 1], "D", mfc="none", color=color, zorder=6)
        else:
            marker = OUTCOME_MARKERS.get(outcome, _UNKNOWN_OUTCOME_MARKER)
            size = 15 if marker == "*" else 11
            ax.plot(path[-1, 0], path[-1, 1], marker, color=color, mec="black", ms=size, zorder=7)
        handles.append(Line2D([], [], color=color, lw=2.2, label=label if outcome is None else f"{label}: {outcome}"))
    if outcomes:
        for outcome, marker in OUTCOME_MARKERS.items():
            handles.append(
                Line2D([], [], ls="", marker=marker, color="0.6", mec="black", ms=9, label=f"end: {outcome}")
            )
    xmin, ymin, xmax, ymax = scene_bounds(scenario)
    ax.set_xlim(xmin - 0.3, xmax + 0.3)
    ax.set_ylim(ymin - 0.3, ymax + 0.3)
    ax.set_aspect("equal")
    ax.set_xlabel("x [m]")
    ax.set_ylabel("y [m]")
    if title:
        ax.set_title(title)
    ax.legend(handles=handles, loc="upper left", bbox_to_anchor=(1.12, 1.0), fontsize=8, frameon=False)
    fig.savefig(out, dpi=_DPI, bbox_inches="tight")
    return out


def plot_tune(
    trials: Sequence[Mapping[str, Any]], gains: Sequence[str], out_png: str | os.PathLike[str]
) -> pathlib.Path:
    """The gain search of ``proxemic tune``: G per trial with the best so far, and G against each gain.

    Args:
        trials: One row per evaluated gain point, in order, with ``G``, ``varied`` and every gain.
        gains: The tuned gains' names (one scatter panel each).
        out_png: Output PNG path; parent directories are created.

    Returns:
        The path written.

    """
    out = pathlib.Path(out_png)
    g = np.array([_as_float(t.get("G")) for t in trials], dtype=np.float64)
    fig = Figure(figsize=(4.2 * (1 + len(gains)), 3.6), dpi=_DPI, layout="constrained")
    FigureCanvasAgg(fig)
    axes = fig.subplots(1, 1 + len(gains), squeeze=False)[0]
    varied = [str(t.get("varied", "")) for t in trials]
    kinds = list(dict.fromkeys(varied))
    colors = dict(zip(kinds, _episode_colors(len(kinds)), strict=True))
    x = np.arange(len(trials))
    ax = axes[0]
    ax.scatter(x, g, c=[colors[v] for v in varied], s=18, edgecolors="black", linewidths=0.4, zorder=3)
    ax.step(x, np.fmin.accumulate(g) if g.size else g, where="post", color="black", linewidth=1.2, label="best so far")
    ax.set_xlabel("trial")
    ax.set_ylabel("G")
    ax.set_title("G per trial")
    handles = [Line2D([], [], marker="o", linestyle="", color=colors[k], label=f"varied: {k}") for k in kinds]
    ax.legend(handles=[*handles, Line2D([], [], color="black", label="best so far")], fontsize=7)
    best = int(np.nanargmin(g)) if np.isfinite(g).any() else None
    for axg, name in zip(axes[1:], gains, strict=True):
        v = np.array([_as_float(t.get(name)) for t in trials], dtype=np.float64)
        axg.scatter(v, g, c=[colors[k] for k in varied], s=18, edgecolors="black", linewidths=0.4, zorder=3)
        if best is not None:
            axg.scatter([v[best]], [g[best]], marker="*", s=160, color="gold", edgecolors="black", zorder=4)
        axg.set_xlabel(name.replace("_", " "))
        axg.set_title(f"G against {name.replace('_', ' ')}")
    for a in axes:
        a.grid(True, linewidth=0.3, alpha=0.6)
    out.parent.mkdir(parents=True, exist_ok=True)
    fig.savefig(out, format="png", metadata={"Software": None})
    return out
