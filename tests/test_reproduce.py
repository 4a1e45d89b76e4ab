"""`proxemic reproduce`: published numbers come from the data file, ours from the episodes run."""

from __future__ import annotations

import csv
import json
import math
import typing

import numpy as np
import pytest

from proxemic import _core, reproduce, scenarios
from proxemic.cli import main
from proxemic.errors import InputError, ScenarioError
from proxemic.evaluation import EpisodeResult, run_task
from proxemic.records import EpisodeMetrics
from proxemic.reproduce import (
    PAPERS,
    average_over_paths,
    check_paper,
    crosses_group,
    experiments,
    explain,
    paper,
    published,
    scene_of,
)
from proxemic.social import SocialMap
from proxemic.world import PLANNER_MODES

#: The papers' own planners, in the core once the planner branches are merged.
OWN = {"daza2021": "daza2021", "sousa2022": "sousa2022", "calderita": "calderita"}


def _needs(planner: str) -> None:
    if planner not in _core.PLANNERS:
        pytest.fail(
            f"planner {planner!r} is not in this build ({sorted(_core.PLANNERS)}): it comes with its own branch"
        )


def test_each_paper_runs_its_own_planner_beside_ours():
    data = published()
    for name in PAPERS:
        p = paper(name)
        assert p.planner == OWN[name] == data[name]["planner"]
        assert p.ours == "social"
    assert paper("daza2021").baseline is None  # Table 2 has no A* column
    assert paper("sousa2022").baseline == paper("calderita").baseline == "astar"
    cald = paper("calderita")
    base = next(e for e in cald.experiments if e.role == "baseline")
    own = next(e for e in cald.experiments if e.role == "planner")
    assert cald.planners_of(base) == ["astar"]
    assert cald.planners_of(own) == ["calderita", "social"]
    assert paper("sousa2022").planners_of(experiments("sousa2022")[0]) == [
        "sousa2022",
        "sousa2022_astar",
        "astar",
        "social",
    ]


def test_published_keys_are_our_metric_names():
    """Every published number sits under the metric with the same definition (docs/metrics.md)."""
    ours = set(typing.get_type_hints(EpisodeMetrics))
    for name in PAPERS:
        p = paper(name)
        for m in [*p.metrics, *p.average]:
            assert m in ours, (name, m)
        for exp in p.experiments:
            for m in exp.published:
                assert m in ours or m.startswith("d_min_"), (name, exp.name, m)
    # the papers' definitions: Smooth read as an angle, Psi(Objects) counting idle spaces too
    assert paper("daza2021").metrics == ["l_ratio", "smooth_rad"]
    assert "psi_objects_any" in paper("calderita").metrics
    assert all("psi_objects_active" not in e.published for e in experiments("calderita"))


def test_every_row_of_the_papers_tables_is_an_experiment():
    assert [e.scene for e in experiments("daza2021")] == [*(f"daza2021_path{k}" for k in range(1, 6)), "daza2021_fig15"]
    names = [e.name for e in experiments("calderita")]
    for table, rows in (
        ("Table 1", ("Path 1", "Path 2", "non-social")),
        ("Table 2", ("Path 1", "Path 2", "non-social")),
    ):
        for row in rows:
            assert sum(n.startswith(f"{table}, {row}") for n in names) == 1, (table, row)
    # Table 1's two social paths are two tests, two scenes and two times of day
    t1, t2 = (next(e for e in experiments("calderita") if e.name.startswith(f"Table 1, Path {k}")) for k in (1, 2))
    assert t1.scene != t2.scene and t1.start_time != t2.start_time


def test_unknown_paper_is_a_clear_error(tmp_path, capsys):
    with pytest.raises(InputError, match="paper: expected one of daza2021, sousa2022, calderita, got nobody2020"):
        experiments("nobody2020")
    with pytest.raises(InputError, match="nobody2020"):
        reproduce.reproduce("nobody2020", tmp_path / "x", episodes=1)
    assert not (tmp_path / "x").exists()
    with pytest.raises(SystemExit) as e:
        main(["reproduce", "nobody2020", "--out", str(tmp_path)])
    assert e.value.code == 2
    assert "invalid choice" in capsys.readouterr().err


