"""Intervals of summarised metrics: Student t means, Wilson rates, paired bootstrap ratios."""

from __future__ import annotations

import math
from collections.abc import Iterable, Sequence

import numpy as np

# Two-sided 95% Student t quantiles for 1..30 degrees of freedom (Fisher & Yates tables).
_T95 = (
    12.706, 4.303, 3.182, 2.776, 2.571, 2.447, 2.365, 2.306, 2.262, 2.228,
    2.201, 2.179, 2.160, 2.145, 2.131, 2.120, 2.110, 2.101, 2.093, 2.086,
    2.080, 2.074, 2.069, 2.064, 2.060, 2.056, 2.052, 2.048, 2.045, 2.042,
)  # fmt: skip


def t95(n: int) -> float:
    """Two-sided 95% Student t quantile for n samples (normal beyond 31)."""
    if n < 2:
        return math.nan
    return _T95[n - 2] if n - 1 <= len(_T95) else 1.96


def mean_ci(values: Iterable[float | None]) -> tuple[float, float, int]:
    """Mean, 95% half-width (Student t) and count of the finite values."""
    x = np.array([v for v in values if v is not None and math.isfinite(v)], dtype=np.float64)
    n = int(x.size)
    if n == 0:
        return math.nan, math.nan, 0
    if n == 1:
        return float(x[0]), math.nan, 1
    return float(x.mean()), t95(n) * float(x.std(ddof=1)) / math.sqrt(n), n


def wilson(successes: int, n: int, z: float = 1.959964) -> tuple[float, float, float]:
    """Rate and 95% Wilson score interval (low, high)."""
    if n == 0:
        return math.nan, math.nan, math.nan
    p = successes / n
    denom = 1 + z * z / n
    centre = (p + z * z / (2 * n)) / denom
    half = z * math.sqrt(p * (1 - p) / n + z * z / (4 * n * n)) / denom
    return p, centre - half, centre + half


BOOTSTRAP_SAMPLES = 2000


def paired_ratio(a: Sequence[float], b: Sequence[float], seed: int = 0) -> tuple[float, float, float]:
    """mean(a) / mean(b) over paired samples and its 95% percentile bootstrap interval (pairs resampled).

    Returns NaNs when b's mean is 0 (or a resample's is: those resamples are left out).
    """
    x, y = np.asarray(a, dtype=np.float64), np.asarray(b, dtype=np.float64)
    if x.size == 0 or y.mean() == 0:
        return math.nan, math.nan, math.nan
    idx = np.random.default_rng(seed).integers(0, x.size, size=(BOOTSTRAP_SAMPLES, x.size))
    num, den = x[idx].mean(axis=1), y[idx].mean(axis=1)
    ok = den > 0
    ratios = num[ok] / den[ok]
    lo, hi = np.percentile(ratios, [2.5, 97.5]) if ratios.size else (math.nan, math.nan)
    return float(x.mean() / y.mean()), float(lo), float(hi)
