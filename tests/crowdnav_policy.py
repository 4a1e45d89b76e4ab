"""A small user policy for the CrowdNav protocol's tests: full speed straight at the goal.

It reads the env's observation (the goal offset in the robot frame, ``obs["robot"][:2]``) and
asks for the normalised velocity toward it at full speed, no turning; a differential robot (its
action space's second value pinned to 0) turns toward the goal at full rate and drives forward
when facing it. It records the episodes it was reset for (:data:`RESETS`).
"""

from __future__ import annotations

from typing import Any

import numpy as np

#: The seeds the policies made here were reset with, in order.
RESETS: list[int | None] = []


class StraightToGoal:
    """Full speed toward the goal, robot frame; `unicycle`: turn toward it, then drive."""

    def __init__(self, unicycle: bool = False) -> None:
        self.unicycle = unicycle

    def reset(self, seed: int | None) -> None:
        """Notes the episode's seed."""
        RESETS.append(seed)

    def __call__(self, obs: dict[str, np.ndarray]) -> np.ndarray:
        """The unit vector toward the goal (vx, vy), no turning."""
        goal = obs["robot"][:2].astype(np.float64)
        if self.unicycle:
            bearing = float(np.arctan2(goal[1], goal[0]))
            forward = 1.0 if abs(bearing) < 0.1 else 0.0
            return np.array([forward, 0.0, np.clip(bearing, -1.0, 1.0)], np.float32)
        return np.array([*(goal / max(float(np.linalg.norm(goal)), 1e-9)), 0.0], np.float32)


def make(observation_space: Any, action_space: Any) -> StraightToGoal:
    """The policy factory of ``proxemic eval --policy tests/crowdnav_policy.py:make``."""
    assert set(observation_space.spaces) == {"robot", "people", "people_mask", "lidar"}
    assert action_space.shape == (3,)
    return StraightToGoal(unicycle=float(action_space.high[1]) == 0.0)


def nan_action(observation_space: Any, action_space: Any) -> Any:
    """A policy whose action is not finite."""
    return lambda obs: np.array([np.nan, 0.0, 0.0])


def sideways(observation_space: Any, action_space: Any) -> Any:
    """A policy that asks for a sideways velocity (refused for a differential robot)."""
    return lambda obs: np.array([0.0, 1.0, 0.0], np.float32)
