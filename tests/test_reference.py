"""The references generated from the core: metric registry, docs pages, scenario schema, `proxemic schema`."""

from __future__ import annotations

import json
import math
from pathlib import Path

import gymnasium as gym
import pytest

import proxemic  # noqa: F401  (registers the envs)
from proxemic import _core, markdown, reference, scenarios
from proxemic.cli import main
from proxemic.env import flatten_metrics
from proxemic.errors import InputError
from proxemic.evaluation import HEADLINE, METRICS, headline_markdown, summarise

DOCS = Path(__file__).resolve().parents[1] / "docs"


def test_generated_docs_are_up_to_date():
    """docs/metrics.md's tables and docs/scenario-schema.json are what the core generates now."""
    for path, text in reference.generated_files(DOCS).items():
        assert path.read_text() == text, f"{path} is stale: run python -m proxemic.reference docs"


def test_every_metric_of_an_episode_is_in_the_registry_and_back():
    """The keys of a real episode's metrics and the registry's keys are the same set."""
    env = gym.make("proxemic/CareCenter-v5")
    env.reset(seed=0)
    for _ in range(5):
        env.step(env.action_space.sample())
    metrics = env.unwrapped.metrics()
    keys = {m["key"] for m in _core.metric_registry()}
    assert set(metrics) == keys
    for m in _core.metric_registry():
        assert isinstance(metrics[m["key"]], list) == (m["per"] != "episode"), m["key"]
    flat = flatten_metrics(metrics, env.unwrapped.scenario)
    columns = reference.record_columns(env.unwrapped.scenario)
    assert set(flat) == set(columns) - set(reference.RECORD_COLUMNS)
    env.close()


def test_summary_labels_and_units_come_from_the_registry():
    for key, info in METRICS.items():
        if key in ("reward", "snqi"):  # the env's return and the evaluation's composite
            continue
        entry = reference.metric_info(key)
        assert info.label == entry["label"]
        if entry["unit"] == "%":
            assert (info.low, info.high) == (0.0, 100.0)
    # every headline column says its unit
    record = {"planner": "p", "outcome": "success", "success": True, "reward": 1.0, "time_to_goal": 3.0}
    header = headline_markdown(summarise([record])).splitlines()[0]
    for key in HEADLINE:
        info = METRICS[key]
        assert info.label in header
    for unit in ("(%)", "(s)", "(x geodesic)", "(steps)"):
        assert unit in header


def test_bounded_metrics_have_bounded_ranges():
    for m in reference.metric_registry():
        if m["unit"] == "%":
            assert (m["low"], m["high"]) == (0.0, 100.0), m["key"]
        if m["low"] is not None and m["high"] is not None:
            assert math.isfinite(m["low"]) and m["low"] < m["high"]


def test_the_schema_describes_every_field_the_bundled_scenarios_use():
    """Every key of every bundled scenario file is a property of the schema at that place."""
    tomllib = pytest.importorskip("tomllib")  # Python 3.11+

    schema = reference.scenario_schema()

    def resolve(node):
        ref = node.get("$ref")
        if ref:
            return resolve(schema["$defs"][ref.rsplit("/", 1)[1]])
        alts = [a for a in node.get("anyOf", []) if a.get("type") != "null"]
        return resolve(alts[0]) if len(alts) == 1 else node

    def check(value, node, where):
        node = resolve(node)
        if isinstance(value, dict):
            props = dict(node.get("properties", {}))
            for variant in node.get("oneOf", []):
                props.update(variant.get("properties", {}))
            for k, v in value.items():
                assert k in props, f"{where}.{k} is not in the schema"
                check(v, props[k], f"{where}.{k}")
        elif isinstance(value, list) and "items" in node and isinstance(node["items"], dict):
            for i, v in enumerate(value):
                check(v, node["items"], f"{where}[{i}]")

    for name in scenarios.available():
        data = tomllib.loads(scenarios.resolve(name).read_text())
        check(data, schema, name)


def test_proxemic_schema_prints_the_json_schema(capsys):
    assert main(["schema"]) == 0
    printed = json.loads(capsys.readouterr().out)
    assert printed == reference.scenario_schema()
    assert printed["$defs"]["RawWall"]["properties"]["to"]["maxItems"] == 2


def test_replace_generated_needs_the_markers():
    with pytest.raises(ValueError, match="markers"):
        reference.replace_generated("no markers here", "x")


def test_replace_block_keeps_what_lies_outside_the_markers():
    page = "intro\n<!-- a -->\nold\n<!-- b -->\noutro\n"
    assert markdown.replace_block(page, "<!-- a -->", "<!-- b -->", "new\n", source="p.md") == (
        "intro\n<!-- a -->\nnew\n<!-- b -->\noutro\n"
    )
    # the end marker must follow the begin marker; the error names the page
    with pytest.raises(InputError, match=r"p\.md: expected a block between the markers"):
        markdown.replace_block("<!-- b -->\n<!-- a -->\n", "<!-- a -->", "<!-- b -->", "x\n", source="p.md")
