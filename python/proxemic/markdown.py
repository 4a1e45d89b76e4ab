"""The project's one markdown table writer.

The generated docs (:mod:`proxemic.reference`), ``proxemic eval``'s summaries, the Francis suite's,
the reproductions' and the tuning's tables and :func:`proxemic.viz.format_table` all write with it.
"""

from __future__ import annotations

from collections.abc import Iterable, Sequence


def table(header: Sequence[str], rows: Iterable[Sequence[str]]) -> str:
    """A markdown table of `header` and `rows` (cells written as given), without a final newline."""
    lines = ["| " + " | ".join(header) + " |", "| " + " | ".join("---" for _ in header) + " |"]
    lines += ["| " + " | ".join(row) + " |" for row in rows]
    return "\n".join(lines)