def _with_scene(monkeypatch, scene: str) -> None:
    data = published()
    data["sousa2022"]["experiment"][1]["scene"] = scene
    monkeypatch.setattr(reproduce, "published", lambda: data)


def test_missing_paper_scene_is_a_typed_error_before_any_episode(monkeypatch, tmp_path):
    _with_scene(monkeypatch, "sousa2022_fig99")
    with pytest.raises(ScenarioError) as e:
        reproduce.reproduce("sousa2022", tmp_path / "out", episodes=1)
    err = e.value
    assert err.field == "sousa2022.experiment[1].scene"
    assert err.found == "sousa2022_fig99"
    assert "bundled" in (err.expected or "")
    assert "no sousa2022_fig99.toml in the package" in str(err) and "Figure 17" in str(err)
    assert not (tmp_path / "out").exists()  # nothing ran, nothing written


def test_unknown_planner_in_the_data_is_a_typed_error(monkeypatch):
    data = published()
    data["daza2021"]["planner"] = "daza1999"
    monkeypatch.setattr(reproduce, "published", lambda: data)
    with pytest.raises(
        ScenarioError, match=r"daza2021.planner: expected one of the built-in planners .* found 'daza1999'"
    ):
        check_paper(paper("daza2021"))


def test_average_says_over_what_it_is_taken():
    assert average_over_paths([0.2, None, 0.4, math.nan, 0.6]) == (pytest.approx(0.4), 3)
    assert math.isnan(average_over_paths([None, None])[0])


def _fake(**record: float | str) -> EpisodeResult:
    base: dict[str, float | str] = {"seed": 0, "outcome": "success", "steps": 99}
    return EpisodeResult({**base, **record})


def test_explanations_are_computed_from_the_run():
    exp = reproduce.Experiment("row", "calderita_exp1", {"d_t": 14.03, "tau": 101.79})
    runs = [_fake(d_t=10.0, tau=20.0), _fake(d_t=12.0, tau=20.0, seed=1, outcome="collision")]
    text = explain("tau", 101.79, exp, runs)
    # our speed 22 m / 40 s, the paper's 14.03 m / 101.79 s; our 11 m at the paper's speed
    assert "0.55 m/s" in text and "0.14 m/s" in text and f"{11.0 * 101.79 / 14.03:.1f} s" in text
    assert "1 of 2 episodes failed (seed 1: collision)" in text
    lr = explain("l_ratio", 0.86, exp, [_fake(d_t=11.0, astar_length=10.0, tau=1.0)])
    assert "D_A* is 10.00 m" in lr and "1.16 times" in lr and "1.10 times" in lr
    sm = explain("smooth_rad", 0.08, exp, [_fake(d_t=1.0, tau=1.0, smooth_k=2, smooth_rad=0.5)])
    assert "k = 2.0" in sm and f"{math.degrees(0.5):.1f} deg" in sm and "4.6 deg" in sm


def _objects_layer_at(scene: str | _core.Scenario, x: float, y: float) -> float:
    layers = SocialMap(scene, seed=0).layers
    ox, oy, res = layers["grid"]
    return float(layers["objects"][int((y - oy) / res), int((x - ox) / res)])


