"""Every list has one source: these fail when a copy of one reappears beside it.

- metrics: what the evaluation summarises, plots, heads and compares is fields of the core's metric
  registry; the evaluation package holds no list of metric keys;
- planners: the core's ``PlannerKind`` docs are the one description of each planner (docs table,
  CLI help), and no Python source nor other docs page repeats one;
- colours: one palette (``proxemic.palette``) for the top-down view, the plots and MuJoCo;
- markdown tables: one writer (``proxemic.markdown.table``);
- defaults: the frame size and the tuner's gain ranges are written once;
- the full suites: every file with a test marked ``full`` is on ``make test-full``'s line.
"""

from __future__ import annotations

import ast
import re
from pathlib import Path

import numpy as np

from proxemic import _core, markdown, palette, scenarios
from proxemic.cli import build_parser
from proxemic.evaluation import HEADLINE, METRIC_GROUPS, METRICS, VERDICT_METRICS
from proxemic.evaluation.metrics import EXTRAS, MEAN_METRICS, PANEL_TITLES, RATE_METRICS

ROOT = Path(__file__).resolve().parents[1]
PACKAGE = ROOT / "python" / "proxemic"


def _sources(folder: Path = PACKAGE) -> dict[Path, str]:
    return {p: p.read_text() for p in sorted(folder.rglob("*.py"))}


# -- metrics ------------------------------------------------------------------------------------


def test_the_evaluation_shows_what_the_registry_says():
    registry = _core.metric_registry()
    summarised = [m for m in registry if m["summary"] is not None]
    extras = [e["key"] for e in EXTRAS]
    assert list(RATE_METRICS) == [m["key"] for m in summarised if m["summary"] == "rate"]
    assert list(MEAN_METRICS) == [m["key"] for m in summarised if m["summary"] == "mean"] + extras
    assert list(HEADLINE) == [m["key"] for m in [*summarised, *EXTRAS] if m["headline"]]
    assert list(VERDICT_METRICS) == [(m["key"], m["verdict"]) for m in summarised if m["verdict"]]
    assert set(PANEL_TITLES) == {m["panel"] for m in registry if m["panel"]}
    for title, keys in METRIC_GROUPS:
        panel = next(p for p, t in PANEL_TITLES.items() if t == title)
        assert [k for k in keys if k not in extras] == [m["key"] for m in registry if m["panel"] == panel]
    for m in summarised:
        fmt = ".0%" if m["summary"] == "rate" else f".{m['decimals']}f"
        assert METRICS[m["key"]].fmt == fmt and METRICS[m["key"]].label == m["label"]


def test_the_evaluation_package_keeps_no_list_of_metric_keys():
    """A tuple, list, set or dict literal naming two or more registry metrics is a copy of the registry."""
    keys = {m["key"] for m in _core.metric_registry()}
    found = []
    for path, text in _sources(PACKAGE / "evaluation").items():
        for node in ast.walk(ast.parse(text)):
            elts = node.keys if isinstance(node, ast.Dict) else getattr(node, "elts", None)
            if not isinstance(node, ast.Tuple | ast.List | ast.Set | ast.Dict) or elts is None:
                continue
            named = [e.value for e in elts if isinstance(e, ast.Constant) and e.value in keys]
            if len(named) >= 2:
                found.append(f"{path.name}:{node.lineno}: {named}")
    assert not found, "metric lists beside the registry: " + "; ".join(found)


# -- colours ------------------------------------------------------------------------------------


def test_mujoco_draws_objects_and_robots_in_the_palettes_colours():
    from proxemic.sim import build_spec

    _, scenario = scenarios.load("museum")
    model = build_spec(scenario, visual=True).compile()
    kinds = set()
    for obj in scenario["objects"]:
        rgba = model.geom(f"object/{obj['name']}").rgba
        colour = palette.OBJECT_COLORS.get(obj["kind"], palette.DEFAULT_OBJECT_COLOR)
        np.testing.assert_allclose(rgba, palette.rgba(colour), err_msg=obj["kind"])
        kinds.add(obj["kind"])
    assert len(kinds) >= 3
    for i in range(len(scenario["robots"])):
        shell = model.geom(f"robot_{i}/shell").rgba
        np.testing.assert_allclose(shell, palette.rgba(palette.ROBOT_PALETTE[i % len(palette.ROBOT_PALETTE)]))


