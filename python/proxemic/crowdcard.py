"""How real are the people: the pedestrian model against recorded crowds (the crowd card).

The model is the core's social force crowd (``proxemic._core.Recording``, ``rimea1/4/6``); this
module computes the card's figures from what the core returns, draws the plots and writes
``card.md``, ``card.json`` and the PNGs (``proxemic crowd-card``, ``docs/people-validation.md``).
It also holds the calibration of the interaction parameters (:func:`calibrate`, on the UCY
recordings only).

Protocols (``docs/people-validation.md`` lists every choice):

- closed loop: every recorded person with at least :data:`MIN_TRACK_S` seconds of track is
  re-enacted by the model (one at a time, everyone else replayed), and compared with the
  recording and with a straight line at the same mean speed that ignores everyone;
- open loop: observe 8 samples at 0.4 s, predict 12, against constant velocity;
- distributions of walking speed and nearest-neighbour distance of the re-enacted people;
- RiMEA tests 1, 4 and 6.
"""

from __future__ import annotations

import json
import sys
import time
from collections.abc import Callable, Sequence
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np

from proxemic import _core
from proxemic.markdown import check_block, write_block

SAMPLE_DT = 0.4
"""Time between samples of the ETH/UCY recordings (s)."""

MIN_TRACK_S = 8.0
"""A recorded person is re-enacted if its track lasts at least this long (s)."""

RADIUS = 0.2
"""Body radius (m) of every person of the card (the scenario default): a close encounter is a
centre distance below twice this."""

OVERTIME_S = 20.0
"""A re-enacted person who has not arrived this long after its recorded arrival counts as
arriving then (its time error is then this, a censored value; ``not_arrived`` counts them)."""

OBSERVE, PREDICT = 8, 12
"""The open-loop protocol: samples observed and predicted."""

RIMEA4_DENSITIES = (0.5, 1.0, 1.5, 2.0, 3.0, 4.0, 5.0)
"""Densities (people per m^2) of RiMEA test 4."""

Params = dict[str, float]


@dataclass
class Scene:
    """A recording: its name, the tracks (``(n, 3)`` arrays of t, x, y) and the core's view."""

    name: str
    tracks: list[np.ndarray]
    core: Any
    window: tuple[float, float] | None
    stride: int = 1

    @property
    def subjects(self) -> list[int]:
        """The tracks re-enacted: at least :data:`MIN_TRACK_S` long (every ``stride``-th of them)."""
        long = [k for k, t in enumerate(self.tracks) if t[-1, 0] - t[0, 0] >= MIN_TRACK_S - 1e-9]
        return long[:: self.stride]


def load(path: str | Path, window: tuple[float, float] | None = None) -> Scene:
    """Reads a replay CSV ``t,id,x,y``.

    With ``window`` (t0, t1 in the recording's clock) only the tracks lying wholly inside it are
    kept. Raises ``ScenarioError`` naming the file, line and
    column of bad input, ``InputError`` for an empty window.
    """
    path = Path(path)
    tracks = [np.asarray(a, dtype=np.float64) for _, a in _core.read_tracks(path)]
    if window is not None:
        tracks = [t for t in tracks if t[0, 0] >= window[0] and t[-1, 0] <= window[1]]
        if not tracks:
            from proxemic.errors import InputError

            raise InputError(
                f"{path}: window: expected a time window holding at least one whole track, got {window}",
                field="window",
                expected="a time window holding at least one whole track",
                found=f"{window}",
            )
    name = path.stem
    return Scene(name, tracks, _core.Recording(tracks, RADIUS), window)