def test_calderita_table1_tests_differ_in_which_activities_are_on():
    """Table 1's Path 1 and Path 2 differ in the clock and so in which activities are on (they once came
    out identical: one scene, only the clock moved)."""
    t1, t2 = experiments("calderita")[:2]
    assert (t1.start_time, t2.start_time) == ("09:05", "10:05")
    _, d1 = scenarios.load(scene_of(t1))
    _, d2 = scenarios.load(scene_of(t2))
    assert math.isclose(d1["scene"]["start_time"], 9 * 3600 + 5 * 60)
    assert math.isclose(d2["scene"]["start_time"], 10 * 3600 + 5 * 60)
    # the TV's space: idle (R = 1.5) in test 1, its therapy on (R = 3.5) in test 2; the table's on in both
    tv, table = (7.5, 8.9), (8.0, 7.0)
    assert _objects_layer_at(scene_of(t1), *tv) == pytest.approx(1.5)
    assert _objects_layer_at(scene_of(t2), *tv) == pytest.approx(3.5)
    assert _objects_layer_at(scene_of(t1), *table) == _objects_layer_at(scene_of(t2), *table) == pytest.approx(3.5)
    # and test 1 has nobody watching the idle TV
    watcher = np.array(next(p["pose"][:2] for p in d2["persons"] if p["name"] == "senior_2"))
    moved = np.array(next(p["pose"][:2] for p in d1["persons"] if p["name"] == "senior_2"))
    assert np.linalg.norm(watcher - moved) > 2.0


@pytest.mark.parametrize("planner", ["calderita", "social"])
def test_calderita_table1_rows_differ_in_the_metrics(planner):
    _needs(planner)
    t1, t2 = experiments("calderita")[:2]
    r1 = run_task((scene_of(t1), planner, 0)).record
    r2 = run_task((scene_of(t2), planner, 0)).record
    keys = ("d_t", "tau", "chc", "psi_personal", "psi_objects_any", "d_min_senior_1", "d_min_senior_2")
    assert [r1[k] for k in keys] != [r2[k] for k in keys]
    # test 1 may use the idle TV's space (the paper's Path 1 does); test 2 must keep out of it while on
    assert (r2["psi_object_active_tv"] or 0.0) == 0.0


def test_daza2021_report_puts_published_beside_measured(tmp_path):
    _needs("daza2021")
    out = tmp_path / "daza"
    report = reproduce.reproduce("daza2021", out, episodes=1, seed=3)
    assert (out / "report.md").read_text() == report
    with (out / "episodes.csv").open() as fh:
        rows = list(csv.DictReader(fh))
    assert len(rows) == 12  # (5 paths + Fig. 15) x (daza2021, social)
    for k, exp in enumerate(experiments("daza2021"), start=1):
        assert (out / f"{k}_{exp.scene}.png").stat().st_size > 0
        own = next(r for r in rows if r["experiment"] == exp.name and r["planner"] == "daza2021")
        assert own["seed"] == "3"
        if not exp.published:
            continue
        ours = f"{float(own['smooth_rad']):.2f}" if own["smooth_rad"] else "n/a"
        assert any(
            line.startswith(f"| smooth_rad | {exp.published['smooth_rad']:g} | {ours}") for line in report.splitlines()
        ), exp.name
        assert float(own["smooth_rad"]) ** 2 == pytest.approx(float(own["smooth_rad2"]))
    assert "## Average over the 5 experiments" in report
    paths = {exp.name for exp in experiments("daza2021") if exp.published}
    defined = sum(bool(r["l_ratio"]) for r in rows if r["planner"] == "daza2021" and r["experiment"] in paths)
    assert f"(over {defined} of 5 paths)" in report
    assert "## Why ours differ" in report


