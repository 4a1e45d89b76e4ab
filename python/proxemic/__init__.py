"""proxemic: an evaluation gym for socially-aware robot navigation.

A Pepper-like holonomic robot among scripted people in MuJoCo scenes (a museum, a care center),
with the per-step planning, pedestrians and metrics computed in a Rust core.

Usage::

    import gymnasium as gym
    import proxemic  # registers the environments

    env = gym.make("proxemic/Museum-v5")
    obs, info = env.reset(seed=0)

Public names: the environments (:class:`ProxemicEnv`, :func:`parallel_env`,
:class:`ProxemicParallelEnv`, :func:`vector_env`, ``ENV_IDS``), the validated scenario of the core (:class:`Scenario`)
and the names it accepts (``PLANNERS``, ``EBAND_GAINS``), :func:`parse_time_of_day`, and the
exception hierarchy under :class:`ProxemicError`. The metrics are described in ``docs/metrics.md``
and the algorithms in ``docs/algorithms.md``.
"""

from __future__ import annotations

import importlib
import importlib.util
from typing import TYPE_CHECKING, Any

from proxemic import _core
from proxemic._core import EBAND_GAINS, PLANNERS, Scenario, parse_time_of_day
from proxemic.errors import (
    EpisodeError,
    InputError,
    InvariantError,
    NeedsResetError,
    PlanningError,
    PolicyError,
    ProxemicError,
    ScenarioError,
    UnknownNameError,
)
from proxemic.registration import ENV_IDS, register_envs

if TYPE_CHECKING:
    from proxemic.env import ProxemicEnv
    from proxemic.evaluation import EvalResult
    from proxemic.parallel import ProxemicParallelEnv
    from proxemic.vector import ProxemicVectorEnv

__version__: str = _core.__version__

register_envs()


def parallel_env(*args: Any, **kwargs: Any) -> ProxemicParallelEnv:
    """A PettingZoo ``ParallelEnv`` of a scenario's robots; see :func:`proxemic.parallel.parallel_env`.

    PettingZoo is imported on first use (the ``multi`` extra).
    """
    from proxemic.parallel import parallel_env as make

    return make(*args, **kwargs)


def vector_env(*args: Any, **kwargs: Any) -> ProxemicVectorEnv:
    """N worlds of a scenario as a gymnasium ``VectorEnv`` in one core call; see :func:`proxemic.vector.vector_env`."""
    from proxemic.vector import vector_env as make

    return make(*args, **kwargs)


def __getattr__(name: str) -> Any:
    """The environment classes and the submodules, imported on first use.

    ``proxemic.env.ProxemicEnv``, ``proxemic.policy.joint_policy`` or ``proxemic.viz.video`` work
    after a plain ``import proxemic`` (MuJoCo, PettingZoo and matplotlib load only when used).
    """
    if name == "ProxemicEnv":
        from proxemic.env import ProxemicEnv

        return ProxemicEnv
    if name == "ProxemicParallelEnv":
        from proxemic.parallel import ProxemicParallelEnv

        return ProxemicParallelEnv
    if not name.startswith("_") and importlib.util.find_spec(f"{__name__}.{name}") is not None:
        return importlib.import_module(f"{__name__}.{name}")
    raise AttributeError(f"module 'proxemic' has no attribute {name!r}")


def generate(seed: int, **params: float | str) -> Scenario:
    """A generated scene as a scenario; see :func:`proxemic.scenarios.generate`."""
    from proxemic.scenarios import generate as make

    return make(seed, **params)


def evaluate(policy: Any = None, **kwargs: Any) -> EvalResult:
    """A policy (and built-in planners) on seeded episodes; see :func:`proxemic.evaluation.evaluate`."""
    from proxemic.evaluation import evaluate as run

    return run(policy, **kwargs)


__all__ = [
    "EBAND_GAINS",
    "ENV_IDS",
    "PLANNERS",
    "EpisodeError",
    "InputError",
    "InvariantError",
    "NeedsResetError",
    "PlanningError",
    "PolicyError",
    "ProxemicEnv",
    "ProxemicError",
    "ProxemicParallelEnv",
    "Scenario",
    "ScenarioError",
    "UnknownNameError",
    "__version__",
    "evaluate",
    "generate",
    "parallel_env",
    "parse_time_of_day",
    "vector_env",
]
