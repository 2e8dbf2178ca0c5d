"""The product speaks of itself: code, tests, workflow, benchmarks, the README and the docs describe
the project and the paper, never the tickets that asked for a change (the changelog keeps the
history).  A reference such as "issue 16" or "ticket #3" in any of them fails this test."""

import re
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
#: Where the product's own words are; CHANGELOG.md is history and may name releases.
PLACES = ("selfalign", "tests", "workflow", "benchmarks", "docs", ".ci")
FILES = ("README.md", "Snakefile", "pyproject.toml")
SUFFIXES = {".py", ".md", ".rst", ".yaml", ".yml", ".smk", ".toml", ".cfg", ".txt", ".sh"}
#: A ticket reference: "issue 12", "issue #12", "Issue 16's", "ticket 3", "(#14)", and a work item
#: named without its number: "targets of the issue", "the issue's target".
TICKET = re.compile(r"\b(?:issue|ticket)s?\s*#?\d+|\(#\d+\)|\b(?:of|in|by) the (?:issue|ticket)\b|"
                    r"\bthe (?:issue|ticket)'s\b", re.IGNORECASE)


def _texts():
    for place in PLACES:
        for path in sorted((ROOT / place).rglob("*")):
            if path.is_file() and path.suffix in SUFFIXES and "_build" not in path.parts:
                yield path
    for name in FILES:
        if (ROOT / name).exists():
            yield ROOT / name


def test_no_ticket_references_in_the_product():
    found = []
    for path in _texts():
        for number, line in enumerate(path.read_text(encoding="utf-8", errors="replace").splitlines(), 1):
            if TICKET.search(line) and path.name != "test_product_language.py":
                found.append(f"{path.relative_to(ROOT)}:{number}: {line.strip()[:100]}")
    assert not found, "ticket references (describe the project instead):\n" + "\n".join(found)


def test_the_pattern_finds_ticket_references():
    for text in ("see issue 16", "Issue #12's target", "(#14)", "tickets 3", "Targets of the issue:",
                 "the issue's speed target"):
        assert TICKET.search(text), text
    for text in ("an issue with the solver", "eq. (16)", "Sect. 7.3", "#: 16 values"):
        assert not TICKET.search(text), text
