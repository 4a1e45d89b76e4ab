"""How the evaluation summarises and shows each metric, read from the core's metric registry.

The registry (``proxemic._core.metric_registry()``, :mod:`proxemic.reference`) says of every metric
whether it is summarised (``summary``: a rate or a mean, and the ``decimals`` of a mean), on which
panel of ``metrics.png`` it is drawn (``panel``), whether it is a headline column (``headline``) and
how verdicts compare it (``verdict``). This module only adds the two summarised values that are not
metrics of one episode in the core: the env's return and SNQI (:data:`EXTRAS`).
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any

from proxemic import reference, snqi


@dataclass(frozen=True)
class SummaryColumn:
    """How a summarised metric is labelled and bounded (intervals are clipped to the bounds)."""

    label: str
    unit: str = ""
    low: float = -math.inf
    high: float = math.inf
    fmt: str = ".2f"


#: Summarised values that are not metrics of the core's registry, as registry-like entries: the
#: env's return (``reward``) and robot-sf's SNQI, computed over an evaluation's records
#: (:mod:`proxemic.snqi`).
EXTRAS: tuple[dict[str, Any], ...] = (
    {
        "key": "reward",
        "label": "return",
        "unit": "",
        "low": None,
        "high": None,
        "summary": "mean",
        "over_successes": False,
        "decimals": 1,
        "panel": "efficiency",
        "headline": False,
        "verdict": None,
    },
    {
        "key": "snqi",
        "label": "SNQI",
        "unit": "",
        "low": None,
        "high": snqi.WEIGHTS["w_success"],
        "summary": "mean",
        "over_successes": False,
        "decimals": 3,
        "panel": None,
        "headline": True,
        "verdict": None,
    },
)

#: The panels of ``metrics.png`` (the registry's ``panel`` values), in rows, with their titles.
PANEL_TITLES: dict[str, str] = {
    "outcome": "outcome",
    "efficiency": "efficiency",
    "social": "social",
    "papers": "papers' metrics (Daza 2021: L_ratio, Smooth; Calderita et al.: CHC, object-space time Psi)",
}


def _summarised() -> list[dict[str, Any]]:
    """The registry's summarised metrics in its order, then :data:`EXTRAS`."""
    return [*(dict(m) for m in reference.metric_registry() if m["summary"] is not None), *EXTRAS]


def _column(m: dict[str, Any]) -> SummaryColumn:
    """Label, unit, bounds and format of a summarised entry; rates are shares of episodes (0-1, as %)."""
    if m["summary"] == "rate":
        return SummaryColumn(m["label"], "% of episodes", 0.0, 1.0, ".0%")
    low = -math.inf if m["low"] is None else m["low"]
    high = math.inf if m["high"] is None else m["high"]
    return SummaryColumn(m["label"], m["unit"], low, high, f".{m['decimals']}f")


_ENTRIES = _summarised()

#: Metrics summarised as rates (0/1 per episode), with Wilson intervals (``collision``: any
#: collision that ends the episode, or a person hit by the robot's fault).
RATE_METRICS: tuple[str, ...] = tuple(m["key"] for m in _ENTRIES if m["summary"] == "rate")
#: Metrics summarised as means with Student t intervals (None values are left out).
MEAN_METRICS: tuple[str, ...] = tuple(m["key"] for m in _ENTRIES if m["summary"] == "mean")
#: Means taken over the successful episodes only (the registry's ``over_successes``).
OVER_SUCCESSES: tuple[str, ...] = tuple(m["key"] for m in _ENTRIES if m["summary"] == "mean" and m["over_successes"])
#: Label, unit, bounds and format of every summarised metric.
METRICS: dict[str, SummaryColumn] = {m["key"]: _column(m) for m in _ENTRIES}
#: The panels of ``metrics.png``, in rows: (title, metrics).
METRIC_GROUPS: tuple[tuple[str, tuple[str, ...]], ...] = tuple(
    (title, tuple(m["key"] for m in _ENTRIES if m["panel"] == panel)) for panel, title in PANEL_TITLES.items()
)
#: The columns of the headline table (terminal and top of ``summary.md``).
HEADLINE: tuple[str, ...] = tuple(m["key"] for m in _ENTRIES if m["headline"])
#: The metrics of a verdict: (metric, how a ratio is said: "times" as 1.2x, "share" as 55% less).
VERDICT_METRICS: tuple[tuple[str, str], ...] = tuple((m["key"], m["verdict"]) for m in _ENTRIES if m["verdict"])