class _Frames:
    """Who is where at each sample (frame = round(t / 0.4))."""

    def __init__(self, tracks: Sequence[np.ndarray]) -> None:
        self.start = [round(t[0, 0] / SAMPLE_DT) for t in tracks]
        lo = min(self.start)
        hi = max(s + len(t) - 1 for s, t in zip(self.start, tracks, strict=True))
        self.lo = lo
        who: list[list[int]] = [[] for _ in range(hi - lo + 1)]
        where: list[list[np.ndarray]] = [[] for _ in range(hi - lo + 1)]
        for k, (s, t) in enumerate(zip(self.start, tracks, strict=True)):
            for i in range(len(t)):
                who[s + i - lo].append(k)
                where[s + i - lo].append(t[i, 1:])
        self.who = [np.asarray(w, dtype=np.int64) for w in who]
        self.where = [np.asarray(w, dtype=np.float64).reshape(-1, 2) for w in where]

    def others(self, frame: int, k: int) -> np.ndarray:
        """Positions of everyone but ``k`` at ``frame``."""
        i = frame - self.lo
        return self.where[i][self.who[i] != k]


def _encounters(path: np.ndarray, frame0: int, k: int, frames: _Frames) -> tuple[int, list[float]]:
    """Close encounters and nearest-neighbour distances of person ``k`` walking ``path``.

    ``path`` has one point per frame from ``frame0``. Encounters are with the replayed others
    (onsets of a centre distance below twice :data:`RADIUS`, per other person); the
    nearest-neighbour distance is taken at each frame with someone else present.
    """
    inside: dict[int, bool] = {}
    count = 0
    nearest: list[float] = []
    for i, p in enumerate(path):
        f = frame0 + i - frames.lo
        mask = frames.who[f] != k
        ids, pos = frames.who[f][mask], frames.where[f][mask]
        if len(ids) == 0:
            inside = {}
            continue
        d = np.hypot(pos[:, 0] - p[0], pos[:, 1] - p[1])
        nearest.append(float(d.min()))
        now = {int(j): bool(c) for j, c in zip(ids, d < 2 * RADIUS, strict=True)}
        count += sum(1 for j, c in now.items() if c and not inside.get(j, False))
        inside = now
    return count, nearest


def _straight(track: np.ndarray) -> tuple[np.ndarray, float]:
    """The straight line from the first to the last sample at the track's mean speed.

    Returns its points at the track's sample times and when it arrives (s).
    """
    t, xy = track[:, 0], track[:, 1:]
    length = float(np.sum(np.hypot(*np.diff(xy, axis=0).T)))
    speed = length / (t[-1] - t[0])
    way = xy[-1] - xy[0]
    dist = float(np.hypot(*way))
    along = np.minimum(speed * (t - t[0]), dist)
    unit = way / dist if dist > 1e-12 else np.zeros(2)
    # A track that never moves is at its goal from the start.
    return xy[0] + along[:, None] * unit, float(t[0] + dist / speed) if speed > 0 else float(t[0])


def _speeds(path: np.ndarray) -> np.ndarray:
    return np.hypot(*np.diff(path, axis=0).T) / SAMPLE_DT


