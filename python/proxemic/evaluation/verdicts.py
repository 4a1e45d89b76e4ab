"""Verdicts: two planners compared in plain words on the seeds both ran."""

from __future__ import annotations

import math
from collections.abc import Callable, Mapping, Sequence
from typing import Any

import numpy as np

from proxemic.evaluation.metrics import METRICS, VERDICT_METRICS
from proxemic.evaluation.stats import paired_ratio
from proxemic.evaluation.summary import collided


def _change(r: float, lo: float, hi: float) -> str:
    """A ratio of means and its interval in words: ``55% less X [33-73% less]``."""

    def pct(x: float) -> str:
        return f"{abs(x - 1):.0%}"

    said = f"{pct(r)} {'less' if r < 1 else 'more'}"
    if hi < 1 or lo > 1:
        a, b = sorted((pct(lo), pct(hi)), key=lambda t: float(t[:-1]))
        word = "less" if hi < 1 else "more"
        return f"{said} [{a} {word}]" if a == b else f"{said} [{a[:-1]}-{b} {word}]"
    return f"{said} [{pct(lo)} less to {pct(hi)} more]"


def verdict(records: Sequence[Mapping[str, Any]], a: str, b: str) -> str:
    """One plain-language paragraph comparing planner `a` with `b` on the seeds both ran.

    Success and collision counts over all shared seeds; then, over the seeds where both reached the
    goal, ratios of means of time to goal, path length and the social time shares with 95%
    bootstrap intervals (pairs of episodes resampled).
    """
    # Episodes pair by (seed, robot): on a multi-robot scene every robot is paired with itself.
    by = {p: {(r["seed"], r.get("robot", 0)): r for r in records if r["planner"] == p} for p in (a, b)}
    seeds = sorted(set(by[a]) & set(by[b]))
    if not seeds:
        return f"{a} vs {b}: no seed in common."
    unit = "seeds" if all(robot == 0 for _, robot in seeds) else "robot-episodes (seed, robot)"

    def count(p: str, pred: Callable[[Mapping[str, Any]], bool]) -> int:
        return sum(pred(by[p][s]) for s in seeds)

    ok = [s for s in seeds if by[a][s].get("success") and by[b][s].get("success")]
    parts = [
        f"{a} vs {b} on {len(seeds)} {unit}: success {count(a, lambda r: bool(r.get('success')))} vs "
        f"{count(b, lambda r: bool(r.get('success')))}, collisions {count(a, collided)} vs {count(b, collided)}"
    ]
    if len(ok) < 2:
        what = "seed(s)" if unit == "seeds" else "robot-episode(s)"
        parts.append(f"only {len(ok)} {what} where both reached the goal, too few to compare further.")
        return "; ".join(parts)
    said = []
    for m, how in VERDICT_METRICS:
        raw = [(by[a][s].get(m), by[b][s].get(m)) for s in ok]
        pairs = [(float(x), float(y)) for x, y in raw if x is not None and y is not None]
        if len(pairs) < 2:
            continue
        xs, ys = [p[0] for p in pairs], [p[1] for p in pairs]
        label = METRICS[m].label
        r, lo, hi = paired_ratio(xs, ys)
        if math.isnan(r):
            if np.mean(xs) == 0:
                said.append(f"no {label} for either")
            else:
                said.append(f"{label} {np.mean(xs):{METRICS[m].fmt}} {METRICS[m].unit} vs none")
        elif how == "times":
            said.append(f"{r:.2f}x {label} [{lo:.2f}x, {hi:.2f}x]")
        else:
            words = _change(r, lo, hi)
            said.append(words.replace(" [", f" {label} [", 1))
    parts.append(f"over the {len(ok)} {unit} both reached the goal: " + ", ".join(said) + ".")
    return "; ".join(parts)


def verdicts(records: Sequence[Mapping[str, Any]], labels: Sequence[str], policies: int = 0) -> list[str]:
    """A :func:`verdict` for every pair of `labels`.

    The first `policies` labels (user policies) come first against every later label, then each
    later planner against each earlier one (``social vs astar``).
    """
    out = []
    for i in range(len(labels)):
        for j in range(i + 1, len(labels)):
            a, b = (labels[i], labels[j]) if i < policies else (labels[j], labels[i])
            out.append(verdict(records, a, b))
    return out
