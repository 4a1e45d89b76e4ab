"""The social cost map of a scenario, from Python: layers, groups, plain and social paths, plots.

Example::

    from proxemic.social import SocialMap

    sm = SocialMap("museum", time_of_day="10:30", seed=0)
    plain, social = sm.plan(social=False), sm.plan(social=True)
    sm.plot("social_map.png", paths={"plain A*": plain, "social A*": social})

Everything is computed by the Rust core: the people are placed as at the start of the seeded
episode, perceived (groups, robots joining interactions, feature-adapted Gaussians), and
rasterised with the objects' interaction spaces at R(t) for the given time of day.
"""

from __future__ import annotations

import itertools
import json
import os
import pathlib
from collections.abc import Mapping
from pathlib import Path
from typing import Any, Literal

import numpy as np

from proxemic import _core, scenarios
from proxemic.records import Perception, SocialLayers


def parse_time_of_day(value: str | float | None) -> float | None:
    """Seconds after midnight from ``"HH:MM"``, ``"HH:MM:SS"`` or a number of seconds (None stays None).

    Parsed by the core, as scenario files are (``proxemic._core.parse_time_of_day``).

    Raises:
        InputError: a malformed time, or seconds outside [0, 86400).
    """
    return None if value is None else _core.parse_time_of_day(value)


class SocialMap:
    """The social cost map of one scenario at one time of day (see the module docstring).

    Attributes:
        scenario: The validated scenario dict.
        time_of_day: Seconds after midnight at which object spaces are evaluated.
        layers: ``static``, ``people``, ``objects``, ``combined`` arrays (H, W) and ``grid``
            (origin_x, origin_y, resolution), ``weight`` (see ``proxemic._core.World.social_layers``).
        perception: Groups and individuals (see ``proxemic._core.World.perception``).
        people: (P, 6) x, y, heading, vx, vy, radius of the people.
    """

    def __init__(
        self,
        scenario: str | Path | _core.Scenario,
        *,
        time_of_day: str | float | None = None,
        seed: int = 0,
        robot: int = 0,
    ) -> None:
        """Places the people as at the start of the episode `seed` and builds the map."""
        core, self.scenario = scenarios.load(scenario)
        self.world = _core.World(core)
        self.robot = robot
        out = np.zeros(self.world.num_robots * self.world.stride)
        people = np.zeros(self.world.num_people * _core.PERSON_OUT)
        self.world.reset(int(seed), out, people)
        tod = parse_time_of_day(time_of_day)
        self.time_of_day = self.world.time_of_day if tod is None else tod
        self.layers: SocialLayers = self.world.social_layers(robot, self.time_of_day)
        self.perception: Perception = self.world.perception()
        self.people = np.asarray(self.world.people())

    def plan(
        self,
        start: tuple[float, float] | None = None,
        goal: tuple[float, float] | None = None,
        *,
        social: bool = True,
    ) -> np.ndarray | None:
        """A plain (``social=False``) or social A* path, (K, 2); default the robot's start and goal."""
        r = self.scenario["robots"][self.robot]
        s = (float(r["start"][0]), float(r["start"][1])) if start is None else start
        g = (float(r["goal"][0]), float(r["goal"][1])) if goal is None else goal
        path = self.world.plan(self.robot, s, g, social=social, time_of_day=self.time_of_day)
        return None if path is None else np.asarray(path)

    def factor_along(
        self,
        path: np.ndarray,
        layer: Literal["people", "objects", "static", "combined"] = "people",
        spacing: float = 0.05,
    ) -> np.ndarray:
        """The layer's traversal factor at points every `spacing` metres along `path`."""
        ox, oy, res = self.layers["grid"]
        grid = self.layers[layer]
        pts = []
        for a, b in itertools.pairwise(path):
            n = max(1, int(np.ceil(np.linalg.norm(b - a) / spacing)))
            t = np.linspace(0.0, 1.0, n, endpoint=False)[:, None]
            pts.append(a + t * (b - a))
        pts.append(path[-1:])
        p = np.concatenate(pts)
        ix = np.clip(((p[:, 0] - ox) / res).astype(int), 0, grid.shape[1] - 1)
        iy = np.clip(((p[:, 1] - oy) / res).astype(int), 0, grid.shape[0] - 1)
        return np.asarray(grid[iy, ix])

    def plot(
        self,
        out_png: str | os.PathLike[str],
        *,
        paths: Mapping[str, np.ndarray | None] | None = None,
        title: str | None = None,
        outcomes: Mapping[str, str] | None = None,
    ) -> pathlib.Path:
        """Writes a picture of the map: zones, groups, object spaces by R(t), and `paths`.

        `outcomes` (label -> episode outcome) ends each executed path with its outcome's marker.
        """
        from proxemic.viz.plots import plot_social_map

        groups = [g for g in self.perception["groups"] if len(g) > 1]
        clean = {k: v for k, v in (paths or {}).items() if v is not None}
        hhmm = f"{int(self.time_of_day // 3600):02d}:{int(self.time_of_day % 3600 // 60):02d}"
        return plot_social_map(
            self.scenario,
            self.layers["people"],
            self.layers["objects"],
            self.layers["grid"],
            out_png,
            paths=clean,
            people=self.people[:, :3],
            groups=groups,
            title=title or f"{self.scenario['scene']['name']} at {hhmm}",
            outcomes=outcomes,
        )

    def summary(self) -> dict[str, Any]:
        """Counts for printing: people, groups, individuals, cells by zone."""
        people = self.layers["people"]
        return {
            "people": int(self.people.shape[0]),
            "groups": sum(1 for g in self.perception["groups"] if len(g) > 1),
            "individuals": len(self.perception["individuals"]),
            "intimate_cells": int(np.isinf(people).sum()),
            "object_cells_active": int((self.layers["objects"] > 1.5).sum()),
        }

    def __repr__(self) -> str:
        """Short description."""
        return f"SocialMap({self.scenario['scene']['name']!r}, {json.dumps(self.summary())})"
