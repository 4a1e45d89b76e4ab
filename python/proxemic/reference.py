"""The references generated from the core: the metric reference and the scenario schema.

The metric registry of the Rust core (``proxemic._core.metric_registry()``) is the one source of
what a metric means; from it come the metric tables of ``docs/metrics.md``, the column
descriptions ``metrics.json`` that ``proxemic eval`` writes beside its records, and the labels
and units of the summary tables and plots. The scenario reference ``docs/scenario-schema.json``
is the JSON Schema the core emits from its scenario types (``proxemic schema`` prints it).

``python -m proxemic.reference docs`` rewrites the generated parts of the docs;
``python -m proxemic.reference --check docs`` fails when they are stale.
"""

from __future__ import annotations

import argparse
import functools
import json
import re
import sys
from collections.abc import Mapping, Sequence
from pathlib import Path
from typing import Any

from proxemic import _core, markdown
from proxemic.records import MetricInfo

#: The columns of an ``eval`` record that are not metrics, with their descriptions.
RECORD_COLUMNS: dict[str, str] = {
    "scenario": "The scene's name ([scene] name of the scenario file).",
    "planner": "The built-in planner or the policy's name that drove the robot.",
    "seed": "The episode's seed (the same seeds for every planner).",
    "robot": "The robot the record scores (0 for single-robot scenes; every robot of a multi-robot scene).",
    "drive": "The robot's drive: holonomic (Pepper's base) or differential (unicycle); eval --drive sets it.",
    "reward": "The episode's return: the sum of the env's rewards (terms in docs/envs.md).",
    "max_time": "The scenario's episode time limit (s, [episode] max_time): the horizon of SNQI's normalised time.",
}

#: Markers around the generated part of a docs page.
BEGIN = "<!-- BEGIN GENERATED: python -m proxemic.reference docs (do not edit by hand) -->"
END = "<!-- END GENERATED -->"

#: The file of the scenario JSON Schema in the docs folder.
SCHEMA_FILE = "scenario-schema.json"


@functools.cache
def _registry() -> tuple[MetricInfo, ...]:
    return tuple(_core.metric_registry())


def metric_registry() -> list[MetricInfo]:
    """Every metric's reference entry, in the reference's order (a fresh list)."""
    return [dict(m) for m in _registry()]  # type: ignore[misc]


def metric_info(key: str) -> MetricInfo:
    """The reference entry of a metric key.

    Raises:
        KeyError: `key` is not a metric.
    """
    for m in _registry():
        if m["key"] == key:
            return m
    raise KeyError(key)


def unit_label(key: str) -> str:
    """``label (unit)`` of a metric, or the label alone for a dimensionless one."""
    info = metric_info(key)
    unit = "" if info["unit"] in ("", "bool") else info["unit"]
    unit = unit.replace(" (", ", ").removesuffix(")") if " (" in unit else unit  # "m (centre)" -> "m, centre"
    return f"{info['label']} ({unit})" if unit else info["label"]


def record_columns(scenario: Mapping[str, Any]) -> dict[str, dict[str, Any]]:
    """Column descriptions of the flat records of `scenario` (``eval``'s ``episodes.csv``).

    The non-metric columns (:data:`RECORD_COLUMNS`), then one entry per metric column: the
    metric's reference entry plus, for the per-person and per-object metrics (one column
    ``<key>_<name>`` each), the ``person`` or ``object`` it describes.

    Args:
        scenario: The scenario description dict (``scenarios.load(...)[1]``).
    """
    people = [p["name"] for p in scenario.get("persons", [])]
    objects = [o["name"] for o in scenario.get("objects", []) if o.get("interaction") is not None]
    out: dict[str, dict[str, Any]] = {k: {"description": v} for k, v in RECORD_COLUMNS.items()}
    for m in _registry():
        if m["per"] == "episode":
            out[m["key"]] = dict(m)
        else:
            names = people if m["per"] == "person" else objects
            for name in names:
                out[f"{m['key']}_{name}"] = {**m, m["per"]: name}
    return out


def write_metrics_json(path: Path, scenario: Mapping[str, Any]) -> None:
    """Writes the column descriptions of `scenario`'s records (:func:`record_columns`) as JSON."""
    doc = {
        "description": "Columns of episodes.csv / episodes.parquet; metrics defined in docs/metrics.md",
        "columns": record_columns(scenario),
    }
    path.write_text(json.dumps(doc, indent=1, ensure_ascii=False) + "\n")


def _better(m: MetricInfo) -> str:
    return {"higher": "higher", "lower": "lower", "neither": "—"}[m["better"]]


def _unit(m: MetricInfo) -> str:
    return m["unit"] or "—"


def metrics_markdown() -> str:
    """The generated part of ``docs/metrics.md``: per family, a summary table and one entry per metric."""
    families = list(dict.fromkeys(m["family"] for m in _registry()))
    lines: list[str] = []
    for family in families:
        ms = [m for m in _registry() if m["family"] == family]
        rows = []
        for m in ms:
            key = f"`{m['key']}_<{m['per']}>`" if m["per"] != "episode" else f"`{m['key']}`"
            rows.append([f"[{key}](#{m['key']})", m["label"], _unit(m), _better(m)])
        lines += [f"## {family}", "", markdown.table(["key", "label", "unit", "better"], rows), ""]
        for m in ms:
            lines += [f"### {m['key']}", ""]
            facts = [f"**{m['label']}**", f"unit: {_unit(m)}", f"better: {_better(m)}"]
            if m["low"] is not None or m["high"] is not None:
                lo = "-inf" if m["low"] is None else f"{m['low']:g}"
                hi = "inf" if m["high"] is None else f"{m['high']:g}"
                facts.append(f"range: [{lo}, {hi}]")
            if m["per"] != "episode":
                facts.append(f"one value per {m['per']} (columns `{m['key']}_<{m['per']} name>`)")
            lines += [" · ".join(facts), "", m["definition"], ""]
            if m["formula"]:
                lines += [f"Formula: {m['formula']}", ""]
            if m["source"]:
                lines += [f"Source: {m['source']}.", ""]
    return "\n".join(lines).rstrip() + "\n"


