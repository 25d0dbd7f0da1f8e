"""The fenced code blocks of README.md and docs/*.md, and how each is tested.

A block's fence names its language: ``sh`` and ``python`` blocks run, ``text``
blocks (output, syntax, tables of options) are read, never run; no other language
is allowed. An HTML comment on the line before the fence says how a block runs
when it cannot simply run as written:

- ``<!-- test: skip (REASON) -->``: it does not run, for REASON (installing into
  your environment, a cluster we do not have...); the tests report it skipped;
- ``<!-- test: by python/tests/FILE.py -->``: that test runs it, with what it needs
  (a scheduler, a fake ``sbatch``) and checks its result;
- ``<!-- test: in ../shared/FOLDER -->``: it runs among the files of FOLDER, and is
  skipped, saying so, without ``../shared``;
- ``<!-- test: server -->``: it starts ``nffrt view``; it must print the URL it
  serves, then stop cleanly on Ctrl-C (exit code 0);
- ``<!-- test: denoiser -->``: it denoises; it runs when Open Image Denoise is
  installed (``pip install pyoidn``, or ``NFFRT_OIDN``), and is skipped, saying
  so, otherwise (a failure under ``NFFRT_REQUIRE_OIDN=1``, as ``.ci/run`` sets).

Every other ``sh`` or ``python`` block runs as written in a scratch directory
(test_docs.py), shell through the ``nffrt`` binary under test (``cargo run
--release --`` stands for it: the tests do not build the release binary) and
Python through the module installed for the tests.
"""

from __future__ import annotations

import re
from dataclasses import dataclass
from pathlib import Path
from typing import Optional

from helpers import REPO

PAGES = [REPO / "README.md", *sorted((REPO / "docs").glob("*.md"))]
LANGUAGES = {"sh", "python", "text"}
DIRECTIVE = re.compile(r"<!-- test: (.*) -->")
FENCE = re.compile(r"```(\S*)\s*$")


@dataclass
class Block:
    """One fenced block: where it is, its language, its code and its directive."""

    page: Path
    line: int
    language: str
    code: str
    directive: Optional[str]

    @property
    def name(self) -> str:
        return f"{self.page.relative_to(REPO)}:{self.line}"

    def directive_argument(self, kind: str) -> Optional[str]:
        """The text after ``kind`` in the directive, if the directive is of that kind."""
        if self.directive is None:
            return None
        word, _, rest = self.directive.partition(" ")
        return rest.strip() if word == kind else None


def blocks() -> list[Block]:
    """Every fenced block of the README and docs/, in page order."""
    found = []
    for page in PAGES:
        lines = page.read_text(encoding="utf-8").split("\n")
        k = 0
        while k < len(lines):
            opening = FENCE.match(lines[k])
            if not opening:
                k += 1
                continue
            end = next(j for j in range(k + 1, len(lines)) if lines[j].startswith("```"))
            previous = DIRECTIVE.fullmatch(lines[k - 1].strip()) if k > 0 else None
            found.append(
                Block(
                    page=page,
                    line=k + 1,
                    language=opening.group(1),
                    code="\n".join(lines[k + 1 : end]) + "\n",
                    directive=previous.group(1) if previous else None,
                )
            )
            k = end + 1
    return found


def run_by(test_file: str) -> list[Block]:
    """The blocks whose directive says ``by python/tests/<test_file>``."""
    return [b for b in blocks() if b.directive_argument("by") == f"python/tests/{test_file}"]