def closed_loop(scene: Scene, params: Params | None = None) -> dict[str, Any]:
    """The closed-loop figures of ``scene`` (see the module doc).

    Per model (``proxemic``,
    ``straight_line``) ADE, FDE, mean absolute arrival time error and close encounters per person;
    the recording's own close encounters per person; and the speed and nearest-neighbour samples
    of the re-enacted and the recorded people (under ``samples``).
    """
    subjects = scene.subjects
    runs = scene.core.reenact(subjects, params or {}, OVERTIME_S)
    frames = _Frames(scene.tracks)
    acc: dict[str, dict[str, list[float]]] = {
        m: {"ade": [], "fde": [], "terr": [], "ce": []} for m in ("proxemic", "straight_line", "recorded")
    }
    samples: dict[str, list[float]] = {"speed_model": [], "speed_recorded": [], "nn_model": [], "nn_recorded": []}
    not_arrived = 0
    for k, (path, arrival) in zip(subjects, runs, strict=True):
        track = scene.tracks[k]
        truth, t_end = track[:, 1:], float(track[-1, 0])
        line, line_arrival = _straight(track)
        if arrival is None:
            not_arrived += 1
            arrival = t_end + OVERTIME_S
        f0 = frames.start[k]
        for name, walk, arr in (("proxemic", path, arrival), ("straight_line", line, line_arrival)):
            err = np.hypot(*(walk - truth).T)
            acc[name]["ade"].append(float(err[1:].mean()))
            acc[name]["fde"].append(float(err[-1]))
            acc[name]["terr"].append(abs(arr - t_end))
            acc[name]["ce"].append(_encounters(walk, f0, k, frames)[0])
        ce, nn_rec = _encounters(truth, f0, k, frames)
        acc["recorded"]["ce"].append(ce)
        samples["nn_recorded"] += nn_rec
        samples["nn_model"] += _encounters(path, f0, k, frames)[1]
        samples["speed_model"] += _speeds(path).tolist()
        samples["speed_recorded"] += _speeds(truth).tolist()
    out: dict[str, Any] = {"people": len(subjects), "not_arrived": not_arrived}
    for name in ("proxemic", "straight_line"):
        a = acc[name]
        out[name] = {
            "ade_m": _mean(a["ade"]),
            "fde_m": _mean(a["fde"]),
            "time_error_s": _mean(a["terr"]),
            "close_encounters_per_person": _mean(a["ce"]),
        }
    out["recorded"] = {"close_encounters_per_person": _mean(acc["recorded"]["ce"])}
    out["samples"] = samples
    return out


def _mean(v: Sequence[float]) -> float:
    return float(np.mean(v)) if len(v) else float("nan")


def open_loop(scene: Scene, params: Params | None = None) -> dict[str, Any]:
    """The open-loop figures (observe 8, predict 12).

    Mean ADE and FDE of the model and of constant velocity over every evaluated person and window.
    """
    rows = scene.core.open_loop(params or {}, OBSERVE, PREDICT, SAMPLE_DT)
    if len(rows) == 0:
        nan = float("nan")
        empty = {"ade_m": nan, "fde_m": nan}
        return {"windows": 0, "proxemic": empty, "constant_velocity": dict(empty)}
    m = rows.mean(axis=0)
    return {
        "windows": len(rows),
        "proxemic": {"ade_m": float(m[2]), "fde_m": float(m[3])},
        "constant_velocity": {"ade_m": float(m[4]), "fde_m": float(m[5])},
    }


def wasserstein1(a: Sequence[float], b: Sequence[float]) -> float:
    """Wasserstein-1 (earth mover's) distance between two 1-D samples.

    The area between their empirical distribution functions.
    """
    x, y = np.sort(np.asarray(a, float)), np.sort(np.asarray(b, float))
    if len(x) == 0 or len(y) == 0:
        return float("nan")
    grid = np.sort(np.concatenate([x, y]))
    fx = np.searchsorted(x, grid[:-1], side="right") / len(x)
    fy = np.searchsorted(y, grid[:-1], side="right") / len(y)
    return float(np.sum(np.abs(fx - fy) * np.diff(grid)))


def ks(a: Sequence[float], b: Sequence[float]) -> float:
    """Kolmogorov-Smirnov statistic: the largest gap between two empirical distribution functions."""
    x, y = np.sort(np.asarray(a, float)), np.sort(np.asarray(b, float))
    if len(x) == 0 or len(y) == 0:
        return float("nan")
    grid = np.concatenate([x, y])
    fx = np.searchsorted(x, grid, side="right") / len(x)
    fy = np.searchsorted(y, grid, side="right") / len(y)
    return float(np.max(np.abs(fx - fy)))


def distributions(samples: dict[str, list[float]]) -> dict[str, Any]:
    """Walking speed and nearest-neighbour distance, re-enacted against recorded.

    Medians, their ratio, Wasserstein-1 and KS.
    """
    out: dict[str, Any] = {}
    for key, name in (("speed", "speed_m_s"), ("nn", "nearest_neighbour_m")):
        model, rec = samples[f"{key}_model"], samples[f"{key}_recorded"]
        mm, mr = float(np.median(model)), float(np.median(rec))
        out[name] = {
            "median_reenacted": mm,
            "median_recorded": mr,
            "median_ratio": mm / mr if mr > 0 else float("nan"),
            "wasserstein_1": wasserstein1(model, rec),
            "ks": ks(model, rec),
        }
    return out


