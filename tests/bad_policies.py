"""Policy factories that are wrong on purpose, for the errors of ``proxemic eval --policy``."""

from __future__ import annotations

from typing import Any

import numpy as np


def short_action(observation_space: Any, action_space: Any) -> Any:
    """A policy returning 2 numbers instead of 3."""
    return lambda obs: np.zeros(2)


def not_a_policy(observation_space: Any, action_space: Any) -> Any:
    """Returns a number, not a policy."""
    return 3


def no_arguments() -> Any:
    """A factory that does not take the spaces."""
    return lambda obs: np.zeros(3)
