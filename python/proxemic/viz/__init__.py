"""2D visualisation for proxemic: a fast numpy top-down renderer and matplotlib figures.

Everything here works on the plain scenario dict (the JSON the Rust core produces) and numpy
arrays; nothing imports ``proxemic._core``. :class:`TopDownRenderer` needs only numpy; the plotting
functions (:func:`plot_episodes`, :func:`plot_metrics_grid`, :func:`format_table`) live in
:mod:`proxemic.viz.plots` and are imported lazily so that rendering frames never pulls in
matplotlib. Video export (:func:`record_episode`, :func:`write_video`, :func:`render_frame` of an
env from any view) lives in :mod:`proxemic.viz.video`, also imported lazily.
"""

from __future__ import annotations

import importlib
import importlib.util
from typing import TYPE_CHECKING, Any

from .topdown import TopDownRenderer

if TYPE_CHECKING:
    from .plots import format_table, plot_episodes, plot_metrics_grid
    from .video import record_episode, render_frame, write_video

__all__ = [
    "TopDownRenderer",
    "format_table",
    "plot_episodes",
    "plot_metrics_grid",
    "record_episode",
    "render_frame",
    "write_video",
]

_LAZY = {
    "format_table": ".plots",
    "plot_episodes": ".plots",
    "plot_metrics_grid": ".plots",
    "record_episode": ".video",
    "render_frame": ".video",
    "write_video": ".video",
}


def __getattr__(name: str) -> Any:
    """Import the plotting and video helpers, and the submodules, on first access.

    Args:
        name: The attribute requested from the package.

    Returns:
        The requested function or submodule.

    Raises:
        AttributeError: If ``name`` is not a public attribute of the package.

    """
    if name in _LAZY:
        return getattr(importlib.import_module(_LAZY[name], __name__), name)
    if not name.startswith("_") and importlib.util.find_spec(f"{__name__}.{name}") is not None:
        return importlib.import_module(f"{__name__}.{name}")  # a submodule: proxemic.viz.video
    raise AttributeError(f"module {__name__!r} has no attribute {name!r}")
