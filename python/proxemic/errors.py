"""The exception hierarchy of proxemic.

Every error raised by proxemic derives from :class:`ProxemicError`. Errors about user input also
derive from :class:`ValueError`, so generic handlers keep working. Each carries the attributes
``file`` (the scenario file, or None), ``field`` (the dotted field or argument name),
``expected`` and ``found``; the message says all four.

The compiled core raises these classes by name, so they must stay importable from here. The
checks every front end shares live here too: :func:`input_error` (the message format),
:func:`typed_repr` (what arrived, with its type) and :func:`check_action` (a robot's action).
"""

from __future__ import annotations

import importlib
from types import ModuleType
from typing import Any

import numpy as np
from gymnasium.error import ResetNeeded


class ProxemicError(Exception):
    """Base class of every proxemic error."""

    def __init__(
        self,
        message: str,
        *,
        file: str | None = None,
        field: str | None = None,
        expected: str | None = None,
        found: str | None = None,
    ) -> None:
        """Creates the error.

        Args:
            message: The full, human-readable message.
            file: The scenario file involved, if any.
            field: The field path or argument name involved, if any.
            expected: What a valid value looks like.
            found: What arrived.

        """
        super().__init__(message)
        self.file = file
        self.field = field
        self.expected = expected
        self.found = found


class ScenarioError(ProxemicError, ValueError):
    """A scenario file is unreadable, malformed, or fails validation."""


class InputError(ProxemicError, ValueError):
    """A runtime input (an action, an argument, a state array) is malformed."""


class PlanningError(ProxemicError):
    """No path exists (for example, a goal unreachable from the start)."""


class EpisodeError(ProxemicError):
    """An episode of an evaluation or tuning run failed; the finished episodes' records are kept."""


class PolicyError(ProxemicError):
    """A user policy failed: it raised (at import, in its factory, at ``reset`` or at a step) or called ``sys.exit``.

    ``field`` is ``"policy"``, ``file`` the policy's label and where it
    failed (the episode's seed and the step), ``found`` the exception it raised; the original
    exception is the ``__cause__``.
    """


class InvariantError(ProxemicError):
    """An episode's record broke one of its invariants: a bug in proxemic, not in the input.

    ``file`` names the episode (scene, seed, robot), ``field`` the invariant (one of the core's
    ``metrics::invariants::INVARIANTS``) and ``found`` what the record says that breaks it.
    """


def invariant_in(episode: str, e: InvariantError) -> InvariantError:
    """The core's broken-record error `e` with `episode` (the env, its reset seed) before the core's name of it.

    The envs raise it from the core's: the core names its world's own seed, the env the seed its
    user gave ``reset``.
    """
    named = f"{episode} (core: {e.file})"
    return InvariantError(
        f"{named}: invariant {e.field} broken: {e.found} (a bug in proxemic: please report it)",
        file=named,
        field=e.field,
        expected=e.expected,
        found=e.found,
    )


class NeedsResetError(ProxemicError, ResetNeeded):
    """An env was stepped before ``reset()``, or after its episode ended (terminated or truncated).

    A :class:`gymnasium.error.ResetNeeded`, the error gymnasium's own order check raises for a
    step before the first reset.
    """


class UnknownNameError(ProxemicError, KeyError):
    """An unknown scenario or environment name.

    A planner or gain name is part of a scenario: an unknown one is a :class:`ScenarioError`,
    whether it is in a file or given as an argument.
    """

    def __str__(self) -> str:
        """Returns the message (KeyError would otherwise quote it)."""
        return str(self.args[0]) if self.args else ""


class MissingExtraError(ProxemicError, ImportError):
    """An optional package is not installed; the message names the extra that installs it.

    An :class:`ImportError`, so ``except ImportError`` handlers keep working. ``field`` is the
    feature that needs the package, ``expected`` the ``pip install`` command, ``found`` the module
    that failed to import.
    """


#: The optional extras and the packages each installs (``pyproject.toml``'s optional-dependencies).
EXTRAS: dict[str, str] = {
    "ray": "the Ray backend of eval and tune",
    "video": "video export (imageio and imageio-ffmpeg)",
    "rl": "the reinforcement-learning example (stable-baselines3 and torch)",
    "multi": "SuperSuit's multi-agent wrappers (examples/parallel_vec_env.py)",
}


