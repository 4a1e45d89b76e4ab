"""A small user policy for the CrowdNav protocol's tests: full speed straight at the goal.

It reads the env's observation (the goal offset in the robot frame, ``obs["robot"][:2]``) and
asks for the normalised velocity toward it at full speed, no turning; it records the episodes
it was reset for (:data:`RESETS`).
"""

from __future__ import annotations

from typing import Any

import numpy as np

#: The seeds the policies made here were reset with, in order.
RESETS: list[int | None] = []


class StraightToGoal:
    """Full speed toward the goal, robot frame."""

    def reset(self, seed: int | None) -> None:
        """Notes the episode's seed."""
        RESETS.append(seed)

    def __call__(self, obs: dict[str, np.ndarray]) -> np.ndarray:
        """The unit vector toward the goal (vx, vy), no turning."""
        goal = obs["robot"][:2].astype(np.float64)
        return np.array([*(goal / max(float(np.linalg.norm(goal)), 1e-9)), 0.0], np.float32)


def make(observation_space: Any, action_space: Any) -> StraightToGoal:
    """The policy factory of ``proxemic eval --policy tests/crowdnav_policy.py:make``."""
    assert set(observation_space.spaces) == {"robot", "people", "people_mask", "lidar"}
    assert action_space.shape == (3,)
    return StraightToGoal()


def nan_action(observation_space: Any, action_space: Any) -> Any:
    """A policy whose action is not finite."""
    return lambda obs: np.array([np.nan, 0.0, 0.0])