def test_colours_are_defined_only_in_the_palette():
    """A table of object kinds to colours outside palette.py is a second palette."""
    kinds = set(palette.OBJECT_COLORS)
    found = []
    for path, text in _sources().items():
        if path.name == "palette.py":
            continue
        for node in ast.walk(ast.parse(text)):
            if isinstance(node, ast.Dict):
                named = {k.value for k in node.keys if isinstance(k, ast.Constant)} & kinds
                colours = [v for v in node.values if isinstance(v, ast.Tuple) and len(v.elts) in (3, 4)]
                if len(named) >= 2 and colours:
                    found.append(f"{path.name}:{node.lineno}: a table of object kinds {sorted(named)}")
    assert not found, found


# -- markdown tables ----------------------------------------------------------------------------


#: Modules that still write their tables by hand: the crowd card arrived beside the writer (in the
#: same merge) and is to be moved onto it; nothing may join this list.
NOT_YET_ON_THE_TABLE_WRITER = ("crowdcard.py",)


def test_one_markdown_table_writer():
    pattern = re.compile(r"""["']\s*\|\s*["']\s*\.join|["']\|\s*-{3}|["']\s*\|\s*-{3}""")
    found = [
        f"{path.relative_to(ROOT)}:{text[: m.start()].count(chr(10)) + 1}"
        for path, text in _sources().items()
        if path.name not in ("markdown.py", *NOT_YET_ON_THE_TABLE_WRITER)
        for m in pattern.finditer(text)
    ]
    assert not found, "markdown tables written beside proxemic.markdown.table: " + ", ".join(found)
    assert markdown.table(["a", "b"], [["1", "2"]]) == "| a | b |\n| --- | --- |\n| 1 | 2 |"


# -- defaults -----------------------------------------------------------------------------------


def test_defaults_are_written_once():
    """The frame size and the tuner's default gain ranges appear only where they are defined."""
    from proxemic import tuning
    from proxemic.viz import topdown

    width, height = topdown.FRAME_SIZE
    found = []
    for path, text in _sources().items():
        code = re.sub(r'"""(?:.|\n)*?"""', "", text)  # docstrings may say the value
        if path.name != "topdown.py" and re.search(rf"\b({width}|{height})\b", code):
            found.append(path.name)
    assert not found, f"the frame size written again in {found}"
    parser = build_parser()
    sub = next(a for a in parser._actions if a.dest == "command").choices
    help_text = sub["tune"].format_help()
    for name, (lo, hi) in tuning.DEFAULT_RANGES.items():
        assert f"{name}={lo:g}:{hi:g}" in help_text
    cli = (PACKAGE / "cli.py").read_text()
    assert "contraction_gain=0.1:3" not in cli


# -- tracker numbers ----------------------------------------------------------------------------


def test_no_tracker_numbers_in_the_code():
    """Code, tests, benches and docstrings say what was done in plain words, not which issue asked for
    it (the CHANGELOG may name issues; Rust suites named ``issue_<n>_<symptom>`` are small regressions
    and keep their number in the file name only)."""
    pattern = re.compile(r"\bissues? #?\d+|\bissue_\d+", re.IGNORECASE)
    files = [p for p in sorted(PACKAGE.rglob("*")) if p.suffix in (".py", ".pyi", ".toml")]
    files += [p for d in ("tests", "benches", "examples") for p in sorted((ROOT / d).rglob("*.py"))]
    files += [p for p in sorted((ROOT / "rust").rglob("*.rs")) if "target" not in p.parts]
    files.remove(Path(__file__).resolve())
    found = [f"{p.relative_to(ROOT)}: {m.group(0)}" for p in files for m in pattern.finditer(p.read_text())]
    assert not found, found


def test_rust_suites_are_named_after_behaviours():
    """An integration suite named after a tracker number (``issue_<n>_<symptom>.rs``) is a small
    regression test; a suite of behaviours is named after them."""
    long = [
        f"{p.relative_to(ROOT)}: {len(p.read_text().splitlines())} lines"
        for p in sorted((ROOT / "rust").glob("*/tests/issue_*.rs"))
        if len(p.read_text().splitlines()) > 100
    ]
    assert not long, long


def test_make_test_full_runs_every_full_test():
    """A test marked ``full`` runs only in ``make test-full``: its file must be on that target's line,
    or the mark turns it into a test that never runs."""
    makefile = (ROOT / "Makefile").read_text()
    recipe = makefile.split("\ntest-full:", 1)[1].split("\n\n", 1)[0]
    named = set(re.findall(r"tests/(test_\w+\.py)", recipe))
    mark = "pytest.mark." + "full"  # spelled in two parts so that this file does not match itself
    marked = {p.name for p in sorted((ROOT / "tests").glob("test_*.py")) if mark in p.read_text()}
    assert marked, "no test is marked full: the check reads the wrong files"
    assert marked <= named, f"marked full but not run by make test-full: {sorted(marked - named)}"
