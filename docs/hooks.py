"""MkDocs hooks: the parts of the docs generated at build time from the installed package.

- ``<!-- generated: scenario-reference -->``: the scenario file's tables and fields, from the
  JSON Schema the core emits (``proxemic.reference.scenario_markdown``);
- ``<!-- generated: cli-help -->``: ``proxemic <command> --help`` of every command;
- ``<!-- generated: readme -->``: the repository's README (the home page; one source), its
  ``docs/`` links made relative to the site;
- after the build, the Rust core's ``cargo doc`` (``target/doc``, built by ``make docs``) is
  copied to ``site/rust-api``.
"""

from __future__ import annotations

import argparse
import shutil
from pathlib import Path
from typing import Any

ROOT = Path(__file__).resolve().parents[1]


def _cli_help() -> str:
    from proxemic.cli import build_parser

    parser = build_parser()
    parts = ["```text", parser.format_help().rstrip(), "```", ""]
    for action in parser._actions:
        if isinstance(action, argparse._SubParsersAction):
            for name, sub in action.choices.items():
                parts += [f"## proxemic {name}", "", "```text", sub.format_help().rstrip(), "```", ""]
    return "\n".join(parts)


def on_page_markdown(markdown: str, page: Any, config: Any, files: Any) -> str:
    """Fills the generated sections of a page."""
    if "<!-- generated: scenario-reference -->" in markdown:
        from proxemic.reference import scenario_markdown

        markdown = markdown.replace("<!-- generated: scenario-reference -->", scenario_markdown())
    if "<!-- generated: readme -->" in markdown:
        readme = (ROOT / "README.md").read_text()
        markdown = markdown.replace("<!-- generated: readme -->", readme.replace("](docs/", "]("))
    if "<!-- generated: cli-help -->" in markdown:
        markdown = markdown.replace("<!-- generated: cli-help -->", _cli_help())
    return markdown


def on_post_build(config: Any) -> None:
    """Copies the Rust core's API docs into the site (``site/rust-api``), when built."""
    rust_doc = ROOT / "target" / "doc"
    if rust_doc.is_dir():
        dest = Path(config["site_dir"]) / "rust-api"
        shutil.rmtree(dest, ignore_errors=True)
        shutil.copytree(rust_doc, dest)
