"""Every relative link in the README and the docs points at a file of the repository.

Why a test: the README's reference sections moved to docs/ pages (session 40), links were rewritten
relative to their new folder, and the bench write-ups move blocks between pages; a link that
resolves from one folder breaks silently from another. Code blocks are skipped (their brackets are
code, not links); web addresses and in-page anchors are not checked.
"""

from __future__ import annotations

import re
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
LINK = re.compile(r"\]\(([^)\s]+)\)")


def _links(md: Path):
    fence = False
    for n, line in enumerate(md.read_text().split("\n"), 1):
        if line.startswith("```"):
            fence = not fence
        if fence:
            continue
        for target in LINK.findall(line):
            if not re.match(r"[a-z]+:", target) and not target.startswith("#"):
                yield n, target


def test_relative_links_in_readme_and_docs_resolve():
    pages = [ROOT / "README.md", *sorted((ROOT / "docs").rglob("*.md")), *sorted((ROOT / "probes").rglob("*.md"))]
    assert len(pages) > 20  # the README, the docs pages and one README per concept
    broken = [f"{md.relative_to(ROOT)}:{n}: {t}" for md in pages for n, t in _links(md)
              if not (md.parent / t.split("#")[0]).exists()]
    assert not broken, "\n".join(broken)


def test_a_broken_link_is_found(tmp_path):
    md = tmp_path / "page.md"
    md.write_text("[here](page.md) [gone](missing.md) [web](https://example.org) [top](#top)\n"
                  "```\n[code](not-a-link.md)\n```\n")
    assert [t for _, t in _links(md) if not (tmp_path / t).exists()] == ["missing.md"]