def require_extra(module: str, extra: str, feature: str) -> ModuleType:
    """Imports `module`, or raises :class:`MissingExtraError` naming the extra to install.

    Args:
        module: The module to import (e.g. ``"ray"``, ``"imageio.v2"``).
        extra: The extra of ``proxemic`` that installs it (a key of :data:`EXTRAS`).
        feature: What needs it, for the message (e.g. ``"backend 'ray'"``).

    Returns:
        The imported module.
    """
    try:
        return importlib.import_module(module)
    except ImportError as e:
        missing = e.name or module
        command = f"pip install 'proxemic[{extra}]'"
        message = f"{feature} needs the package {missing!r}, which is not installed: {command}"
        raise MissingExtraError(message, field=feature, expected=command, found=missing) from e


def input_error(field: str, expected: str, found: object, *, note: str | None = None) -> InputError:
    """The :class:`InputError` of a bad argument, its message in the core's format.

    Args:
        field: The argument (or dotted field) name.
        expected: What a valid value looks like.
        found: What arrived (strings as they are, anything else as its ``repr``).
        note: An optional hint appended to the message in parentheses (e.g. how to fix it).

    Returns:
        The error, to be raised by the caller: ``"{field}: expected {expected}, got {found} ({note})"``.
    """
    text = found if isinstance(found, str) else repr(found)
    message = f"{field}: expected {expected}, got {text}" + (f" ({note})" if note else "")
    return InputError(message, field=field, expected=expected, found=text)


def typed_repr(value: object, limit: int = 80) -> str:
    """What arrived, for a message: its type and its ``repr``, cut to `limit` characters.

    ``"str 'robot_0'"``, ``"NoneType None"``: a string is never mistaken for a number or a list.
    """
    text = repr(value)
    return f"{type(value).__name__} {text if len(text) <= limit else text[: limit - 3] + '...'}"


#: What an action must be, as error messages say.
ACTION_EXPECTED = "3 finite real numbers in [-1, 1], shape (3,)"

#: The numpy dtype kinds of real numbers: signed and unsigned integers and floats. Booleans,
#: complex numbers, text and objects are refused, never converted.
REAL_KINDS = "iuf"


def check_action(action: Any, field: str, *, note: str | None = None) -> np.ndarray:
    """`action` as 3 float64 values, or an :class:`InputError` naming `field`.

    The one check of a robot's action, for ``env.step``, the parallel env's ``step`` and the
    actions a user policy returns (:class:`proxemic.policy.PolicyActor`). Accepted: anything
    numpy reads as a real (integer or floating, :data:`REAL_KINDS`) array of shape (3,) with
    finite values (values outside [-1, 1] are clipped by the core, as documented).

    Args:
        action: What arrived.
        field: The argument named in the message (``"action"``, ``"actions['robot_1']"``, ``"policy"``).
        note: An optional hint appended to the message (e.g. which policy returned it, when).
    """
    try:
        raw = np.asarray(action)
    except (ValueError, TypeError):
        raw = np.asarray(None)
    if raw.shape != (3,) or raw.dtype.kind not in REAL_KINDS:
        numbers = raw.dtype.kind in REAL_KINDS + "bc"
        what = f"shape {raw.shape} of {raw.dtype}" if numbers else typed_repr(action)
        raise input_error(field, ACTION_EXPECTED, what, note=note)
    a = raw.astype(np.float64)
    if not np.isfinite(a).all():
        raise input_error(field, ACTION_EXPECTED, str(a.tolist()), note=note)
    return a


__all__ = [
    "ACTION_EXPECTED",
    "EXTRAS",
    "REAL_KINDS",
    "EpisodeError",
    "InputError",
    "InvariantError",
    "MissingExtraError",
    "NeedsResetError",
    "PlanningError",
    "PolicyError",
    "ProxemicError",
    "ScenarioError",
    "UnknownNameError",
    "check_action",
    "input_error",
    "invariant_in",
    "require_extra",
    "typed_repr",
]
