"""A policy module that fails when imported, for the errors of ``proxemic eval --policy``."""

from __future__ import annotations

from typing import Any

raise RuntimeError("this policy module fails at import")


def make(observation_space: Any, action_space: Any) -> Any:  # pragma: no cover - never reached
    """Never reached."""
    return None