def scenario_schema() -> dict[str, Any]:
    """The JSON Schema of a scenario file, as emitted by the core."""
    return dict(json.loads(_core.scenario_schema()))


def _schema_type(root: Mapping[str, Any], node: Mapping[str, Any]) -> str:
    """A field's type in words (``number``, ``[number x 2]``, ``table RawWall`` ...)."""
    if "$ref" in node:
        return f"[{node['$ref'].rsplit('/', 1)[1].removeprefix('Raw').lower()}](#{_anchor(node['$ref'])})"
    if "anyOf" in node:
        alts = [a for a in node["anyOf"] if a.get("type") != "null"]
        return " or ".join(_schema_type(root, a) for a in alts)
    if "oneOf" in node or "enum" in node:
        names = [str(v) for v in node.get("enum", [])]
        names += [str(a["const"]) for a in node.get("oneOf", []) if "const" in a]
        return "one of " + ", ".join(f"`{n}`" for n in names)
    kind = node.get("type")
    if isinstance(kind, list):
        kind = next((k for k in kind if k != "null"), "any")
    if kind == "array":
        items = node.get("items", {})
        inner = _schema_type(root, items) if isinstance(items, dict) else "any"
        if node.get("minItems") is not None and node.get("minItems") == node.get("maxItems"):
            return f"[{inner} x {node['minItems']}]"
        return f"list of {inner}"
    return {"number": "number", "integer": "integer", "string": "text", "boolean": "bool"}.get(str(kind), str(kind))


def _anchor(ref: str) -> str:
    return "table-" + ref.rsplit("/", 1)[1].removeprefix("Raw").lower()


def _cell(text: str) -> str:
    """One table cell: one line, pipes escaped, rustdoc links (`[`x`](y)`, `[`x`]`) as code."""
    text = re.sub(r"\[(`[^`]+`)\](\([^)]*\))?", r"\1", text)
    return " ".join(text.split()).replace("|", "\\|")


def _fields_table(root: Mapping[str, Any], node: Mapping[str, Any]) -> list[str]:
    required = set(node.get("required", []))
    rows = []
    for name, prop in node.get("properties", {}).items():
        default = "required" if name in required else ("" if "default" not in prop else json.dumps(prop["default"]))
        desc = prop.get("description", "")
        if not desc and "$ref" in prop:
            desc = root["$defs"][prop["$ref"].rsplit("/", 1)[1]].get("description", "")
        rows.append([f"`{name}`", _schema_type(root, prop), _cell(default), _cell(desc)])
    return markdown.table(["field", "type", "default", "description"], rows).split("\n")


def scenario_markdown() -> str:
    """The scenario reference: the top-level tables, then one field table per table type, from the schema."""
    root = scenario_schema()
    lines = ["## Top level", "", *_fields_table(root, root), ""]
    for name, node in root.get("$defs", {}).items():
        title = name.removeprefix("Raw").lower()
        lines += [f"## {title} {{ #{_anchor('#/$defs/' + name)} }}", "", _cell(node.get("description", "")), ""]
        if "properties" in node:
            lines += [*_fields_table(root, node), ""]
        for variant in node.get("oneOf", []):
            props = variant.get("properties", {})
            tag = next((k for k, p in props.items() if "const" in p), None)
            if tag is None:
                desc = variant.get("description", "")
                const = variant.get("const", variant.get("enum", [""])[0] if variant.get("enum") else "")
                lines.append(f"- `{const}`: {_cell(desc)}")
                continue
            lines += [f'### {tag} = "{props[tag]["const"]}"', "", _cell(variant.get("description", "")), ""]
            rest = {**variant, "properties": {k: p for k, p in props.items() if k != tag}}
            lines += [*_fields_table(root, rest), ""]
        lines.append("")
    return "\n".join(lines).rstrip() + "\n"


def replace_generated(page: str, generated: str) -> str:
    """`page` with the text between :data:`BEGIN` and :data:`END` replaced by `generated`.

    Raises:
        InputError: The page lacks the markers (:func:`proxemic.markdown.replace_block`).
    """
    return markdown.replace_block(page, BEGIN, END, f"\n{generated}\n", source="the metrics page")


def generated_files(docs: Path) -> dict[Path, str]:
    """What the generated docs files should hold: path -> text."""
    metrics_page = docs / "metrics.md"
    return {
        metrics_page: replace_generated(metrics_page.read_text(), metrics_markdown()),
        docs / SCHEMA_FILE: json.dumps(scenario_schema(), indent=2, ensure_ascii=False) + "\n",
    }


def main(argv: Sequence[str] | None = None) -> int:
    """``python -m proxemic.reference [--check] DOCS``: rewrite (or check) the generated docs."""
    parser = argparse.ArgumentParser(prog="python -m proxemic.reference", description=main.__doc__)
    parser.add_argument("docs", type=Path, help="the docs folder")
    parser.add_argument("--check", action="store_true", help="fail if a generated file is stale")
    args = parser.parse_args(argv)
    stale = []
    for path, text in generated_files(args.docs).items():
        if path.exists() and path.read_text() == text:
            continue
        if args.check:
            stale.append(str(path))
        else:
            path.write_text(text)
            print(f"wrote {path}")
    if stale:
        print(f"stale generated docs: {', '.join(stale)}; run python -m proxemic.reference docs", file=sys.stderr)
        return 1
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
