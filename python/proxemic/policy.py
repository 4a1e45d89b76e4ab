"""The policy protocol: how a user's controller or trained agent drives a proxemic robot.

A **policy** is any of:

* a callable ``policy(obs) -> action``, optionally with a ``reset(seed)`` method called at the
  start of every episode with the episode's seed;
* an object with ``predict(obs, deterministic=True)`` returning ``action`` or
  ``(action, state)`` (the stable-baselines3 convention; ``reset(seed)`` is called if present).

``obs`` is the env's observation (a dict of float32 arrays, see :class:`proxemic.env.ProxemicEnv`)
and ``action`` anything convertible to a float array of the action space's shape ``(3,)`` (a
leading batch axis of 1, as ``predict`` may return, is dropped).

For several robots (:func:`proxemic.parallel_env`), a policy is either one shared policy, called
for every agent with that agent's observation, or a mapping ``agent -> policy``
(:func:`joint_policy`).

A **policy factory** is a callable ``make(observation_space, action_space) -> policy``; the CLI and
the worker processes build policies from a factory's import path ``"package.module:make"`` (or
``"path/to/file.py:make"``), so each worker makes its own (see :func:`load_factory`).
"""

from __future__ import annotations

import importlib
import importlib.util
import inspect
import os
import sys
from collections.abc import Callable, Mapping
from dataclasses import dataclass
from pathlib import Path
from typing import Any, Protocol, runtime_checkable

import numpy as np

from proxemic.errors import PolicyError, check_action, input_error

__all__ = [
    "FlatObservation",
    "Policy",
    "PolicyActor",
    "PolicyRef",
    "PredictPolicy",
    "build_policy",
    "check_policy",
    "flat_observation_env",
    "joint_policy",
    "load_factory",
    "observation_scales",
]

_EXPECTED_FACTORY = "an import path 'module:factory' (or 'file.py:factory') naming a callable"
_EXPECTED_POLICY = "a callable obs -> action, or an object with predict(obs, deterministic=True)"


def policy_failure(name: str, where: str, exc: BaseException) -> PolicyError:
    """The :class:`PolicyError` of policy `name` failing `where` with `exc`.

    `where` is e.g. ``"at step 3 of the episode of seed 5"``; `exc` an exception, or the
    ``SystemExit`` of a ``sys.exit`` call.
    """
    what = f"called sys.exit({exc.code!r})" if isinstance(exc, SystemExit) else f"raised {type(exc).__name__}: {exc}"
    found = f"{type(exc).__name__}: {exc}"
    return PolicyError(
        f"policy {name!r} {what} {where}",
        file=f"policy {name!r} {where}",
        field="policy",
        expected="an action",
        found=found,
    )


@runtime_checkable
class PredictPolicy(Protocol):
    """A policy with the stable-baselines3 ``predict`` method."""

    def predict(self, observation: Any, deterministic: bool = True) -> Any:
        """``action`` or ``(action, state)`` for one observation."""
        ...


#: What :func:`proxemic.evaluate` and :class:`PolicyActor` accept as a policy.
Policy = Callable[[Any], Any] | PredictPolicy


@dataclass(frozen=True)
class PolicyRef:
    """A user policy in an evaluation: its label and where it comes from.

    ``target`` is an import path ``"module:factory"`` (built in each worker, so any backend works)
    or ``""`` for a policy object given to :func:`proxemic.evaluate` (run in this process and in
    forked worker processes only). ``search_path``
    is put on ``sys.path`` before importing (the directory the CLI ran from, so that
    ``examples.my_policy:make`` imports from the repository root in every worker).
    """

    name: str
    target: str = ""
    search_path: str | None = None

    def __repr__(self) -> str:
        """The label, as tasks print it in error messages."""
        return f"policy {self.name!r} ({self.target or 'a policy object'})"


