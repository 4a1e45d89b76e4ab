"""docs/learned.md's generated block has what ``python -m proxemic.baselines`` writes.

Cheap checks (no rerun of the episodes): the block lists every planner the generator runs in every
scene set's table under the generator's header, every Francis archetype with a column per
planner, and a headline that agrees with the tables.
"""

from __future__ import annotations

import re
from pathlib import Path

import pytest

from proxemic import _core, baselines, francis2023, markdown, splits
from proxemic.errors import InputError

ROOT = Path(__file__).resolve().parents[1]


def _block() -> str:
    docs = (ROOT / "docs" / "learned.md").read_text(encoding="utf-8")
    assert baselines.DOCS_BEGIN in docs and baselines.DOCS_END in docs
    return docs.partition(baselines.DOCS_BEGIN)[2].partition(baselines.DOCS_END)[0]


def _counts(block: str) -> tuple[int, int]:
    m = re.search(r"--episodes (\d+) --francis-episodes (\d+)", block)
    assert m, "the block does not say what was run"
    return int(m[1]), int(m[2])


def test_generator_runs_every_built_in_planner() -> None:
    """The generator's planners are the core's, learned first."""
    assert baselines.PLANNERS[0] == "learned"
    assert sorted(baselines.PLANNERS) == sorted(_core.PLANNERS)


def test_docs_block_lists_every_planner_set_and_archetype() -> None:
    block = _block()
    episodes, francis_episodes = _counts(block)
    head = markdown.table(baselines.table_header(), []).splitlines()
    tables = block.split("\n### ")[1:]
    assert len(tables) == len(baselines.SETS) + 1
    for s, table in zip(baselines.SETS, tables, strict=False):
        assert table.startswith(s.title(episodes)), s.key
        lines = table.splitlines()
        assert "\n".join(head) in table, s.key
        rows = [line for line in lines if line.startswith("| ") and line not in head]
        assert [r.split(" | ")[0].removeprefix("| ") for r in rows] == list(baselines.PLANNERS), s.key
        assert all(r.split(" | ")[1] == str(episodes) for r in rows), s.key
    francis = tables[-1]
    f_head = markdown.table(baselines.francis_header(), []).splitlines()
    assert "\n".join(f_head) in francis
    rows = [line for line in francis.splitlines() if line.startswith("| ") and line not in f_head]
    assert [r.split(" | ")[0].removeprefix("| ") for r in rows] == list(francis2023.ARCHETYPES)
    assert all(r.count(" coll.)") == len(baselines.PLANNERS) for r in rows)
    assert f"{len(francis2023.ARCHETYPES)} archetypes" in francis
    first = splits.TEST_EPISODE_SEEDS[0]
    assert f"scene seeds {first}-{first + francis_episodes - 1} each" in francis


def test_docs_headline_agrees_with_the_tables() -> None:
    """Learned's success rate in each headline line is the one of its table row."""
    block = _block()
    tables = block.split("\n### ")[1:]
    for s, table in zip(baselines.SETS, tables, strict=False):
        line = next(x for x in block.splitlines() if x.startswith(f"- {s.key}: learned "))
        said = line.removeprefix(f"- {s.key}: learned ").split(" success")[0]
        row = next(x for x in table.splitlines() if x.startswith("| learned | "))
        assert row.split(" | ")[2].split(" [")[0] == said, s.key


def test_bad_counts_and_missing_block_are_refused(tmp_path: Path) -> None:
    with pytest.raises(InputError, match="episodes"):
        baselines.run(0, 1, progress=False)
    with pytest.raises(InputError, match="francis_episodes"):
        baselines.run(1, 61, progress=False)
    page = tmp_path / "page.md"
    page.write_text("no block here\n", encoding="utf-8")
    with pytest.raises(InputError, match=r"page\.md"):
        baselines.write_docs(page, 1, 1)


@pytest.mark.full
def test_docs_block_is_what_a_fresh_run_gives() -> None:
    """The whole block, every planner's row, rerun (about 3 minutes on 2 cores): a planner whose
    episodes changed without the page being regenerated fails here."""
    episodes, francis_episodes = _counts(_block())
    summaries, francis = baselines.run(episodes, francis_episodes, workers=2, progress=False)
    fresh = baselines.block_text(summaries, francis, episodes, francis_episodes)
    assert fresh.strip() == _block().strip()
