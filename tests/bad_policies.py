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


def complex_action(observation_space: Any, action_space: Any) -> Any:
    """A policy returning complex numbers (env.step refuses them)."""
    return lambda obs: np.zeros(3, dtype=complex)


def bool_action(observation_space: Any, action_space: Any) -> Any:
    """A policy returning booleans (env.step refuses them)."""
    return lambda obs: np.array([True, False, True])


def raises_in_factory(observation_space: Any, action_space: Any) -> Any:
    """A factory that fails."""
    raise RuntimeError("no weights file")


def _raise(obs: Any) -> Any:
    raise ZeroDivisionError("division by zero in the policy")


def raises_at_step(observation_space: Any, action_space: Any) -> Any:
    """A policy that raises at its first step."""
    return _raise


def _exit(obs: Any) -> Any:
    import sys

    sys.exit(3)


def exits_at_step(observation_space: Any, action_space: Any) -> Any:
    """A policy that calls sys.exit at its first step."""
    return _exit