def test_sousa2022_reports_the_figures_claim_from_the_run(tmp_path):
    _needs("sousa2022")
    report = reproduce.reproduce("sousa2022", tmp_path / "s", episodes=1, seed=0)
    with (tmp_path / "s" / "episodes.csv").open() as fh:
        rows = list(csv.DictReader(fh))
    sections = {sec.split(" (`")[0]: sec for sec in report.split("\n## ")[1:]}
    for exp in experiments("sousa2022"):
        section = sections[exp.name]
        for planner in ("sousa2022", "astar", "social"):
            row = next(r for r in rows if r["experiment"] == exp.name and r["planner"] == planner)
            rec = {
                "ospace_pct": float(row["ospace_pct"] or 0.0),
                "interaction_crossings_person_person": int(row["interaction_crossings_person_person"]),
            }
            verdict = "crosses" if crosses_group(rec) else "does not cross"
            line = next(x for x in section.splitlines() if x.startswith(f"- `{planner}` crosses a group's space in"))
            assert line.endswith(f"**{verdict}**."), line
    assert "Groups the robot perceives (Delaunay, at the start)" in report
    # Sect. 4.5's claim in personal-space terms, on each figure: plain A* enters a group's and a
    # single person's personal space, Sousa's path enters neither.
    for exp in experiments("sousa2022"):
        lines = sections[exp.name].splitlines()
        verdict = {
            p: next(x for x in lines if x.startswith(f"- `{p}` enters the personal space"))
            for p in ("astar", "sousa2022")
        }
        assert verdict["astar"].endswith("**crosses both kinds**."), verdict["astar"]
        assert verdict["sousa2022"].endswith("**respects both kinds**."), verdict["sousa2022"]


def test_published_data_cites_its_sources():
    data = published()
    for name in PAPERS:
        assert data[name]["source"]
        assert json.dumps(data[name]["experiment"])


#: The scenes `proxemic reproduce` runs: standing people, so only the robot's start jitter (and Daza
#: Path 1's and Path 5's walkers' speeds and phases) can tell two seeds apart.
VARIED = [
    *(f"daza2021_path{k}" for k in range(1, 6)),
    "daza2021_fig15",
    "sousa2022_fig16",
    "sousa2022_fig17",
    "calderita_exp1_test1",
    "calderita_exp1",
    "calderita_exp2_path1",
    "calderita_exp2_path2",
]


@pytest.mark.parametrize("scene", VARIED)
def test_seeds_give_different_episodes(scene):
    """Daza's Paths 2-4 and Calderita's scenes once gave the same episode for every seed (a
    confidence interval over copies)."""
    a, b = (run_task((scene, "astar", s), keep=True) for s in (0, 1))
    assert a.robot is not None and b.robot is not None
    assert not np.allclose(a.robot[0, :2], b.robot[0, :2])  # the start jitter moved the robot
    assert a.record["path_length"] != b.record["path_length"]


def test_reproduce_table_prints_published_ours_ratio_and_mechanism(tmp_path):
    _needs("daza2021")
    report = reproduce.reproduce("daza2021", tmp_path / "d", episodes=2, seed=0)
    table = report.split("## Reproduce table")[1].split("\n## ")[0]
    assert "| experiment | metric | published | ours [95% CI] | ratio | mechanism |" in table
    rows = [line.split(" | ") for line in table.splitlines() if line.startswith("| Path ") or line.startswith("| Fig")]
    assert len(rows) == 5 * 2 + 1  # two published metrics per path, Fig. 15's mechanism alone
    with (tmp_path / "d" / "episodes.csv").open() as fh:
        own = [r for r in csv.DictReader(fh) if r["planner"] == "daza2021"]
    for exp in experiments("daza2021"):
        recs = [r for r in own if r["experiment"] == exp.name]
        results = [
            EpisodeResult(
                {
                    **r,
                    "l_ratio": float(r["l_ratio"]) if r["l_ratio"] else None,
                    "smooth_rad": float(r["smooth_rad"]) if r["smooth_rad"] else None,
                }
            )
            for r in recs
        ]
        # The mechanism needs each episode's planner modes, which the CSV does not hold: the same
        # episodes are run again, kept.
        kept = [run_task((exp.scene, "daza2021", int(r["seed"])), keep=True) for r in recs]
        held = (
            sum(reproduce.MECHANISMS[exp.mechanism].happened(r, exp.scene) for r in kept)
            if exp.scene != "daza2021_fig15"
            else None
        )
        for row in (r for r in rows if r[0].lstrip("| ").startswith(exp.name)):
            if held is not None:
                assert row[-1].rstrip(" |").endswith(f"({held}/2)"), row
            if row[1] == "l_ratio":
                values = [v.record["l_ratio"] for v in results if v.record["l_ratio"] is not None]
                if len(values) == 2:
                    mean = sum(values) / 2
                    assert row[3].startswith(f"{mean:.2f} ["), row
                    assert row[4] == f"{mean / exp.published['l_ratio']:.2f}", row


