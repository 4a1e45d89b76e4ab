"""``proxemic tune``: the controller gain search of Calderita et al. §5.4, over seeded episodes.

Calderita et al. (seed 003, §5.4, Eq. 17-20) tune the elastic band's two gains (``k_c``,
contraction, and ``k_r``, repulsion) by minimising a cost over the robot's executed trajectories

    G = a*H + b*D + c*Q + d*P

- ``H``: the sum of heading changes along the path (Eq. 18), ``sum |wrap(theta_{k+1} - theta_k)|``
  over the control instants (rad; theta is the robot's yaw, the paper's ``H = integral of dtheta``):
  the core's ``chc`` metric;
- ``D``: the distance travelled (Eq. 19), the length of the executed polyline (m): ``d_t``;
- ``Q``: the time used to complete the path, ``steps * control_dt`` (s): ``tau``;
- ``P``: the mean over the control instants of the distance from the robot to the nearest person
  (Eq. 20, printed with ``H`` on its left but defining P; centre to centre, m): ``cp_avg``. The
  paper takes the people *visible* from the robot; here every person counts (no people: ``P = 0``).

The four terms are read from the episode's metrics (computed by the core, see
``docs/metrics.md``), not recomputed here.

The paper does not give ``a, b, c, d``. H, D and Q are penalties (more is worse); P is a
distance kept from people, which is better when larger, so its weight is negative for a cost to
be *minimised*. Defaults: ``a = 1 /rad``, ``b = 1 /m``, ``c = 1 /s``, ``d = -1 /m`` (all
configurable). The paper's paths all reach their targets; here an episode that does not reach its
goal (collision or timeout, which would otherwise *lower* D and Q) adds ``failure_penalty``
(default 100) to its G. A gain point's G is the mean of its episodes' G (the paper keeps the best
single path of each gain; a mean over seeded episodes and targets is less noisy).

Search (as in the paper): start from the current gains (the defaults: Calderita's optimum
``k_c = 120``, ``k_r = 60`` mapped by ratio, see ``proxemic-core`` ``control::eband``), then fix all
gains but one and sample that one in its range (``samples`` points, stratified random from the
run's seed), keep the best point, move to the next gain, and stop when a full cycle over the gains
brings no improvement or the trial budget is spent. Every gain point runs the same episode seeds
on every target scene, on the same process pool or Ray backend as ``proxemic eval``.
"""

from __future__ import annotations

import json
import math
from collections.abc import Mapping, Sequence
from dataclasses import asdict, dataclass, field
from pathlib import Path
from typing import Any

import numpy as np

from proxemic import markdown, scenarios
from proxemic.errors import input_error
from proxemic.evaluation import Backend, RecordWriter, cached_env, check_out_dir, mean_ci

#: The Calderita scenes (the robot's targets when none are given).
DEFAULT_TARGETS: tuple[str, ...] = ("calderita_exp1", "calderita_exp2")

#: Planners whose gains are exposed (the elastic band's ``contraction_gain``, ``repulsion_gain``,
#: ``social_gain``): ``calderita`` (Calderita's system: the band on the Dijkstra path over the
#: time-dependent social map, the band the paper tunes; the default) and ``eband`` (the band on a
#: plain A* path).
TUNABLE_PLANNERS: tuple[str, ...] = ("calderita", "eband")

Target = tuple[str, tuple[float, float] | None]
"""A scene (bundled name or TOML path) and the robot's goal in it (None: the scene's own goal)."""

#: Search ranges of the gains when none are given: Calderita's two gains (contraction and
#: repulsion), each around the default (1.0 and 0.5).
DEFAULT_RANGES: Mapping[str, tuple[float, float]] = {"contraction_gain": (0.1, 3.0), "repulsion_gain": (0.0, 2.0)}


@dataclass(frozen=True)
class CostWeights:
    """Weights of G = a*H + b*D + c*Q + d*P (Calderita Eq. 17; values not given by the paper)."""

    a: float = 1.0
    """Per radian of heading change."""
    b: float = 1.0
    """Per metre travelled."""
    c: float = 1.0
    """Per second."""
    d: float = -1.0
    """Per metre of mean distance to the nearest person (negative: keeping away is better)."""
    failure_penalty: float = 100.0
    """Added to an episode's G when it does not reach its goal."""

    def cost(self, terms: Mapping[str, Any]) -> float:
        """G of one episode from its terms ``H``, ``D``, ``Q``, ``P`` and ``success``."""
        g = self.a * terms["H"] + self.b * terms["D"] + self.c * terms["Q"] + self.d * terms["P"]
        return float(g + (0.0 if terms["success"] else self.failure_penalty))


#: Calderita's terms and the core's metrics they are (see the module docs).
TERM_METRICS: Mapping[str, str] = {"H": "chc", "D": "d_t", "Q": "tau", "P": "cp_avg"}


