"""What an evaluation runs (:class:`EvalConfig`) and what one episode yields (:class:`EpisodeResult`)."""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import numpy as np

from proxemic.policy import PolicyRef

#: The non-social baselines, the default planners of ``proxemic eval`` (without ``--policy``) and of
#: :func:`evaluate`: plain A* blind to people, plain A* followed with ORCA (people do not
#: reciprocate), plain A* that stops for whoever is in its way and re-plans around them after 2 s.
BASELINE_PLANNERS: tuple[str, ...] = ("astar", "astar_orca", "astar_stop")


@dataclass(frozen=True)
class EvalConfig:
    """What to evaluate and where to write it.

    `policies` are user policies (:class:`proxemic.policy.PolicyRef`) evaluated beside the
    built-in `planners`, on the same seeds; both are "planners" in the records' ``planner`` column.
    With ``out=None`` nothing is written.
    """

    scenario: str
    planners: Sequence[str]
    episodes: int = 20
    seed: int = 0
    out: Path | None = Path("out/eval")
    workers: int = 2
    backend: str = "process"
    ray_address: str | None = None
    keep_trajectories: int = 5
    """Episodes per planner whose trajectories are kept for the trajectory plot."""
    policies: Sequence[PolicyRef] = ()
    drive: str | None = None
    """Every robot's drive (``"holonomic"`` or ``"differential"``) instead of the scenario's; None keeps it."""

    @property
    def scene_label(self) -> str:
        """The scenario as titles name it, with the drive when one is imposed."""
        return self.scenario if self.drive is None else f"{self.scenario} ({self.drive} drive)"

    @property
    def labels(self) -> list[str]:
        """The label of every evaluated policy and planner, in task order."""
        return [p.name for p in self.policies] + list(self.planners)

    def tasks(self) -> list[tuple[str, str | PolicyRef, int] | tuple[str, str | PolicyRef, int, str | None]]:
        """(scenario, planner or policy, seed[, drive]) of every episode, policies then planners, planner-major.

        The drive is there only when one is imposed (``drive`` not None).
        """
        who: list[str | PolicyRef] = [*self.policies, *self.planners]
        seeds = [(p, self.seed + k) for p in who for k in range(self.episodes)]
        if self.drive is None:
            return [(self.scenario, p, s) for p, s in seeds]
        return [(self.scenario, p, s, self.drive) for p, s in seeds]


@dataclass
class EpisodeResult:
    """One episode's record and, optionally, its trajectories."""

    record: dict[str, Any]
    robot: np.ndarray | None = field(default=None, repr=False)
    people: np.ndarray | None = field(default=None, repr=False)
    path: np.ndarray | None = field(default=None, repr=False)
    others: list[EpisodeResult] = field(default_factory=list, repr=False)
    """On a multi-robot scene, the other robots' records of the same episode (robot 1, 2, ...)."""
    people_heading: np.ndarray | None = field(default=None, repr=False)
    """(T + 1, P) the people's headings (rad) beside ``people`` (single-robot episodes)."""
    modes: list[str] | None = field(default=None, repr=False)
    """The robot's built-in planner mode at each control step while its episode ran (kept with the
    trajectories; None when not kept or no planner ran): ``"follow_path"``, ``"social_momentum"``,
    ``"orca"``, ``"wait"``, ..."""
