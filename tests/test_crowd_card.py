"""The crowd card: RiMEA known answers, the card end to end, the calibrated model's targets on the
ETH recordings (never fitted on), and its speed and spacing on every recording."""

from __future__ import annotations

import json
import math
from functools import cache
from pathlib import Path
from typing import Any

import numpy as np
import pytest

from proxemic import _core, crowdcard
from proxemic.cli import main
from proxemic.errors import InputError, ScenarioError

DATA = Path(__file__).resolve().parents[2] / "shared" / "data" / "recorded_crowds"
if not DATA.is_dir():
    DATA = Path("/work/shared/data/recorded_crowds")
needs_data = pytest.mark.skipif(not (DATA / "hotel.csv").is_file(), reason="the ETH/UCY recordings are not here")


def test_rimea_1_one_person_crosses_40_m_in_26_to_34_s() -> None:
    t = _core.rimea1()
    assert 26.0 <= t <= 34.0, t


def test_rimea_6_twenty_people_round_the_corner_through_no_wall() -> None:
    r = _core.rimea6()
    assert (r["arrived"], r["wall_crossings"]) == (20, 0)


def test_weidmann_curve() -> None:
    assert crowdcard.weidmann(5.4) == 0.0
    assert crowdcard.weidmann(1.0) == pytest.approx(1.34 * (1 - math.exp(-1.913 * (1 - 1 / 5.4))))


def test_distribution_distances() -> None:
    a = [0.0, 1.0, 2.0]
    assert crowdcard.wasserstein1(a, a) == 0.0
    assert crowdcard.wasserstein1(a, [x + 0.5 for x in a]) == pytest.approx(0.5)
    assert crowdcard.ks(a, [10.0, 11.0]) == 1.0


def _write_crossing(path: Path) -> None:
    """Two streams of walkers crossing at right angles, sampled every 0.4 s for 30 s."""
    rows = ["t,id,x,y"]
    for k in range(6):
        for i in range(40):
            t = round(0.4 * (i + 5 * k), 1)
            rows.append(f"{t},a{k},{-8 + 1.2 * 0.4 * i:.3f},{0.3 * (k % 2):.3f}")
            rows.append(f"{t},b{k},{0.3 * (k % 2) + 0.05:.3f},{-8 + 1.1 * 0.4 * i:.3f}")
    path.write_text("\n".join(rows) + "\n")


def test_card_end_to_end_from_the_command_line(tmp_path: Path) -> None:
    rec = tmp_path / "crossing.csv"
    _write_crossing(rec)
    assert main(["crowd-card", str(rec), "--out", str(tmp_path / "card")]) == 0
    out = tmp_path / "card"
    for f in ("card.md", "card.json", "speed.png", "nearest_neighbour.png", "rimea4.png", "rimea6.png"):
        assert (out / f).is_file(), f
    c = json.loads((out / "card.json").read_text())
    for model in ("proxemic", "straight_line"):
        for key in ("ade_m", "fde_m", "time_error_s", "close_encounters_per_person"):
            assert math.isfinite(c["closed_loop"][model][key]), (model, key)
    assert math.isfinite(c["closed_loop"]["recorded"]["close_encounters_per_person"])
    assert c["closed_loop"]["people"] == 12
    for model in ("proxemic", "constant_velocity"):
        assert math.isfinite(c["open_loop"][model]["ade_m"])
    assert c["rimea"]["test1"]["pass"] and c["rimea"]["test6"]["pass"]
    assert "| proxemic |" in (out / "card.md").read_text()


def test_several_recordings_get_one_folder_each(tmp_path: Path) -> None:
    for name in ("one", "two"):
        _write_crossing(tmp_path / f"{name}.csv")
    assert main(["crowd-card", str(tmp_path / "one.csv"), str(tmp_path / "two.csv"), "--out", str(tmp_path / "o")]) == 0
    assert (tmp_path / "o" / "one" / "card.json").is_file() and (tmp_path / "o" / "two" / "card.md").is_file()


def test_a_bad_recording_names_file_line_and_column(tmp_path: Path) -> None:
    bad = tmp_path / "bad.csv"
    bad.write_text("t,id,x,y\n0.0,1,0.0,0.0\n0.4,1,nan,0.0\n")
    with pytest.raises(ScenarioError, match=r"bad\.csv.*line 3, column 7 \(x\)"):
        crowdcard.load(bad)
    with pytest.raises(InputError, match=r"social_force\.strenght"):
        _core.rimea1({"strenght": 1.0})


@needs_data
def test_card_on_a_recorded_crowd_window(tmp_path: Path) -> None:
    """CI's card on a real recording: zara1's first 120 s."""
    assert main(["crowd-card", str(DATA / "zara1.csv"), "--out", str(tmp_path), "--window", "0", "120"]) == 0
    c = json.loads((tmp_path / "card.json").read_text())
    assert c["window_s"] == [0.0, 120.0] and c["closed_loop"]["people"] > 20


@cache
def _card(scene: str) -> dict[str, Any]:
    s = crowdcard.load(DATA / f"{scene}.csv")
    c = crowdcard.card(s, rimea_result={})
    c.pop("_samples")
    return c


def _figures(scene: str) -> dict[str, float]:
    c = _card(scene)
    cl, ol, d = c["closed_loop"], c["open_loop"], c["distributions"]
    return {
        "ade": cl["proxemic"]["ade_m"],
        "ade_line": cl["straight_line"]["ade_m"],
        "ce": cl["proxemic"]["close_encounters_per_person"],
        "ce_line": cl["straight_line"]["close_encounters_per_person"],
        "ce_rec": cl["recorded"]["close_encounters_per_person"],
        "ol": ol["proxemic"]["ade_m"],
        "ol_cv": ol["constant_velocity"]["ade_m"],
        "speed_ratio": d["speed_m_s"]["median_ratio"],
        "nn_ratio": d["nearest_neighbour_m"]["median_ratio"],
    }


