"""Helpers of the Python tests: the repository, the shared scenes beside it (tests
that need them skip, saying so, when ``../shared`` is absent, as the Rust tests
do), running the ``nffrt`` command line, and reading its files."""

from __future__ import annotations

import os
import subprocess
from pathlib import Path

import numpy as np
import pytest

REPO = Path(__file__).resolve().parents[2]
# $NFFRT_SHARED, as for the Rust tests (NFFRT_SHARED=/nowhere rehearses a fresh clone).
SHARED = Path(os.environ.get("NFFRT_SHARED") or REPO.parent / "shared")
DATA = REPO / "tests" / "data"

# The reason of every ../shared skip, as the Rust tests give it (tests/common/skip.rs);
# conftest.py fails such skips when NFFRT_REQUIRE_SHARED=1.
SHARED_ABSENT = "../shared is absent (the SPD and course scenes, reference pictures)"


def shared_path(relative: str) -> Path:
    """``../shared/RELATIVE``, or a skip saying ../shared is absent (or that this
    is missing from it)."""
    path = SHARED / relative
    if not path.exists():
        if SHARED.is_dir():
            pytest.skip(f"{relative} is absent from ../shared")
        pytest.skip(SHARED_ABSENT)
    return path


def shared(*parts: str) -> Path:
    """A file under ../shared/scenes, or a skip (see ``shared_path``)."""
    return shared_path("/".join(("scenes", *parts)))


def run_cli(binary: str, *args: str, cwd: Path | None = None) -> None:
    """Runs ``nffrt ARGS``, failing the test with its standard error if it fails."""
    out = subprocess.run([binary, *args], capture_output=True, cwd=cwd)
    assert out.returncode == 0, f"nffrt {' '.join(args)}: {out.stderr.decode(errors='replace')}"


def read_pfm(path: Path) -> np.ndarray:
    """Decodes a colour PFM (written here, independently of nffrt's decoder): header
    ``PF``, ``W H``, a negative scale for little-endian; rows bottom first."""
    data = path.read_bytes()
    magic, size, scale, rest = data.split(b"\n", 3)
    assert magic == b"PF", magic
    width, height = (int(v) for v in size.split())
    assert float(scale) < 0, "big-endian PFM"
    pixels = np.frombuffer(rest, dtype="<f4").reshape(height, width, 3)
    return np.flipud(pixels).astype(np.float32)


def header_values(path: Path, key: str) -> list[str]:
    """The values of the ``# KEY: value`` comment lines at the top of a test scene."""
    values = []
    for line in path.read_bytes().split(b"\n"):
        if not line.startswith(b"#"):
            break
        text = line[1:].strip().decode("utf-8", errors="replace")
        if text.startswith(key + ":"):
            values.append(text[len(key) + 1 :].strip())
    return values
