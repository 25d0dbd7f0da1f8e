"""Every code block of README.md and docs/*.md that is meant to run runs, as
written (doc_blocks.py says how blocks are tagged): shell blocks through the ``nffrt``
binary under test in a scratch directory, Python blocks through the installed
module; blocks that cannot run say why and are reported skipped."""

from __future__ import annotations

import os
import re
import signal
import subprocess
from pathlib import Path

import pytest

from doc_blocks import LANGUAGES, Block, blocks
from helpers import REPO, shared_path

ALL = blocks()
# Blocks run here: `sh` and `python` ones but those another test runs (`by`).
RUNNABLE = [b for b in ALL if b.language != "text" and b.directive_argument("by") is None]
# How long any one block may take (the slowest renders 800x600 at 64 samples per
# pixel: seconds, on a busy machine).
PATIENCE = 600


def test_every_block_has_a_known_language_and_a_well_formed_directive() -> None:
    assert len(ALL) >= 15
    for b in ALL:
        assert b.language in LANGUAGES, f"{b.name}: fence ```{b.language}: use sh, python or text"
        if b.directive is None:
            continue
        assert b.language != "text", f"{b.name}: a text block never runs; it needs no directive"
        kind = b.directive.split(" ", 1)[0]
        assert kind in {"skip", "by", "in", "server", "denoiser"}, f"{b.name}: unknown directive {b.directive!r}"
        if kind == "skip":
            assert re.fullmatch(r"\(.+\)", b.directive_argument("skip")), f"{b.name}: skip (REASON)"
        if kind == "by":
            test = REPO / b.directive_argument("by")
            assert test.is_file(), f"{b.name}: no {test}"
            assert "run_by(" in test.read_text(), f"{b.name}: {test.name} does not read its blocks"
        if kind == "in":
            assert b.directive_argument("in").startswith("../shared/"), b.name


def scratch(tmp_path: Path, block: Block) -> Path:
    """The directory a block runs in: ``examples/`` of the checkout beside it, and
    for ``in ../shared/FOLDER`` the files of that folder."""
    (tmp_path / "examples").symlink_to(REPO / "examples")
    folder = block.directive_argument("in")
    if folder is not None:
        for entry in shared_path(folder.removeprefix("../shared/")).iterdir():
            (tmp_path / entry.name).symlink_to(entry)
    return tmp_path


def shell(block: Block, nffrt_bin: str) -> tuple[str, dict]:
    """The block's commands, with ``cargo run --release --`` standing for the
    binary under test (on the PATH), and their environment (no desktop: no browser
    opens)."""
    code = block.code.replace("cargo run --release -- ", "nffrt ")
    env = {k: v for k, v in os.environ.items() if k not in ("DISPLAY", "WAYLAND_DISPLAY")}
    env["PATH"] = f"{Path(nffrt_bin).parent}{os.pathsep}{env['PATH']}"
    return code, env


def run_server(code: str, env: dict, cwd: Path) -> None:
    """Starts the block, waits for the URL it serves, stops it with Ctrl-C: it must
    exit with code 0."""
    proc = subprocess.Popen(
        ["bash", "-euo", "pipefail", "-c", code], cwd=cwd, env=env,
        stdout=subprocess.PIPE, stderr=subprocess.PIPE, stdin=subprocess.DEVNULL,
        start_new_session=True, text=True,
    )
    try:
        line = proc.stdout.readline()
        assert line.startswith("serving http://"), f"first line {line!r}, stderr {proc.stderr.read()}"
        os.killpg(proc.pid, signal.SIGINT)
        out, err = proc.communicate(timeout=PATIENCE)
        assert proc.returncode == 0, f"exit {proc.returncode} after Ctrl-C: {err}"
    finally:
        if proc.poll() is None:
            os.killpg(proc.pid, signal.SIGKILL)
            proc.wait()


def denoiser_installed() -> bool:
    """True if Open Image Denoise is found as ``Scene.render(denoise=...)`` looks
    for it."""
    import nffrt

    try:
        nffrt.parse(nffrt.gen("tetra", size=1)).render(width=4, height=4, spp=2, denoise=True)
    except OSError:
        return False
    return True


@pytest.mark.parametrize("block", RUNNABLE, ids=lambda b: b.name)
def test_block_runs_as_written(block: Block, nffrt_bin: str, tmp_path: Path, monkeypatch) -> None:
    reason = block.directive_argument("skip")
    if reason is not None:
        pytest.skip(f"a doc block that cannot run here: {reason[1:-1]}")
    if block.directive == "denoiser" and not denoiser_installed():
        reason = "Open Image Denoise is not installed (pip install pyoidn, or NFFRT_OIDN)"
        if os.environ.get("NFFRT_REQUIRE_OIDN") == "1":
            pytest.fail(f"NFFRT_REQUIRE_OIDN=1 but {reason}")
        pytest.skip(reason)
    cwd = scratch(tmp_path, block)
    if block.language == "python":
        monkeypatch.chdir(cwd)
        exec(compile(block.code, block.name, "exec"), {"__name__": "__doc_block__"})
        return
    code, env = shell(block, nffrt_bin)
    if block.directive == "server":
        run_server(code, env, cwd)
        return
    out = subprocess.run(
        ["bash", "-euo", "pipefail", "-c", code], cwd=cwd, env=env,
        capture_output=True, stdin=subprocess.DEVNULL, timeout=PATIENCE,
    )
    assert out.returncode == 0, f"{block.name}: exit {out.returncode}\n{out.stderr.decode(errors='replace')}"
