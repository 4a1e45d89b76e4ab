"""Who approached whom: ``proxemic eval`` shows the zones read on body gaps, robot- and person-caused.

The zone metrics themselves are known-answer tested in the core
(``rust/proxemic-core/src/metrics/approach.rs``); here: the records carry them and add up, the
headline shows the body-gap intimate reading beside the centre one, each named for what it
measures, and the summary has the robot-caused and person-caused columns.
"""

from __future__ import annotations

import csv
import math

from proxemic.cli import main
from proxemic.evaluation import HEADLINE, METRICS

#: The who-approached-whom columns of eval's summary (one per zone, reading and cause).
SPLIT = (
    "intimate_gap_time_robot_caused",
    "intimate_gap_time_person_caused",
    "intimate_gap_entries_robot_caused",
    "intimate_gap_entries_person_caused",
    "personal_gap_time_robot_caused",
    "personal_gap_time_person_caused",
    "personal_gap_entries_robot_caused",
    "personal_gap_entries_person_caused",
)


def test_the_headline_names_each_intimate_reading_for_what_it_measures() -> None:
    assert {"psi_intimate", "intimate_gap_time"} <= set(HEADLINE)
    assert METRICS["psi_intimate"].label == "intimate-zone time, centres"
    assert METRICS["intimate_gap_time"].label == "intimate-zone time, body gaps"
    for key in (
        "intimate_gap_entries_robot_caused",
        "intimate_gap_entries_person_caused",
        "personal_gap_time_robot_caused",
        "personal_gap_time_person_caused",
    ):
        assert key in HEADLINE, key


def test_eval_on_the_museum_shows_robot_and_person_caused_columns(tmp_path, capsys) -> None:
    out = tmp_path / "eval"
    argv = ["eval", "--scenario", "museum", "--planner", "astar", "--episodes", "1", "--seed", "200"]
    assert main([*argv, "--workers", "1", "--out", str(out)]) == 0
    printed = capsys.readouterr().out
    for key in ("psi_intimate", "intimate_gap_time", *(k for k in SPLIT if k in HEADLINE)):
        assert METRICS[key].label in printed, key
    summary = (out / "summary.md").read_text()
    for key in SPLIT:
        assert METRICS[key].label in summary, key
    with (out / "episodes.csv").open() as fh:
        (rec,) = list(csv.DictReader(fh))
    for zone in ("intimate", "personal"):
        for what in ("time", "entries"):
            total = float(rec[f"{zone}_gap_{what}"])
            parts = float(rec[f"{zone}_gap_{what}_robot_caused"]) + float(rec[f"{zone}_gap_{what}_person_caused"])
            assert math.isclose(total, parts, rel_tol=1e-9, abs_tol=1e-12), (zone, what, rec)
    # Plain A* crosses the museum's walkers: it spends time within 1.2 m of people's bodies.
    assert float(rec["personal_gap_time"]) > 0.0
