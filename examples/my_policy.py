"""A hand-written policy to evaluate beside the built-in planners: ``proxemic eval --policy``.

The robot heads straight for its goal, is pushed away from what its lidar sees closer than 1 m
and from people closer than 1.5 m, slides along what pushes it and slows down near obstacles (a
reactive potential field; no map, no global plan, so the museum's walls between it and the goal
trap or stop it: that is what an evaluation shows).

Run from the repository root::

    proxemic eval --policy examples.my_policy:make --planner astar --episodes 20

or in Python::

    import proxemic
    from examples.my_policy import GoalSeeker

    result = proxemic.evaluate(GoalSeeker(), scenario="museum", episodes=5, planners=["astar"])
"""

from __future__ import annotations

from typing import Any

import numpy as np

#: Obstacles closer than this (m) push the robot away.
OBSTACLE_RANGE = 1.0
#: People closer than this (m) push the robot away.
PERSON_RANGE = 1.5


class GoalSeeker:
    """Goal attraction plus lidar and people repulsion, in the robot frame (holonomic)."""

    def __init__(self, repulsion: float = 0.6, turn_gain: float = 1.0) -> None:
        """`repulsion` weighs the push of obstacles and people against the pull of the goal."""
        self.repulsion, self.turn_gain = repulsion, turn_gain

    def reset(self, seed: int | None) -> None:
        """Called at each episode's start; this policy keeps no state."""

    def __call__(self, obs: dict[str, np.ndarray]) -> np.ndarray:
        """The normalised command (vx, vy, wz) in [-1, 1] for one observation."""
        goal = obs["robot"][:2].astype(np.float64)
        dist = float(np.linalg.norm(goal))
        pull = goal / max(dist, 1e-6)
        ranges = obs["lidar"].astype(np.float64)
        angles = np.linspace(0.0, 2.0 * np.pi, ranges.size, endpoint=False)
        near = ranges < OBSTACLE_RANGE
        weight = np.where(near, 1.0 / np.maximum(ranges, 0.05) - 1.0 / OBSTACLE_RANGE, 0.0)
        push = -np.array([np.sum(weight * np.cos(angles)), np.sum(weight * np.sin(angles))]) / max(ranges.size / 8, 1)
        people = obs["people"][obs["people_mask"] > 0.5, :2].astype(np.float64)
        for p in people:
            d = float(np.linalg.norm(p))
            if 1e-6 < d < PERSON_RANGE:
                push -= (1.0 / d - 1.0 / PERSON_RANGE) * p / d
        v = pull + self.repulsion * push
        norm_push = float(np.linalg.norm(push))
        if norm_push > 1e-6:  # slide along what pushes: the tangent on the goal's side (left on a tie)
            tangent = np.array([-push[1], push[0]]) / norm_push
            tangent *= 1.0 if tangent @ pull >= 0.0 else -1.0
            v += min(norm_push, 1.0) * tangent
        closest = float(ranges.min()) if ranges.size else OBSTACLE_RANGE
        slow = float(np.clip((closest - 0.3) / (OBSTACLE_RANGE - 0.3), 0.2, 1.0))
        v *= slow * min(1.0, dist) / max(float(np.linalg.norm(v)), 1e-6)
        wz = np.clip(self.turn_gain * np.arctan2(goal[1], goal[0]), -1.0, 1.0)
        return np.array([v[0], v[1], wz], dtype=np.float32)


def make(observation_space: Any, action_space: Any) -> GoalSeeker:
    """The factory ``proxemic eval --policy examples.my_policy:make`` calls with the env's spaces."""
    if action_space.shape != (3,) or "lidar" not in observation_space.spaces:
        raise ValueError(f"expected a proxemic env's spaces, got {observation_space} and {action_space}")
    return GoalSeeker()
