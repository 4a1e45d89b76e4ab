"""2D visualisation for proxemic: a fast numpy top-down renderer and matplotlib figures.

Everything here works on the plain scenario dict (the JSON the Rust core produces) and numpy
arrays; nothing imports ``proxemic._core``. :class:`TopDownRenderer` needs only numpy; the plotting
functions (:func:`plot_episodes`, :func:`plot_metrics_bars`, :func:`format_table`) live in
:mod:`proxemic.viz.plots` and are imported lazily so that rendering frames never pulls in
matplotlib.
"""

from __future__ import annotations

import importlib
from typing import TYPE_CHECKING, Any

from .topdown import TopDownRenderer

if TYPE_CHECKING:
    from .plots import format_table, plot_episodes, plot_metrics_bars

__all__ = ["TopDownRenderer", "format_table", "plot_episodes", "plot_metrics_bars"]

_LAZY = frozenset({"format_table", "plot_episodes", "plot_metrics_bars"})


def __getattr__(name: str) -> Any:
    """Import the matplotlib-based helpers from :mod:`proxemic.viz.plots` on first access.

    Args:
        name: The attribute requested from the package.

    Returns:
        The requested function.

    Raises:
        AttributeError: If ``name`` is not a public attribute of the package.

    """
    if name in _LAZY:
        return getattr(importlib.import_module(".plots", __name__), name)
    raise AttributeError(f"module {__name__!r} has no attribute {name!r}")