def load_factory(path: str, search_path: str | None = None) -> Callable[..., Any]:
    """The factory named by ``"module:attr"`` or ``"file.py:attr"``.

    Args:
        path: The import path; ``attr`` may be dotted (``module:Class.make``).
        search_path: A directory put first on ``sys.path`` before importing (default: the current
            directory, as ``python -m`` does).

    Raises:
        InputError: A malformed path, a module that does not import or an attribute that is missing
            or not callable (one line naming what was expected).
    """
    module_name, sep, attr = path.partition(":")
    if not sep or not module_name or not attr:
        raise input_error("policy", _EXPECTED_FACTORY, path, note="e.g. examples.my_policy:make")
    where = search_path or os.getcwd()
    if where not in sys.path:
        sys.path.insert(0, where)
    try:
        if module_name.endswith(".py"):
            file = Path(module_name)
            if not file.is_absolute():
                file = Path(where) / file
            spec = importlib.util.spec_from_file_location(file.stem, file)
            if spec is None or spec.loader is None or not file.is_file():
                raise ModuleNotFoundError(f"no file {file}")
            module = importlib.util.module_from_spec(spec)
            spec.loader.exec_module(module)
        else:
            module = importlib.import_module(module_name)
    except ImportError as e:
        raise input_error("policy", _EXPECTED_FACTORY, path, note=f"cannot import {module_name!r}: {e}") from e
    except (Exception, SystemExit) as e:
        raise policy_failure(path, f"while its module {module_name!r} was imported", e) from e
    obj: Any = module
    for part in attr.split("."):
        if not hasattr(obj, part):
            raise input_error(
                "policy", _EXPECTED_FACTORY, path, note=f"module {module_name!r} has no attribute {attr!r}"
            )
        obj = getattr(obj, part)
    if not callable(obj):
        raise input_error(
            "policy",
            "a callable factory make(observation_space, action_space) -> policy",
            f"{attr!r}, a {type(obj).__name__}",
            note=f"--policy {path!r}: not callable",
        )
    return obj


def build_policy(path: str, observation_space: Any, action_space: Any, search_path: str | None = None) -> Any:
    """Imports the factory at `path` and calls it with the env's spaces; checks what it returns.

    Raises:
        InputError: The factory cannot be loaded, fails, or returns something that is not a policy.
    """
    factory = load_factory(path, search_path)
    try:
        inspect.signature(factory).bind(observation_space, action_space)
    except TypeError as e:
        raise input_error(
            "policy",
            "a factory make(observation_space, action_space) -> policy",
            f"a factory {inspect.signature(factory)}",
            note=f"--policy {path!r}: the factory must take (observation_space, action_space): {e}",
        ) from e
    except ValueError:
        pass  # a builtin without a signature: let the call decide
    try:
        policy = factory(observation_space, action_space)
    except (Exception, SystemExit) as e:
        raise policy_failure(path, "in its factory make(observation_space, action_space)", e) from e
    check_policy(policy, f"--policy {path!r}: the factory returned")
    return policy


def check_policy(policy: Any, what: str = "policy") -> None:
    """Raises :class:`InputError` unless `policy` is a callable or has ``predict``."""
    if not (callable(policy) or callable(getattr(policy, "predict", None))):
        raise input_error("policy", _EXPECTED_POLICY, f"{what} a {type(policy).__name__}")


class PolicyActor:
    """A policy seen through one interface: ``actor(obs)`` returns a checked float32 action.

    Calls ``predict(obs, deterministic=True)`` if the policy has it (keeping only the action of an
    ``(action, state)`` pair), else ``policy(obs)``; :meth:`reset` forwards to the policy's
    ``reset(seed)`` when it has one. The action is checked by ``env.step``'s own check
    (:func:`proxemic.errors.check_action`: 3 finite real numbers; booleans, complex numbers and
    text refused), after dropping a leading batch axis of 1. A policy that raises or calls
    ``sys.exit`` becomes a :class:`PolicyError` naming the policy, the episode and the step.
    """

    def __init__(self, policy: Any, name: str = "policy", *, scene: str | None = None) -> None:
        """Wraps `policy` (checked: callable or with ``predict``), labelled `name` in errors.

        `scene`, if given, names the episodes' scene in errors (with the seed of :meth:`reset`).
        """
        check_policy(policy, f"policy {name!r} is")
        self.policy, self.name, self.scene = policy, name, scene
        predict = getattr(policy, "predict", None)
        self._predict = predict if callable(predict) else None
        reset = getattr(policy, "reset", None)
        self._reset = reset if callable(reset) else None
        self.seed: int | None = None
        self.steps = 0

    def _where(self) -> str:
        on = f" on {self.scene}" if self.scene else ""
        return f"at step {self.steps} of the episode of seed {self.seed}{on}"

    def reset(self, seed: int | None) -> None:
        """Tells the policy a new episode starts from `seed`.

        Raises:
            PolicyError: The policy's ``reset`` raised or called ``sys.exit``.
        """
        self.seed, self.steps = seed, 0
        if self._reset is not None:
            try:
                self._reset(seed)
            except (Exception, SystemExit) as e:
                raise policy_failure(self.name, f"in reset({seed!r})", e) from e

    def __call__(self, obs: Any) -> np.ndarray:
        """The policy's action for `obs`, as a float32 array of shape (3,).

        Raises:
            InputError: The action is not 3 finite real numbers (one line naming the policy, the
                episode's seed and the step).
            PolicyError: The policy raised or called ``sys.exit`` (naming the episode's seed and the step).
        """
        try:
            if self._predict is not None:
                out = self._predict(obs, deterministic=True)
                if isinstance(out, tuple) and len(out) == 2:
                    out = out[0]
            else:
                out = self.policy(obs)
        except (Exception, SystemExit) as e:
            raise policy_failure(self.name, self._where(), e) from e
        action = self.check_action(out)
        self.steps += 1
        return action

    def check_action(self, action: Any) -> np.ndarray:
        """`action` as a float32 array of shape (3,), or an :class:`InputError` naming ``policy``.

        The check of ``env.step`` (:func:`proxemic.errors.check_action`), after a leading batch
        axis of 1 (as ``predict`` may return) is dropped.
        """
        try:
            raw = np.asarray(action)
        except (TypeError, ValueError):
            raw = None
        if raw is not None and raw.shape == (1, 3):
            action = raw[0]
        note = f"returned by policy {self.name!r} {self._where()}"
        return check_action(action, "policy", note=note).astype(np.float32)