def metric_terms(metrics: Mapping[str, Any]) -> dict[str, float]:
    """H, D, Q, P of one episode from its metrics (``ProxemicEnv.metrics``; see the module docs).

    ``cp_avg`` is undefined (None) without people; P is then 0.
    """
    return {term: float(metrics[name] or 0.0) for term, name in TERM_METRICS.items()}


@dataclass(frozen=True)
class TuneConfig:
    """What to tune, on which targets, and where to write it."""

    targets: Sequence[str | Target] = DEFAULT_TARGETS
    """Scenes (bundled names or TOML paths: the robot goes to the scene's goal) or (scene, goal) pairs."""
    planner: str = "calderita"
    """The planner whose band is tuned, one of ``TUNABLE_PLANNERS``."""
    trials: int = 20
    """Gain points evaluated at most (the first is the starting gains)."""
    episodes: int = 3
    """Seeded episodes per target and gain point (seeds ``seed .. seed + episodes - 1``)."""
    seed: int = 0
    """First episode seed, and the seed of the search's sampling."""
    samples: int = 4
    """Values of one gain tried per search step."""
    ranges: Mapping[str, tuple[float, float]] = field(default_factory=lambda: dict(DEFAULT_RANGES))
    weights: CostWeights = field(default_factory=CostWeights)
    out: Path = Path("out/tune")
    workers: int = 2
    backend: str = "process"
    ray_address: str | None = None

    def target_list(self) -> list[Target]:
        """The targets as (scene, goal or None) pairs."""
        return [(t, None) if isinstance(t, str | Path) else (str(t[0]), t[1]) for t in self.targets]

    def check(self) -> None:
        """Raises a ProxemicError for bad input (names, goals, counts, ranges).

        Planner and gain names are validated by the core (``ScenarioError`` naming them).
        """
        from proxemic import _core

        if not self.targets:
            raise input_error("targets", "at least one scene", "none")
        for scene, goal in self.target_list():
            core, _ = scenarios.load(scene, planner=self.planner, goal=goal)
            if goal is not None:
                _core.World(core)  # a goal inside a wall or object is rejected here, naming it
        if self.planner not in TUNABLE_PLANNERS:
            raise input_error(
                "planner", f"a planner with tunable gains, one of {', '.join(TUNABLE_PLANNERS)}", self.planner
            )
        for name, value in (("trials", self.trials), ("episodes", self.episodes), ("samples", self.samples)):
            if value < 1:
                raise input_error(name, "at least 1", value)
        if not self.ranges:
            raise input_error("ranges", "at least one gain to tune", "none")
        for name, (lo, hi) in self.ranges.items():
            if not (math.isfinite(lo) and math.isfinite(hi) and 0.0 <= lo < hi <= 100.0):
                raise input_error(f"gain.{name}", "a range 0 <= low < high <= 100", f"[{lo}, {hi}]")
        # the gain names, checked by the core (its ScenarioError names an unknown one)
        scenarios.load(self.target_list()[0][0], eband={name: lo for name, (lo, _) in self.ranges.items()})


@dataclass
class Trial:
    """One evaluated gain point."""

    trial: int
    step: int
    """Search step (0: the starting gains)."""
    varied: str
    """The gain sampled in this step ("start" for the starting point)."""
    gains: dict[str, float]
    G: float
    G_ci: float
    """95% half-width of G over the seeds (each seed's G averaged over the targets; Student t; NaN
    for one seed)."""
    H: float
    D: float
    Q: float
    P: float
    success: float
    """Share of its episodes that reached the goal."""


TuneTask = tuple[int, Target, str, int, tuple[tuple[str, float], ...]]
"""(trial, target, planner, seed, eband gains as sorted (name, value) pairs)."""


def run_tune_task(task: TuneTask) -> dict[str, Any]:
    """Runs one episode of a gain point; returns its record with H, D, Q, P (no G: the caller weighs)."""
    from proxemic.runner import run_episode

    trial, (scenario, goal), planner, seed, gains = task
    env = cached_env(scenario, planner, dict(gains), goal)
    rec = run_episode(scenario, seed, env=env)
    terms = metric_terms(rec.metrics)
    gx, gy = env.scenario["robots"][0]["goal"]
    return {
        "trial": trial,
        "scenario": env.scenario["scene"]["name"],
        "goal_x": gx,
        "goal_y": gy,
        "seed": seed,
        **dict(gains),
        "outcome": rec.metrics["outcome"],
        "success": bool(rec.metrics["success"]),
        **terms,
    }


def _start_gains(cfg: TuneConfig) -> dict[str, float]:
    """The first target's gains (file values or defaults), clipped into the ranges."""
    _, desc = scenarios.load(cfg.target_list()[0][0], planner=cfg.planner)
    current = desc["robots"][0]["eband"]
    return {k: float(np.clip(current[k], lo, hi)) for k, (lo, hi) in cfg.ranges.items()}