def rimea(params: Params | None = None) -> dict[str, Any]:
    """RiMEA tests 1, 4 and 6 with the model (``params`` over the defaults)."""
    p = params or {}
    t1 = _core.rimea1(p, RADIUS)
    speeds = _core.rimea4(list(RIMEA4_DENSITIES), p, RADIUS, 0)
    t6 = _core.rimea6(p, RADIUS, 0)
    return {
        "test1": {"time_s": t1, "expected_s": [26.0, 34.0], "pass": 26.0 <= t1 <= 34.0},
        "test4": {
            "densities_per_m2": list(RIMEA4_DENSITIES),
            "speed_m_s": speeds,
            "weidmann_m_s": [weidmann(d) for d in RIMEA4_DENSITIES],
        },
        "test6": {
            "people": 20,
            "arrived": t6["arrived"],
            "wall_crossings": t6["wall_crossings"],
            "time_s": t6["time"],
            "pass": t6["arrived"] == 20 and t6["wall_crossings"] == 0,
            "paths": [np.asarray(p).tolist() for p in t6["paths"]],
        },
    }


def weidmann(density: float) -> float:
    """Weidmann's walking speed (m/s) at ``density`` (people per m^2).

    Free speed 1.34 m/s, gamma 1.913, jam density 5.4 (Weidmann 1993).
    """
    if density >= 5.4:
        return 0.0
    return 1.34 * (1.0 - float(np.exp(-1.913 * (1.0 / density - 1.0 / 5.4))))


def card(scene: Scene, params: Params | None = None, rimea_result: dict[str, Any] | None = None) -> dict[str, Any]:
    """Every figure of ``scene``'s card (``card.json``).

    The samples behind the plots are under the private key ``_samples``.
    """
    cl = closed_loop(scene, params)
    samples = cl.pop("samples")
    out: dict[str, Any] = {
        "recording": scene.name,
        "window_s": list(scene.window) if scene.window else None,
        "tracks": len(scene.tracks),
        "params": {**_core.social_force_defaults(), **(params or {})},
        "closed_loop": cl,
        "open_loop": open_loop(scene, params),
        "distributions": distributions(samples),
        "rimea": rimea_result if rimea_result is not None else rimea(params),
        "_samples": samples,
    }
    return out


