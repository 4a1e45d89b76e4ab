"""The exception hierarchy of proxemic.

Every error raised by proxemic derives from :class:`ProxemicError`. Errors about user input also
derive from :class:`ValueError`, so generic handlers keep working. Each carries the attributes
``file`` (the scenario file, or None), ``field`` (the dotted field or argument name),
``expected`` and ``found``; the message says all four.

The compiled core raises these classes by name, so they must stay importable from here.
"""

from __future__ import annotations

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


__all__ = [
    "EpisodeError",
    "InputError",
    "NeedsResetError",
    "PlanningError",
    "ProxemicError",
    "ScenarioError",
    "UnknownNameError",
    "input_error",
]