def joint_policy(
    policies: Policy | Mapping[str, Policy], agents: list[str]
) -> Callable[[Mapping[str, Any]], dict[str, np.ndarray]]:
    """For several robots: ``act(observations) -> actions`` over PettingZoo-style agent dicts.

    Args:
        policies: One shared policy (called for every agent with its own observation) or a mapping
            ``agent -> policy`` naming every agent.
        agents: The env's possible agents.

    Returns:
        A function mapping ``{agent: obs}`` (the agents still running) to ``{agent: action}``; it has
        ``reset(seed)`` forwarding to every policy.

    Raises:
        InputError: A mapping that misses an agent or names an unknown one.
    """
    if isinstance(policies, Mapping):
        missing, unknown = sorted(set(agents) - set(policies)), sorted(set(policies) - set(agents))
        if missing or unknown:
            raise input_error(
                "policies",
                f"a policy for each of {agents}",
                str(sorted(policies)),
                note=f"missing {missing}, unknown {unknown}",
            )
        by_agent: Mapping[str, Policy] = policies
    else:
        by_agent = dict.fromkeys(agents, policies)
    # One actor per agent (its errors name the agent and count that agent's steps).
    actors = {a: PolicyActor(by_agent[a], a) for a in agents}

    class _Joint:
        def __call__(self, observations: Mapping[str, Any]) -> dict[str, np.ndarray]:
            return {agent: actors[agent](obs) for agent, obs in observations.items()}

        def reset(self, seed: int | None) -> None:
            told: set[int] = set()
            for actor in actors.values():
                if id(actor.policy) in told:  # a policy shared by several agents is reset once
                    actor.seed, actor.steps = seed, 0
                else:
                    told.add(id(actor.policy))
                    actor.reset(seed)

    return _Joint()


def observation_scales(observation_space: Any) -> dict[str, np.ndarray]:
    """Per-key divisors bringing each observation array to about [-1, 1].

    Each is its space's largest finite bound, elementwise (1 where infinite or zero).
    """
    scales = {}
    for key, space in observation_space.spaces.items():
        bound = np.maximum(np.abs(space.low), np.abs(space.high)).astype(np.float32)
        scales[key] = np.where(np.isfinite(bound) & (bound > 0), bound, 1.0).astype(np.float32)
    return scales


class FlatObservation:
    """The observation dict as one float32 vector, each key scaled by its space's bound.

    Learning libraries that want one ``Box`` (or train better on inputs near [-1, 1]) use it as
    ``flat(obs)``, and :func:`flat_observation_env` applies it to an env. Keys are concatenated
    in sorted order, each array flattened row-major.
    """

    def __init__(self, observation_space: Any) -> None:
        """Reads the keys, shapes and scales of a proxemic ``Dict`` observation space."""
        import gymnasium as gym

        self.keys = sorted(observation_space.spaces)
        self.scales = observation_scales(observation_space)
        size = sum(int(np.prod(observation_space[k].shape)) for k in self.keys)
        low = np.concatenate([(observation_space[k].low / self.scales[k]).ravel() for k in self.keys])
        high = np.concatenate([(observation_space[k].high / self.scales[k]).ravel() for k in self.keys])
        self.space = gym.spaces.Box(low.astype(np.float32), high.astype(np.float32), (size,), np.float32)

    def __call__(self, obs: Mapping[str, Any]) -> np.ndarray:
        """One observation dict as the flat scaled vector."""
        return np.concatenate([(np.asarray(obs[k], np.float32) / self.scales[k]).ravel() for k in self.keys])


def flat_observation_env(env: Any) -> Any:
    """`env` with :class:`FlatObservation` applied (a gymnasium ``TransformObservation``)."""
    import gymnasium as gym

    flat = FlatObservation(env.observation_space)
    return gym.wrappers.TransformObservation(env, flat, flat.space)