def _plots(c: dict[str, Any], out: Path) -> list[str]:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    name = c["recording"]
    s = c["_samples"]
    files = []
    for key, label, fname in (
        ("speed", "walking speed (m/s)", "speed.png"),
        ("nn", "nearest-neighbour distance (m)", "nearest_neighbour.png"),
    ):
        fig, ax = plt.subplots(figsize=(5, 3.2))
        a, b = np.asarray(s[f"{key}_recorded"]), np.asarray(s[f"{key}_model"])
        hi = float(np.percentile(np.concatenate([a, b]), 99)) if len(a) + len(b) else 1.0
        bins = np.linspace(0.0, hi, 40).tolist()
        ax.hist(a, bins=bins, alpha=0.5, density=True, label="recorded")
        ax.hist(b, bins=bins, alpha=0.5, density=True, label="re-enacted (proxemic)")
        ax.set_xlabel(label)
        ax.set_ylabel("density")
        ax.set_title(f"{name}: {label.split(' (')[0]}")
        ax.legend()
        fig.tight_layout()
        fig.savefig(out / fname, dpi=90)
        plt.close(fig)
        files.append(fname)
    r4 = c["rimea"]["test4"]
    fig, ax = plt.subplots(figsize=(5, 3.2))
    d = np.linspace(0.2, 5.4, 100)
    ax.plot(d, [weidmann(x) for x in d], "k-", label="Weidmann (1993)")
    ax.plot(r4["densities_per_m2"], r4["speed_m_s"], "o-", label="proxemic (ring corridor)")
    ax.set_xlabel("density (people per m²)")
    ax.set_ylabel("speed (m/s)")
    ax.set_title("RiMEA test 4: speed against density")
    ax.legend()
    fig.tight_layout()
    fig.savefig(out / "rimea4.png", dpi=90)
    plt.close(fig)
    files.append("rimea4.png")
    fig, ax = plt.subplots(figsize=(4, 4))
    for poly in ([(-0.2, -0.2), (12.2, -0.2), (12.2, 12.0)], [(-0.2, 2.0), (10.0, 2.0), (10.0, 12.0)]):
        xs, ys = zip(*poly, strict=True)
        ax.plot(xs, ys, "k-", lw=2)
    for p in c["rimea"]["test6"]["paths"]:
        p = np.asarray(p)
        ax.plot(p[:, 0], p[:, 1], lw=0.7)
    ax.set_aspect("equal")
    ax.set_title("RiMEA test 6: round a corner")
    fig.tight_layout()
    fig.savefig(out / "rimea6.png", dpi=90)
    plt.close(fig)
    files.append("rimea6.png")
    return files


def _f(v: Any) -> str:
    if v is None:
        return "-"
    if isinstance(v, bool):
        return "yes" if v else "no"
    if isinstance(v, float):
        return f"{v:.3f}"
    return str(v)


def markdown(c: dict[str, Any], image_dir: str = ".") -> str:
    """The card as Markdown: its tables and plots (images under ``image_dir``)."""
    cl, ol, di, ri = c["closed_loop"], c["open_loop"], c["distributions"], c["rimea"]
    window = f", time window {c['window_s'][0]:g}-{c['window_s'][1]:g} s" if c["window_s"] else ""
    lines = [
        f"### {c['recording']}",
        "",
        f"{c['tracks']} tracks{window}; {cl['people']} re-enacted (tracks of {MIN_TRACK_S:g} s or more), "
        f"{cl['not_arrived']} of them not arrived {OVERTIME_S:g} s after the recorded arrival.",
        "",
        "| closed loop | ADE (m) | FDE (m) | arrival time error (s) | close encounters per person |",
        "|---|---|---|---|---|",
    ]
    for m in ("proxemic", "straight_line"):
        r = cl[m]
        lines.append(
            f"| {m.replace('_', ' ')} | {_f(r['ade_m'])} | {_f(r['fde_m'])} | {_f(r['time_error_s'])} | "
            f"{_f(r['close_encounters_per_person'])} |"
        )
    lines.append(f"| recorded | | | | {_f(cl['recorded']['close_encounters_per_person'])} |")
    lines += [
        "",
        f"| open loop (observe {OBSERVE}, predict {PREDICT}; {ol['windows']} predictions) | ADE (m) | FDE (m) |",
        "|---|---|---|",
    ]
    for m in ("proxemic", "constant_velocity"):
        lines.append(f"| {m.replace('_', ' ')} | {_f(ol[m]['ade_m'])} | {_f(ol[m]['fde_m'])} |")
    lines += [
        "",
        "| distribution | median re-enacted | median recorded | ratio | Wasserstein-1 | KS |",
        "|---|---|---|---|---|---|",
    ]
    for key, label in (("speed_m_s", "walking speed (m/s)"), ("nearest_neighbour_m", "nearest neighbour (m)")):
        d = di[key]
        lines.append(
            f"| {label} | {_f(d['median_reenacted'])} | {_f(d['median_recorded'])} | {_f(d['median_ratio'])} | "
            f"{_f(d['wasserstein_1'])} | {_f(d['ks'])} |"
        )
    t4 = ri["test4"]
    lines += [
        "",
        "| RiMEA | result | expected | pass |",
        "|---|---|---|---|",
        f"| 1: 40 m corridor at 1.33 m/s | {_f(ri['test1']['time_s'])} s | 26-34 s | {_f(ri['test1']['pass'])} |",
        f"| 6: twenty people round a corner | {ri['test6']['arrived']} arrived, {ri['test6']['wall_crossings']} "
        f"wall crossings, last out at {_f(ri['test6']['time_s'])} s | 20 arrived, 0 crossings | "
        f"{_f(ri['test6']['pass'])} |",
        "",
        "| RiMEA 4: density (1/m²) | " + " | ".join(f"{d:g}" for d in t4["densities_per_m2"]) + " |",
        "|---" * (len(t4["densities_per_m2"]) + 1) + "|",
        "| proxemic speed (m/s) | " + " | ".join(f"{v:.2f}" for v in t4["speed_m_s"]) + " |",
        "| Weidmann speed (m/s) | " + " | ".join(f"{v:.2f}" for v in t4["weidmann_m_s"]) + " |",
        "",
    ]
    for f, alt in (
        ("speed.png", "walking speed"),
        ("nearest_neighbour.png", "nearest-neighbour distance"),
        ("rimea4.png", "RiMEA 4"),
        ("rimea6.png", "RiMEA 6"),
    ):
        lines.append(f"![{c['recording']}: {alt}]({image_dir}/{f})")
    lines.append("")
    return "\n".join(lines)