def test_daza_mechanisms_read_the_planner_modes_of_the_kept_episode():
    """A detour counts only where Social Momentum ran (Sect. 5.3-5.6), Fig. 15 only where ORCA did."""
    detour = reproduce.MECHANISMS["daza_detour"].happened
    bent = {"l_ratio": 0.9, "smooth_rad": 0.3}
    assert detour(EpisodeResult({**bent}, modes=["follow_path", "social_momentum"]), "daza2021_path1")
    assert not detour(EpisodeResult({**bent}, modes=["follow_path", "wait"]), "daza2021_path1")
    assert not detour(EpisodeResult({**bent}), "daza2021_path1")  # modes not kept: not shown
    kept = run_task(("daza2021_path1", "daza2021", 0), keep=True)
    assert kept.robot is not None and kept.modes is not None
    assert len(kept.modes) == len(kept.robot) - 1  # one mode per control step
    assert set(kept.modes) <= set(PLANNER_MODES) and "social_momentum" in kept.modes
    team = run_task(("daza2021_fig15", "daza2021", 0), keep=True)
    assert all(r.modes and set(r.modes) <= set(PLANNER_MODES) for r in [team, *team.others])
    orca_team = reproduce.MECHANISMS["daza_orca_team"].happened
    assert orca_team(team, "daza2021_fig15")
    for r in [team, *team.others]:
        r.modes = ["follow_path"]
    assert not orca_team(team, "daza2021_fig15")


def test_unknown_mechanism_is_a_typed_error():
    exp = reproduce.Experiment("row", "daza2021_path1", {}, mechanism="teleport")
    with pytest.raises(ScenarioError, match=r"mechanism: expected one of .* found 'teleport'"):
        reproduce.mechanism_cell(exp, [_fake()], "daza2021_path1")


#: Test-split seeds for the mechanism claims (python/proxemic/splits.py).
TEST_SEEDS = (1000, 1001, 1002)


@pytest.fixture(scope="module")
def daza_runs() -> dict[str, list[EpisodeResult]]:
    return {
        exp.scene: [run_task((exp.scene, "daza2021", s), keep=True) for s in TEST_SEEDS]
        for exp in experiments("daza2021")
    }


def _detours(runs: list[EpisodeResult], scene: str) -> list[bool]:
    return [reproduce.MECHANISMS["daza_detour"].happened(r, scene) for r in runs]


@pytest.mark.parametrize(
    "k",
    [
        1,
        pytest.param(
            2,
            marks=pytest.mark.xfail(
                strict=True,
                reason="measured on seeds 1000-1002: seed 1002 keeps to the A* line (L_ratio 1.004, "
                "Smooth 0.0; seeds 1000 and 1001 detour, 0.973 and 0.995). The robot slowed beside the "
                "people (0.18 m/s) and stood still for a step 0.66 m from one of them, centre to centre, "
                "and the people, who make room for a robot standing still within 0.55 m of them, shifted "
                "up to 0.48 m aside: the way was clear without a detour",
            ),
        ),
        3,
        4,
        5,
    ],
)
def test_daza_robot_detours_where_the_papers_robot_does(daza_runs, k):
    """Sect. 5.3-5.6: on every path the A* path crosses the people's zones and Social Momentum bends it
    (Table 2: L_ratio 0.80-0.86, Smooth 0.08-0.77 rad): L_ratio < 1 and Smooth > 0, reaching the goal."""
    scene = f"daza2021_path{k}"
    assert all(_detours(daza_runs[scene], scene)), [
        (r.record["outcome"], r.record["l_ratio"], r.record["smooth_rad"]) for r in daza_runs[scene]
    ]


