"""What an evaluation writes: records as CSV and Parquet, the summary, the plots."""

from __future__ import annotations

import csv
from collections.abc import Sequence
from pathlib import Path
from typing import TYPE_CHECKING, Any

from proxemic.errors import EpisodeError, MissingExtraError, ProxemicError, input_error
from proxemic.evaluation.config import EpisodeResult, EvalConfig
from proxemic.evaluation.metrics import METRIC_GROUPS, METRICS
from proxemic.evaluation.summary import is_rate

if TYPE_CHECKING:
    from proxemic.evaluation.run import EvalResult


def check_out_dir(out: Path) -> None:
    """Creates `out` if needed and checks that it can be written (InputError naming it if not)."""
    try:
        out.mkdir(parents=True, exist_ok=True)
        probe = out / ".write-test"
        probe.write_text("")
        probe.unlink()
    except OSError as e:
        raise input_error(
            "out", "a writable folder", str(out), note=f"the output folder cannot be written: {e.strerror}"
        ) from e


class RecordWriter:
    """Per-episode records written as they arrive: CSV rows flushed one by one, Parquet at the end.

    Used as a context manager around a run. If the run fails or is interrupted, the records that
    finished stay in the CSV, the Parquet file is written with them, and the error is re-raised as
    an :class:`EpisodeError` naming the episode that failed (an interrupt stays a
    ``KeyboardInterrupt``). `tasks` (in result order) names the failed episode.
    """

    def __init__(self, csv_path: Path, parquet_path: Path, tasks: Sequence[Any] = ()) -> None:
        """Opens the CSV file for writing (and removes an earlier run's Parquet file)."""
        self.csv_path, self.parquet_path, self.tasks = csv_path, parquet_path, tasks
        parquet_path.unlink(missing_ok=True)
        self.rows: list[dict[str, Any]] = []
        self._fh = csv_path.open("w", newline="")
        self._writer: csv.DictWriter[str] | None = None

    def write(self, record: dict[str, Any]) -> None:
        """Appends one record (the first fixes the columns) and flushes it to disk."""
        if self._writer is None:
            self._writer = csv.DictWriter(self._fh, fieldnames=list(record.keys()))
            self._writer.writeheader()
        self._writer.writerow(record)
        self._fh.flush()
        self.rows.append(record)

    def __enter__(self) -> RecordWriter:
        return self

    def __exit__(self, exc_type: type[BaseException] | None, exc: BaseException | None, tb: object) -> None:
        self._fh.close()
        if self.rows:
            _write_parquet(self.rows, self.parquet_path)
        if not isinstance(exc, Exception) or isinstance(exc, EpisodeError):
            return  # success, or an interrupt: the records stay, the exception goes on as it is
        if isinstance(exc, MissingExtraError) or (
            isinstance(exc, ProxemicError) and exc.field in ("backend", "ray_address")
        ):
            return  # the backend did not start: no episode ran
        n = sum(1 for r in self.rows if r.get("robot", 0) == 0)  # episodes (a record per robot)
        task = f" {self.tasks[n]}" if n < len(self.tasks) else ""
        raise EpisodeError(
            f"episode {n + 1}{task} failed ({type(exc).__name__}: {exc}); the {n} finished episodes are kept "
            f"in {self.csv_path} and {self.parquet_path.name}",
            field="episode",
            expected="an episode that runs to its end",
            found=f"{type(exc).__name__}: {exc}",
        ) from exc


def _write_outputs(cfg: EvalConfig, result: EvalResult, scenario: Any, kept: dict[str, list[EpisodeResult]]) -> None:
    from proxemic.viz.plots import plot_episodes, plot_metrics_grid

    out = Path(cfg.out or ".")
    (out / "summary.md").write_text(result.summary_markdown() + "\n")
    plot_metrics_grid(
        result.summary,
        [
            (name, [(m, METRICS[m].label, "rate" if is_rate(m) else METRICS[m].unit) for m in ms])
            for name, ms in METRIC_GROUPS
        ],
        out / "metrics.png",
        title=f"{cfg.scene_label}: {cfg.episodes} seeded episodes each "
        f"(seeds {cfg.seed}-{cfg.seed + cfg.episodes - 1}); "
        "bars: rate or mean, whiskers: 95% interval (Wilson for rates, Student t for means),\n"
        "clipped to each metric's range (0-100% for rates and time shares, >= 0 for lengths and times)",
    )
    for planner, results in kept.items():
        episodes = [
            {
                "label": f"seed {r.record['seed']}",
                "robot": r.robot,
                "people": r.people,
                "path": r.path if i == 0 else None,
                "outcome": r.record["outcome"],
            }
            for i, r in enumerate(results)
        ]
        if episodes:
            title = f"{cfg.scene_label}: {planner}"
            plot_episodes(scenario, episodes, out / f"trajectories_{planner}.png", title=title)
    plot_planners_on_social_map(cfg.scenario, cfg.seed, kept, out / "trajectories_social_map.png")


def plot_planners_on_social_map(
    scenario: str, seed: int, kept: dict[str, list[EpisodeResult]], out_png: Path
) -> Path | None:
    """Each planner's executed trajectory of episode `seed` over the social cost map at its start."""
    from proxemic.social import SocialMap

    paths = {
        planner: results[0].robot[:, :2]
        for planner, results in kept.items()
        if results and results[0].record["seed"] == seed and results[0].robot is not None
    }
    if not paths:
        return None
    outcomes = {planner: str(results[0].record["outcome"]) for planner, results in kept.items() if planner in paths}
    sm = SocialMap(scenario, seed=seed)
    return sm.plot(
        out_png,
        paths=paths,
        outcomes=outcomes,
        title=f"{scenario}, seed {seed}: executed trajectories over the social map",
    )


def _write_parquet(records: Sequence[dict[str, Any]], path: Path) -> None:
    import pyarrow as pa
    import pyarrow.parquet as pq

    pq.write_table(pa.Table.from_pylist(list(records)), path)
