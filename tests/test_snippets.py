"""Every ```python and ```bash snippet of the README and the docs pages runs as written.

Each page's snippets run in order, each in its own process, from a fresh temporary directory
outside the repository (standing for a user's working directory: the package is the built one
installed in the virtual env, whose ``bin`` is first on ``PATH``; ``.venv`` in that directory
links to it, as in a clone after ``make demo``). A fenced block with a title (```python
title="my_policy.py"```, ```toml title="corridor.toml"```) is a file the page asks the reader to
save: it is written there, not run, before the next snippets.

The comment line right above a fence says how it runs:

- ``<!-- snippet: full (...) -->``: minutes of episodes, run by ``make test-full``;
- ``<!-- snippet: not run (...) -->``: not runnable here, with the reason (kept to a few, listed
  by ``NOT_RUN_AT_MOST``).
"""

from __future__ import annotations

import os
import re
import subprocess
import sys
from dataclasses import dataclass
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parent.parent
PAGES = [ROOT / "README.md", *sorted((ROOT / "docs").glob("*.md"))]
RUN_LANGS = {"python", "bash"}
#: The snippets marked "not run": the README's and Getting started's `make` targets, and the crowd
#: cards of the recordings (not bundled).
NOT_RUN_AT_MOST = 4  # two of them need the ETH/UCY recordings, which are not bundled
FENCE = re.compile(
    r"^(?:<!-- snippet: (?P<mark>[^>]*?) -->\n)?```(?P<lang>\w*)(?P<attrs>[^\n]*)\n(?P<code>.*?)^```$", re.M | re.S
)


@dataclass(frozen=True)
class Snippet:
    """One fenced block of a page."""

    page: str
    line: int
    lang: str
    code: str
    title: str | None  # a file to save, not a snippet to run
    mark: str  # "", "full" or "not run"


def snippets(page: Path) -> list[Snippet]:
    text = page.read_text()
    out = []
    for m in FENCE.finditer(text):
        title = re.search(r'title="([^"]+)"', m["attrs"])
        mark = (m["mark"] or "").split(" (")[0]
        assert mark in {"", "full", "not run"}, f"{page.name}: unknown snippet mark {m['mark']!r}"
        line = text.count("\n", 0, m.start("code"))
        rel = str(page.relative_to(ROOT))
        out.append(Snippet(rel, line, m["lang"], m["code"], title[1] if title else None, mark))
    return out


ALL = {str(p.relative_to(ROOT)): snippets(p) for p in PAGES}


def _runnable(s: Snippet) -> bool:
    return s.title is None and s.lang in RUN_LANGS and s.mark != "not run"


def run_page(page: str, tmp_path: Path, full: bool) -> int:
    """Runs a page's snippets in order in ``tmp_path``; returns how many ran."""
    venv_bin = Path(sys.executable).parent
    (tmp_path / ".venv").symlink_to(Path(sys.prefix), target_is_directory=True)
    env = {k: v for k, v in os.environ.items() if k not in {"PYTHONPATH", "VIRTUAL_ENV"}}
    env["PATH"] = f"{venv_bin}{os.pathsep}{env.get('PATH', '')}"
    env.setdefault("MUJOCO_GL", "egl")
    ran = 0
    for s in ALL[page]:
        if s.title is not None:
            if s.lang == "python":
                compile(s.code, f"{s.page}:{s.line + 1}", "exec")
            (tmp_path / s.title).write_text(s.code)
            continue
        if not _runnable(s) or (s.mark == "full" and not full):
            continue
        cmd = [sys.executable, "-c", s.code] if s.lang == "python" else ["bash", "-euo", "pipefail", "-c", s.code]
        proc = subprocess.run(cmd, cwd=tmp_path, env=env, capture_output=True, text=True, timeout=3600)
        assert proc.returncode == 0, (
            f"{s.page}:{s.line + 1}: the {s.lang} snippet failed (exit {proc.returncode})\n"
            f"{s.code}\n--- stdout\n{proc.stdout[-3000:]}\n--- stderr\n{proc.stderr[-3000:]}"
        )
        ran += 1
    return ran


def test_every_page_is_scanned_and_few_snippets_are_not_run():
    runnable = [s for ss in ALL.values() for s in ss if s.lang in RUN_LANGS and s.title is None]
    not_run = [f"{s.page}:{s.line}" for s in runnable if s.mark == "not run"]
    assert len(not_run) <= NOT_RUN_AT_MOST, f"snippets marked 'not run': {not_run}"
    assert sum(s.mark == "" for s in runnable) >= 10, "the README and the docs have runnable snippets"
    assert ALL["README.md"][0].code.startswith("make demo"), "the README's two commands come first"
    assert any("make test" in s.code for s in ALL["README.md"]), "the README says how to run the tests"


@pytest.mark.parametrize("page", [p for p, ss in ALL.items() if any(_runnable(s) and s.mark == "" for s in ss)])
def test_page_snippets_run_from_outside_the_repository(page, tmp_path):
    assert run_page(page, tmp_path, full=False) > 0


@pytest.mark.full
@pytest.mark.parametrize("page", [p for p, ss in ALL.items() if any(_runnable(s) and s.mark == "full" for s in ss)])
def test_page_snippets_run_including_the_long_ones(page, tmp_path):
    assert run_page(page, tmp_path, full=True) > 0


def test_readme_episode_prints_an_outcome(tmp_path):
    """The README's episode ends with an outcome and a path length, printed."""
    block = next(s for s in ALL["README.md"] if s.lang == "python")
    proc = subprocess.run([sys.executable, "-c", block.code], cwd=tmp_path, capture_output=True, text=True, check=True)
    outcome, length = proc.stdout.split()
    assert outcome in {"success", "collision", "timeout"}
    assert float(length) > 0.0


def test_submodules_are_reachable_after_a_plain_import():
    """The docs write ``proxemic.env.ProxemicEnv`` and ``proxemic.viz.video.record_episode``."""
    code = (
        "import proxemic\n"
        "assert proxemic.env.ProxemicEnv is proxemic.ProxemicEnv\n"
        "assert callable(proxemic.viz.video.record_episode)\n"
        "assert callable(proxemic.policy.joint_policy) and proxemic.policy.FlatObservation\n"
        "try:\n    proxemic.no_such_module\nexcept AttributeError as e:\n    print(e)\n"
    )
    proc = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, cwd="/")
    assert proc.returncode == 0, proc.stderr
    assert "has no attribute 'no_such_module'" in proc.stdout


def test_long_snippets_parse_in_the_fast_run():
    """Every ``proxemic`` command of a snippet marked full parses (its run is in make test-full)."""
    import shlex

    from proxemic.cli import build_parser

    commands = [
        line.split("#")[0]
        for ss in ALL.values()
        for s in ss
        if _runnable(s) and s.mark == "full"
        for line in s.code.splitlines()
        if line.startswith("proxemic ")
    ]
    assert len(commands) >= 5
    for command in commands:
        args = build_parser().parse_args(shlex.split(command)[1:])
        assert callable(args.func), command