def write_cards(
    recordings: Sequence[str | Path],
    out: str | Path,
    *,
    window: tuple[float, float] | None = None,
    params: Params | None = None,
    log: Callable[[str], None] = lambda s: print(s, file=sys.stderr, flush=True),
) -> list[dict[str, Any]]:
    """Builds the card of each recording into ``out`` (one) or ``out/<name>/`` (several).

    Writes ``card.md``, ``card.json`` and the PNG plots. Returns the cards (without the samples).
    """
    out = Path(out)
    log("RiMEA tests 1, 4, 6 ...")
    t = time.perf_counter()
    rimea_result = rimea(params)
    log(f"  done in {time.perf_counter() - t:.1f} s")
    cards = []
    for rec in recordings:
        t = time.perf_counter()
        scene = load(rec, window)
        log(f"{scene.name}: {len(scene.tracks)} tracks, {len(scene.subjects)} re-enacted ...")
        c = card(scene, params, rimea_result)
        d = out / scene.name if len(recordings) > 1 else out
        d.mkdir(parents=True, exist_ok=True)
        _plots(c, d)
        c.pop("_samples")
        public = json.loads(json.dumps(c))
        public["rimea"]["test6"].pop("paths", None)
        (d / "card.json").write_text(json.dumps(public, indent=2) + "\n")
        (d / "card.md").write_text(markdown(public) + "\n")
        log(f"  {d}/card.md, card.json, 4 plots ({time.perf_counter() - t:.1f} s)")
        cards.append(public)
    return cards


FIT_GRID: dict[str, tuple[float, ...]] = {
    "strength": (1.0, 2.0, 3.0, 4.5, 6.0, 8.0),
    "gamma": (0.2, 0.27, 0.35, 0.45, 0.6),
    "lambda": (0.5, 1.0, 2.0, 3.0),
    "tau": (0.3, 0.5, 0.8, 1.2),
    "n": (1.0, 2.0, 3.0),
    "n_prime": (2.0, 3.0, 4.5),
}
"""The calibration's grid: the interaction strength A (m/s^2), range factor gamma, the weight of
the relative velocity lambda (the anisotropy), the relaxation time tau (s) and the angular widths
n and n' of Moussaid et al. 2009 (their published values are in each axis)."""

FIT_ROUNDS = 2
"""Coordinate-descent passes over :data:`FIT_GRID`."""

FIT_STRIDE = 3
"""The calibration re-enacts every third eligible person of each training recording (in file
order; a deterministic subset that keeps a fit within minutes on two cores)."""


