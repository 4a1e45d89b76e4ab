"""Lists and rules that have one source: a copy that reappears elsewhere fails here.

Each test names the one source and searches the places a copy used to live (or could live).
"""

from __future__ import annotations

import re
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
BINDING = ROOT / "rust" / "proxemic-py" / "src"


def _rust_files(folder: Path) -> list[Path]:
    return sorted(folder.rglob("*.rs"))


def test_the_binding_holds_no_rules_of_the_core():
    """Gain names, time-of-day ranges and the group-match threshold are the core's (binding: none)."""
    copies = []
    patterns = {
        "an elastic-band gain name (EbandGains::NAMES)": r"\"(contraction|repulsion|social)_gain\"",
        "the day's length (scenario::is_time_of_day)": r"86_?400\.0",
        "the group-match threshold (groups::MATCH_THRESHOLD)": r"2\.0\s*/\s*3\.0",
    }
    for path in _rust_files(BINDING):
        text = path.read_text()
        for what, pattern in patterns.items():
            copies += [f"{path.relative_to(ROOT)}: {what}" for _ in re.finditer(pattern, text)]
    assert copies == []


def test_no_error_is_returned_as_data():
    """A serialisation failure raises (the binding's ``to_py``/``to_json_text``), never ``{"error": ...}``."""
    found = [
        str(p.relative_to(ROOT))
        for p in _rust_files(ROOT / "rust")
        if re.search(r"\\\"error\\\"", p.read_text()) and "target" not in p.parts
    ]
    assert found == []


def test_the_zone_distance_is_written_once():
    """Sousa 2022's zone distance (``zone_scale * sqrt(2 q)``, eq. 8's sides by half planes) is the
    core's ``proxemics::zone_distance`` and ``Placed``; the planners, the social map, the binding,
    the reproduction report and the paper tests use it, none writes its own."""
    home = ROOT / "rust" / "proxemic-core" / "src" / "proxemics" / "space.rs"
    oracle = home.with_suffix("") / "tests.rs"  # the tests' independent restatement of eq. 6-8
    rust = {
        "zone_scale * sqrt(2 q)": r"\(2\.0 \* [\w.()]+\)\.max\(0\.0\)\.sqrt\(\)",
        "eq. 8's sides by half planes": r">= 0\.0 \{ [\w.]*front \} else \{ [\w.]*rear \}",
    }
    copies = [
        f"{path.relative_to(ROOT)}: {what}"
        for path in _rust_files(ROOT / "rust")
        if "target" not in path.parts and path not in (home, oracle)
        for what, pattern in rust.items()
        if re.search(pattern, path.read_text())
    ]
    python = r"\bsag\b|\bd_sag\b|np\.where\([^)]*\bfront\b, *\brear\b"
    copies += [
        str(path.relative_to(ROOT))
        for folder in ("python", "tests", "examples")
        for path in sorted((ROOT / folder).rglob("*.py"))
        if path != Path(__file__).resolve() and re.search(python, path.read_text())
    ]
    assert copies == [], copies
    assert all(re.search(p, home.read_text()) for p in rust.values()), "the one definition moved: update this test"


def test_code_cites_the_metrics_page_by_section():
    """``docs/metrics.md`` is generated from the registry and has no numbered items: code cites its
    sections (a family, or a metric's key) by name."""
    pattern = re.compile(
        r"metrics\.md`? items? \d+|items? \d+(-\d+)?( and \d+-\d+)? of\s+(//[/!]\s*)?`docs/metrics\.md"
    )
    found = [
        f"{path.relative_to(ROOT)}: {m.group(0)}"
        for folder in ("rust", "python")
        for path in sorted((ROOT / folder).rglob("*"))
        if path.suffix in (".rs", ".py") and "target" not in path.parts
        for m in pattern.finditer(path.read_text())
    ]
    assert found == [], found


def test_the_elastic_band_defaults_are_written_once():
    """``EbandParams::default`` holds every default; ``from_calderita_gains`` and the scenario's
    gains start from it instead of repeating the values."""
    defaults = ["influence_distance: 1.0", "min_bubble: 0.05", "max_bubble: 0.5", "overlap: 0.7", "max_bubbles: 4096"]
    counts = {d: 0 for d in defaults}
    for path in _rust_files(ROOT / "rust"):
        if "target" in path.parts or path.name == "tests.rs":
            continue
        text = path.read_text()
        for d in defaults:
            counts[d] += text.count(d)
    assert counts == {d: 1 for d in defaults}, counts


def test_the_core_zone_distance_from_python():
    """``_core.zone_distances``: Euclidean for equal 1 m sides, stretched by a wider side, and a
    typed error naming the field for bad input."""
    import numpy as np
    import pytest

    from proxemic import _core
    from proxemic.errors import InputError

    pts = np.array([[3.0, 4.0], [1.0, 0.0], [-1.0, 0.0]])
    np.testing.assert_allclose(_core.zone_distances((0.0, 0.0), 0.0, (1.0, 1.0, 1.0, 1.0), 1.0, pts), [5.0, 1.0, 1.0])
    # A front sigma of 2 m halves the zone distance ahead (heading +x), not behind.
    np.testing.assert_allclose(_core.zone_distances((0.0, 0.0), 0.0, (2.0, 1.0, 1.0, 1.0), 1.0, pts)[1:], [0.5, 1.0])
    with pytest.raises(InputError, match="points"):
        _core.zone_distances((0.0, 0.0), 0.0, (1.0, 1.0, 1.0, 1.0), 1.0, np.zeros((3, 3)))
    with pytest.raises(InputError, match="rear"):
        _core.zone_distances((0.0, 0.0), 0.0, (1.0, float("nan"), 1.0, 1.0), 1.0, pts)
    with pytest.raises(InputError, match=r"points\[1\]"):
        _core.zone_distances((0.0, 0.0), 0.0, (1.0, 1.0, 1.0, 1.0), 1.0, np.array([[0.0, 0.0], [np.inf, 0.0]]))