def _target(name: str, f: dict[str, float]) -> tuple[bool, str]:
    checks = {
        "closed_loop_ade_below_straight_line": (f["ade"] < f["ade_line"], f"ADE {f['ade']:.3f} vs {f['ade_line']:.3f}"),
        "encounters_at_most_half_the_line": (
            f["ce"] <= 0.5 * f["ce_line"],
            f"{f['ce']:.3f} vs straight line {f['ce_line']:.3f} per person",
        ),
        "encounters_within_2x_recorded": (
            f["ce_rec"] / 2 <= f["ce"] <= 2 * f["ce_rec"],
            f"{f['ce']:.3f} vs recorded {f['ce_rec']:.3f} per person",
        ),
        "open_loop_within_10pct_of_constant_velocity": (
            f["ol"] <= 1.1 * f["ol_cv"],
            f"ADE {f['ol']:.3f} vs constant velocity {f['ol_cv']:.3f}",
        ),
        "speed_median_within_10pct": (abs(f["speed_ratio"] - 1) <= 0.1, f"ratio {f['speed_ratio']:.3f}"),
        "nearest_neighbour_median_within_10pct": (abs(f["nn_ratio"] - 1) <= 0.1, f"ratio {f['nn_ratio']:.3f}"),
    }
    return checks[name]


TARGETS = [
    "closed_loop_ade_below_straight_line",
    "encounters_at_most_half_the_line",
    "encounters_within_2x_recorded",
    "open_loop_within_10pct_of_constant_velocity",
    "speed_median_within_10pct",
    "nearest_neighbour_median_within_10pct",
]

# Measured with the calibrated defaults (the figure each strict xfail states; see
# docs/people-validation.md).
FAILING: dict[tuple[str, str], str] = {
    ("eth", "encounters_at_most_half_the_line"): "eth: 0.469 close encounters per person vs 0.719 for the line",
    ("eth", "encounters_within_2x_recorded"): "eth: 0.469 close encounters per person, the recording 0.000",
    ("eth", "nearest_neighbour_median_within_10pct"): "eth: nearest-neighbour median 1.497 m vs 1.114 (ratio 1.344)",
    ("hotel", "closed_loop_ade_below_straight_line"): "hotel: closed-loop ADE 0.287 m vs the line's 0.284",
}


def _cases() -> list[Any]:
    out = []
    for scene in ("eth", "hotel"):
        for t in TARGETS:
            why = FAILING.get((scene, t))
            marks = [needs_data, pytest.mark.full]
            if why:
                marks.append(pytest.mark.xfail(strict=True, reason=why))
            out.append(pytest.param(scene, t, marks=marks, id=f"{scene}-{t}"))
    return out


@pytest.mark.parametrize(("scene", "target"), _cases())
def test_calibrated_model_on_eth(scene: str, target: str) -> None:
    ok, figure = _target(target, _figures(scene))
    assert ok, f"{scene}: {target}: {figure}"


#: The speed and spacing targets hold for every recording, the UCY ones the model was fitted on
#: too (their figures in docs/people-validation.md's cards).
UCY = ("univ", "zara1", "zara2")
SPACING = ("speed_median_within_10pct", "nearest_neighbour_median_within_10pct")
FAILING_UCY: dict[tuple[str, str], str] = {
    ("univ", "speed_median_within_10pct"): "univ: walking-speed median 0.434 m/s vs 0.504 (ratio 0.861)",
    ("univ", "nearest_neighbour_median_within_10pct"): "univ: nearest-neighbour median 1.013 m vs 0.626 (ratio 1.618)",
    ("zara1", "nearest_neighbour_median_within_10pct"): "zara1: nearest-neighbour median 1.178 m vs 0.903 (ratio "
    "1.305)",
    ("zara2", "speed_median_within_10pct"): "zara2: walking-speed median 0.896 m/s vs 1.000 (ratio 0.895)",
    ("zara2", "nearest_neighbour_median_within_10pct"): "zara2: nearest-neighbour median 1.248 m vs 0.752 (ratio "
    "1.659)",
}


def _ucy_cases() -> list[Any]:
    out = []
    for scene in UCY:
        for t in SPACING:
            marks = [needs_data, pytest.mark.full]
            if why := FAILING_UCY.get((scene, t)):
                marks.append(pytest.mark.xfail(strict=True, reason=why))
            out.append(pytest.param(scene, t, marks=marks, id=f"{scene}-{t}"))
    return out


@pytest.mark.parametrize(("scene", "target"), _ucy_cases())
def test_speed_and_spacing_on_the_fitted_recordings(scene: str, target: str) -> None:
    ok, figure = _target(target, _figures(scene))
    assert ok, f"{scene}: {target}: {figure}"


def test_fit_grid_holds_the_published_values() -> None:
    """Moussaid et al. 2009's values are on the calibration's grid (the fit may keep them)."""
    published = {"strength": 4.5, "gamma": 0.35, "lambda": 2.0, "n": 2.0, "n_prime": 3.0, "tau": 0.5}
    for k, v in published.items():
        assert v in crowdcard.FIT_GRID[k], k
    assert np.all(np.diff(crowdcard.FIT_GRID["strength"]) > 0)
