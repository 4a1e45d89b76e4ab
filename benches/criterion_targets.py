"""Checks the criterion benches of the core against their speed targets.

``make bench`` runs the criterion benches first (``cargo bench``); this script then reads the
median of every targeted bench from criterion's output (``target/criterion/<id>/new/estimates.json``,
the median over criterion's samples of the time per iteration) and prints one row per target:
the measured median, the target and ``met`` or ``MISSED``. A target whose bench left no estimate
(it was not run, or crashed), or only an estimate older than the file given with ``--newer-than``
(``make bench`` touches ``target/bench-start`` before it runs the benches), counts as missed.
Exit status 1 when a target is missed.

The targets hold for every planner that has the part measured:

- a Social Momentum step with 50 people (<= 20 us): the ``social`` planner's (discs, comfort
  term), ``daza2021``'s (Daza et al. 2021's intimate discs and group o-spaces, no comfort term)
  and ``sousa2022``'s (Sousa et al. 2022's fully asymmetric Gaussians, their construction from
  the perceived individuals included);
- the social map with 50 people and 10 object spaces, full rebuild (<= 2 ms) and the update when
  5 of the 50 move (<= 0.5 ms): the map of the ``social`` and ``social_astar`` planners (each
  individual's Hall zones) and ``calderita``'s (the contours of the summed density ``G_d``).
  ``daza2021`` and ``sousa2022`` plan on the static map (plain A*, their Algorithm 1 line 1), so
  they have no social map to time;
- social A* across the museum (<= 5 ms) and group detection among 200 people (<= 200 us).

Run: ``python benches/criterion_targets.py [--dir target/criterion]`` after ``cargo bench``.
"""

from __future__ import annotations

import argparse
import json
import sys
from pathlib import Path

#: (criterion id, target in microseconds, what it measures)
TARGETS: tuple[tuple[str, float, str], ...] = (
    ("sm/step_50_people", 20.0, "Social Momentum step, 50 people (social)"),
    ("sm/daza2021_step_50_people", 20.0, "Social Momentum step, 50 people (daza2021)"),
    ("sm/sousa2022_step_50_people", 20.0, "Social Momentum step, 50 people (sousa2022, Gaussians)"),
    ("socialmap/full_rebuild_50_people_10_objects", 2000.0, "social map full rebuild (social)"),
    ("socialmap/incremental_5_of_50_move", 500.0, "social map update, 5 of 50 move (social)"),
    ("socialmap/calderita_full_rebuild_50_people_10_objects", 2000.0, "social map full rebuild (calderita)"),
    ("socialmap/calderita_update_5_of_50_move", 500.0, "social map update, 5 of 50 move (calderita)"),
    ("socialmap/social_astar_across_museum", 5000.0, "social A* across the museum"),
    ("socialmap/group_detection_200_people", 200.0, "group detection, 200 people"),
)


def median_us(root: Path, bench_id: str, since: float) -> float | None:
    """The median time per iteration (us) criterion saved for `bench_id` after `since`, if any."""
    # A benchmark group's function is a directory inside the group's; a bare function's id keeps
    # its slashes as underscores.
    grouped = root.joinpath(*bench_id.split("/"), "new", "estimates.json")
    path = grouped if grouped.exists() else root / bench_id.replace("/", "_") / "new" / "estimates.json"
    try:
        if path.stat().st_mtime < since:
            return None
        data = json.loads(path.read_text())
        return float(data["median"]["point_estimate"]) / 1e3
    except (OSError, KeyError, TypeError, ValueError):
        return None


def main() -> int:
    """Prints the target rows; returns 1 when one is missed."""
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    default = Path(__file__).resolve().parent.parent / "target" / "criterion"
    p.add_argument("--dir", type=Path, default=default, help=f"criterion's output directory (default: {default})")
    p.add_argument("--newer-than", type=Path, help="ignore estimates older than this file (a stale run)")
    a = p.parse_args()
    since = a.newer_than.stat().st_mtime if a.newer_than else 0.0
    print("criterion targets (median time per iteration)")
    missed = []
    for bench_id, target, what in TARGETS:
        us = median_us(a.dir, bench_id, since)
        if us is None:
            missed.append(bench_id)
            print(f"  {what:58s} {'no estimate':>12s}  target <= {target:7.1f} us  MISSED ({bench_id}: not run)")
            continue
        ok = us <= target
        if not ok:
            missed.append(bench_id)
        print(f"  {what:58s} {us:9.1f} us  target <= {target:7.1f} us  {'met' if ok else 'MISSED'}  ({bench_id})")
    print("targets: " + ("all met" if not missed else "MISSED: " + ", ".join(missed)))
    return 1 if missed else 0


if __name__ == "__main__":
    sys.exit(main())
