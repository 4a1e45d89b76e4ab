"""proxemic: an evaluation gym for socially-aware robot navigation.

A Pepper-like holonomic robot among scripted people in MuJoCo scenes (a museum, a care center),
with the per-step planning, pedestrians and metrics computed in a Rust core.

Usage::

    import gymnasium as gym
    import proxemic  # registers the environments

    env = gym.make("proxemic/Museum-v0")
    obs, info = env.reset(seed=0)
"""

from __future__ import annotations

from typing import TYPE_CHECKING, Any

from proxemic import _core
from proxemic.errors import InputError, PlanningError, ProxemicError, ScenarioError, UnknownNameError
from proxemic.registration import ENV_IDS, register_envs

if TYPE_CHECKING:
    from proxemic.evaluation import EvalResult
    from proxemic.parallel import ProxemicParallelEnv

__version__: str = _core.__version__

register_envs()


def parallel_env(*args: Any, **kwargs: Any) -> ProxemicParallelEnv:
    """A PettingZoo ``ParallelEnv`` of a scenario's robots; see :func:`proxemic.parallel.parallel_env`.

    PettingZoo is imported on first use (the ``multi`` extra).
    """
    from proxemic.parallel import parallel_env as make

    return make(*args, **kwargs)


def evaluate(policy: Any = None, **kwargs: Any) -> EvalResult:
    """A policy (and built-in planners) on seeded episodes; see :func:`proxemic.evaluation.evaluate`."""
    from proxemic.evaluation import evaluate as run

    return run(policy, **kwargs)


__all__ = [
    "ENV_IDS",
    "InputError",
    "PlanningError",
    "ProxemicError",
    "ScenarioError",
    "UnknownNameError",
    "__version__",
    "evaluate",
    "parallel_env",
]
