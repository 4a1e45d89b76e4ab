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
    """An unknown scenario, environment or planner name."""

    def __str__(self) -> str:
        """Returns the message (KeyError would otherwise quote it)."""
        return str(self.args[0]) if self.args else ""


__all__ = [
    "EpisodeError",
    "InputError",
    "NeedsResetError",
    "PlanningError",
    "ProxemicError",
    "ScenarioError",
    "UnknownNameError",
]