def test_daza_path1_robot_does_the_avoiding(daza_runs):
    """Sect. 5.3: the scripted person walks on (reaction 'ignore'), the robot bends around it."""
    _, data = scenarios.load("daza2021_path1")
    assert data["persons"][0]["reaction"] == "ignore"
    for r in daza_runs["daza2021_path1"]:
        assert r.record["outcome"] == "success"
        assert reproduce.MECHANISMS["daza_detour"].happened(r, "daza2021_path1")
        # the person keeps to its line y = 5: the robot's detour is the robot's doing
        assert r.people is not None and float(np.abs(r.people[:, 0, 1] - 5.0).max()) < 0.01


@pytest.mark.xfail(
    strict=True,
    reason="measured on seeds 1000-1002: mean Smooth Path 1 1.64 rad (0.51, 2.38, 2.02), Path 2 0.379, "
    "Path 3 0.376, Path 4 0.57, Path 5 0.75: Path 1's is the greatest, not the least, and Path 3's the "
    "least, not the greatest. Measured cause for Path 1: on seeds 1001 and 1002 the robot leaves the A* "
    "path at 2.37 and 2.01 rad, pushed backwards off it (0.13 and 0.08 m in one control step) by the "
    "walker, who ignores the robot and walks into it while it waits. Path 3's detour past the group is "
    "a near-straight one (L_ratio 0.98-1.00)",
)
def test_daza_paired_directions_are_the_papers(daza_runs):
    """Sect. 5.6: the best Smooth is Path 1's (0.08 rad), the highest Path 3's (0.77 rad)."""
    smooth = {s: float(np.mean([r.record["smooth_rad"] for r in rs])) for s, rs in daza_runs.items() if "path" in s}
    assert min(smooth, key=smooth.__getitem__) == "daza2021_path1", smooth
    assert max(smooth, key=smooth.__getitem__) == "daza2021_path3", smooth


def test_daza_fig15_robots_meet_without_colliding(daza_runs):
    """Sect. 5.2, Fig. 15: four robots move to a point in common with ORCA, without colliding."""
    assert all(
        reproduce.MECHANISMS["daza_orca_team"].happened(r, "daza2021_fig15") for r in daza_runs["daza2021_fig15"]
    )
    assert all(len(r.others) == 3 for r in daza_runs["daza2021_fig15"])


@pytest.mark.parametrize(
    "scene",
    [
        pytest.param(
            "sousa2022_fig16",
            marks=pytest.mark.xfail(
                strict=True,
                reason="measured on seeds 1000-1004, the people standing still: `sousa2022_astar` keeps "
                "out of every personal space on 3 of 5 (zone distance 1.10 m); on seeds 1002 and 1004 it "
                "comes within 0.68 and 0.67 m of group 1 (plain A* 0.78-0.91 m on the five). Measured "
                "cause: Social Momentum's way round group 1 makes no progress within the monitor's window, "
                "and the recovery (ORCA among everyone keeping out of the intimate zones only, as every "
                "planner but `social` recovers) passes the group; on tuning seeds 0-9 it kept out on 6 of 10",
            ),
        ),
        "sousa2022_fig17",
    ],
)
def test_sousa_gaussian_social_momentum_keeps_plain_astar_out_of_personal_spaces(scene):
    """Sect. 4.5, Figs. 16-17: the A* path (blue) crosses personal spaces; "combining the proposed
    approach with social momentum (red line)" respects them. `sousa2022_astar` is that pairing:
    Social Momentum on the Gaussians bending the plain A* path (our `sousa2022` plans on the
    Gaussians' cost map instead). Test-split seeds; plain A* alone must enter one for the claim
    to say something."""
    _needs("sousa2022_astar")
    respects = reproduce.MECHANISMS["sousa_respects_spaces"].happened
    for seed in TEST_SEEDS:
        plain = run_task((scene, "astar", seed), keep=True)
        bent = run_task((scene, "sousa2022_astar", seed), keep=True)
        assert not respects(plain, scene), seed
        assert respects(bent, scene), (seed, bent.record["outcome"], bent.record["dist_person_min"])