def run_tune(cfg: TuneConfig, *, progress: bool = True) -> dict[str, Any]:
    """Runs the gain search and writes every evaluated point into ``cfg.out``.

    Files: ``trials.csv``/``.parquet`` (one row per gain point: gains, G and its mean terms),
    ``episodes.csv``/``.parquet`` (one row per episode, written as it finishes), ``tune.json``
    (the settings, the best point and every trial; also returned) and ``tune.png`` (the G curve).
    """
    from tqdm import tqdm

    cfg.check()
    out = Path(cfg.out)
    check_out_dir(out)
    names = list(cfg.ranges)
    rng = np.random.default_rng(cfg.seed)
    seeds = [cfg.seed + k for k in range(cfg.episodes)]
    targets = cfg.target_list()
    per_point = len(targets) * len(seeds)
    trials: list[Trial] = []
    bar = tqdm(total=cfg.trials * per_point, desc=f"tune {cfg.planner}", unit="ep", disable=not progress)

    def evaluate(points: list[dict[str, float]], step: int, varied: str) -> None:
        first = len(trials)
        tasks: list[TuneTask] = [
            (first + i, t, cfg.planner, s, tuple(sorted(p.items())))
            for i, p in enumerate(points)
            for t in targets
            for s in seeds
        ]
        recs: list[dict[str, Any]] = []
        for rec in backend.imap(run_tune_task, tasks):
            rec["G"] = cfg.weights.cost(rec)
            episodes.write(rec)
            recs.append(rec)
            bar.update(1)
        for i, p in enumerate(points):
            mine = recs[i * per_point : (i + 1) * per_point]
            mean = {k: float(np.mean([r[k] for r in mine])) for k in ("G", "H", "D", "Q", "P", "success")}
            # the spread over seeds of the seed's G averaged over the targets (targets are a fixed design)
            by_seed = [np.mean([r["G"] for r in mine if r["seed"] == s]) for s in seeds]
            mean["G_ci"] = mean_ci(by_seed)[1]
            trials.append(Trial(first + i, step, varied, dict(p), **mean))
            trials_out.write(_trial_row(trials[-1]))

    with (
        Backend(cfg.backend, cfg.workers, cfg.ray_address) as backend,
        RecordWriter(out / "trials.csv", out / "trials.parquet") as trials_out,
        RecordWriter(out / "episodes.csv", out / "episodes.parquet") as episodes,
    ):
        evaluate([_start_gains(cfg)], 0, "start")
        best = trials[0]
        step, stale = 0, 0
        while len(trials) < cfg.trials and stale < len(names):
            name = names[step % len(names)]
            step += 1
            k = min(cfg.samples, cfg.trials - len(trials))
            lo, hi = cfg.ranges[name]
            # Stratified random: one uniform sample in each of k equal slices of the range.
            values = lo + (np.arange(k) + rng.uniform(size=k)) * (hi - lo) / k
            evaluate([{**best.gains, name: round(float(v), 6)} for v in values], step, name)
            cand = min(trials[-k:], key=lambda t: t.G)
            if cand.G < best.G:
                best, stale = cand, 0
            else:
                stale += 1
    bar.close()
    result = {
        "targets": [{"scenario": str(t), "goal": list(g) if g is not None else None} for t, g in targets],
        "planner": cfg.planner,
        "seeds": seeds,
        "search_seed": cfg.seed,
        "weights": asdict(cfg.weights),
        "ranges": {k: list(v) for k, v in cfg.ranges.items()},
        "best": _trial_row(best),
        "trials": [_trial_row(t) for t in trials],
    }
    (out / "tune.json").write_text(json.dumps(result, indent=2) + "\n")
    from proxemic.viz.plots import plot_tune

    plot_tune([_trial_row(t) for t in trials], names, out / "tune.png")
    return result


def _trial_row(t: Trial) -> dict[str, Any]:
    row = asdict(t)
    if not math.isfinite(row["G_ci"]):
        row["G_ci"] = None  # one episode: no interval (JSON has no NaN)
    gains = row.pop("gains")
    return {"trial": row.pop("trial"), "step": row.pop("step"), "varied": row.pop("varied"), **gains, **row}


def curve_text(result: Mapping[str, Any]) -> str:
    """The G curve as a markdown table: every trial's gains and G, and the best G so far."""
    trials = result["trials"]
    names = list(result["ranges"])
    cols = ["trial", "varied", *names, "G (95% CI)", "best G", "success"]
    rows = []
    best = math.inf
    for t in trials:
        best = min(best, t["G"])
        cells = [str(t["trial"]), t["varied"], *(f"{t[n]:.4g}" for n in names)]
        ci = f" ± {t['G_ci']:.3f}" if t["G_ci"] is not None else ""
        cells += [f"{t['G']:.3f}{ci}", f"{best:.3f}", f"{t['success']:.2f}"]
        rows.append(cells)
    return markdown.table(cols, rows)
