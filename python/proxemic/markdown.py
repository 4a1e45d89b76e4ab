"""The project's one markdown table writer, and its one writer of generated blocks in docs pages.

The generated docs (:mod:`proxemic.reference`), ``proxemic eval``'s summaries, the Francis suite's,
the reproductions' and the tuning's tables and :func:`proxemic.viz.format_table` all write with
:func:`table`. Every generator that fills a marked block of a docs page (the reference, the crowd
card, the CrowdNav table, the baselines' tables) replaces it with :func:`replace_block`.
"""

from __future__ import annotations

from collections.abc import Iterable, Sequence
from pathlib import Path

from proxemic.errors import input_error


def table(header: Sequence[str], rows: Iterable[Sequence[str]]) -> str:
    """A markdown table of `header` and `rows` (cells written as given), without a final newline."""
    lines = ["| " + " | ".join(header) + " |", "| " + " | ".join("---" for _ in header) + " |"]
    lines += ["| " + " | ".join(row) + " |" for row in rows]
    return "\n".join(lines)


def replace_block(text: str, begin: str, end: str, block: str, *, source: str) -> str:
    """`text` with what lies between the marker lines `begin` and `end` replaced by `block`.

    The result is the text before `begin`, `begin` and a newline, `block` (which ends with its own
    newline), then `end` and the text after it.

    Raises:
        InputError: `text` (read from `source`, named in the message) has no `begin` marker
            followed by an `end` marker.
    """
    head, found, rest = text.partition(begin)
    if not found or end not in rest:
        raise input_error(source, f"a block between the markers {begin!r} and {end!r}", "no such block")
    return f"{head}{begin}\n{block}{end}{rest.partition(end)[2]}"


def check_block(path: Path, begin: str, end: str) -> None:
    """Raises :func:`replace_block`'s error if the page at `path` has no block to fill.

    Called before a long run that would fill it, so a wrong page fails at once.
    """
    replace_block(path.read_text(encoding="utf-8"), begin, end, "", source=str(path))


def write_block(path: Path, begin: str, end: str, block: str) -> None:
    """Replaces the block between the marker lines `begin` and `end` of the page at `path` by `block`.

    Raises :func:`replace_block`'s error if the page has no such block.
    """
    text = path.read_text(encoding="utf-8")
    path.write_text(replace_block(text, begin, end, block, source=str(path)), encoding="utf-8")