def objective(scenes: Sequence[Scene], params: Params) -> tuple[float, dict[str, float]]:
    """The calibration's objective and its parts.

    Closed-loop ADE (m, every re-enacted person of every scene counted once) plus the gap
    between the model's and the recordings' close encounters per person (one encounter per
    person weighs like a metre of ADE).
    """
    ade, ce, ce_rec, n = 0.0, 0.0, 0.0, 0
    for s in scenes:
        cl = closed_loop(s, params)
        k = cl["people"]
        ade += cl["proxemic"]["ade_m"] * k
        ce += cl["proxemic"]["close_encounters_per_person"] * k
        ce_rec += cl["recorded"]["close_encounters_per_person"] * k
        n += k
    ade, ce, ce_rec = ade / n, ce / n, ce_rec / n
    return ade + abs(ce - ce_rec), {"ade_m": ade, "ce_per_person": ce, "ce_recorded": ce_rec}


def calibrate(
    recordings: Sequence[str | Path],
    *,
    start: Params | None = None,
    grid: dict[str, tuple[float, ...]] | None = None,
    rounds: int = FIT_ROUNDS,
    stride: int = FIT_STRIDE,
    log: Callable[[str], None] = lambda s: print(s, file=sys.stderr, flush=True),
) -> tuple[Params, list[dict[str, Any]]]:
    """Fits the interaction parameters on ``recordings``.

    The UCY ones: never the ETH ones, which validate. Coordinate descent over ``grid``: each
    parameter in turn takes the grid value that minimises :func:`objective` with the others
    held, for ``rounds`` passes (deterministic: no random draw). Returns the fitted parameters
    and the log of every evaluation.
    """
    scenes = [load(r) for r in recordings]
    for s in scenes:
        s.stride = stride
    grid = grid or FIT_GRID
    defaults = _core.social_force_defaults()
    best: Params = {k: float(defaults[k]) for k in grid} | dict(start or {})
    best_j, info = objective(scenes, best)
    history = [{"params": dict(best), "objective": best_j, **info}]
    log(f"start {best}: J = {best_j:.4f} {info}")
    for r in range(rounds):
        changed = False
        for name, values in grid.items():
            for v in values:
                if v == best[name]:
                    continue
                trial = best | {name: v}
                j, info = objective(scenes, trial)
                history.append({"params": dict(trial), "objective": j, **info})
                ade, ce = info["ade_m"], info["ce_per_person"]
                log(f"round {r + 1} {name} = {v:g}: J = {j:.4f} (ADE {ade:.3f}, CE {ce:.3f})")
                if j < best_j - 1e-9:
                    best, best_j, changed = trial, j, True
            log(f"round {r + 1}: {name} -> {best[name]:g} (J = {best_j:.4f})")
        if not changed:
            break
    return best, history


DOCS_BEGIN = "<!-- crowd-card: begin (written by proxemic crowd-card --docs; do not edit) -->"
DOCS_END = "<!-- crowd-card: end -->"


def write_docs(cards: Sequence[dict[str, Any]], out: str | Path, page: str | Path) -> None:
    """Puts the cards written in ``out`` into the docs ``page``.

    Their plots are copied under
    ``images/crowd-card/<recording>/`` beside the page, their tables between the page's
    :data:`DOCS_BEGIN` and :data:`DOCS_END` markers.
    """
    import shutil

    page, out = Path(page), Path(out)
    check_block(page, DOCS_BEGIN, DOCS_END)
    parts = []
    for c in cards:
        src = out / c["recording"] if len(cards) > 1 else out
        images = Path("images") / "crowd-card" / c["recording"]
        (page.parent / images).mkdir(parents=True, exist_ok=True)
        for png in src.glob("*.png"):
            shutil.copyfile(png, page.parent / images / png.name)
        parts.append(markdown(c, images.as_posix()))
    write_block(page, DOCS_BEGIN, DOCS_END, "\n" + "\n".join(parts) + "\n")
