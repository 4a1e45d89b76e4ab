"""Geometry of the validated scenario dict for the 2D views: wall, object and interaction polygons.

The core computes the polygons once, when the scenario is validated (``polygon``, ``footprint``,
``interaction.polygon``); these helpers read them as numpy arrays.
"""

from __future__ import annotations

from collections.abc import Mapping
from typing import Any

import numpy as np


def _polygon(points: Any) -> np.ndarray:
    """``points`` (a polygon of the validated scenario) as an ``(N, 2)`` float array."""
    return np.asarray(points, dtype=np.float64).reshape(-1, 2)


def wall_polygon(wall: Mapping[str, Any]) -> np.ndarray:
    """A wall's world-frame footprint, ``(N, 2)`` vertices in metres (the core's ``polygon``).

    Args:
        wall: A wall entry of the validated scenario dict (``scenarios.load``).
    """
    return _polygon(wall["polygon"])


def object_polygon(obj: Mapping[str, Any]) -> np.ndarray:
    """An object's world-frame footprint, ``(N, 2)`` vertices in metres (the core's ``footprint``).

    Args:
        obj: An object entry of the validated scenario dict.
    """
    return _polygon(obj["footprint"])


def interaction_polygon(obj: Mapping[str, Any]) -> np.ndarray | None:
    """An object's interaction-space polygon (the core's ``interaction.polygon``), or None without one.

    Args:
        obj: An object entry of the validated scenario dict.
    """
    inter = obj.get("interaction")
    return None if not inter else _polygon(inter["polygon"])


def scene_bounds(scenario: Mapping[str, Any]) -> tuple[float, float, float, float]:
    """The scene bounds ``(xmin, ymin, xmax, ymax)`` in metres (``scene.bounds`` of the validated scenario)."""
    xmin, ymin, xmax, ymax = (float(v) for v in scenario["scene"]["bounds"])
    return xmin, ymin, xmax, ymax
