"""The render-farm recipes of docs/command-line.md, run on this machine as written
there, each result compared with a direct render byte for byte:

- GNU parallel (``parallel`` from Debian), with this machine alone (``-S :``
  instead of ``-S :,host1,host2``; parallel then copies nothing), then
  ``nffrt merge``;
- Dask, against a real scheduler: ``dask scheduler`` and ``dask worker`` started
  here as processes, their address put in place of the page's.
"""

from __future__ import annotations

import json
import os
import re
import shutil
import subprocess
import sys
import time
from pathlib import Path

import pytest

from helpers import REPO, run_cli, shared

PAGE = REPO / "docs" / "command-line.md"


def block(language: str, containing: str) -> str:
    """The page's fenced ``language`` block that contains ``containing``."""
    blocks = re.findall(rf"```{language}\n(.*?)```", PAGE.read_text(), re.S)
    found = [b for b in blocks if containing in b]
    assert len(found) == 1, f"{len(found)} {PAGE.name} {language} blocks contain {containing!r}"
    return found[0]


def test_gnu_parallel_recipe(nffrt_bin: str, tmp_path: Path) -> None:
    if shutil.which("parallel") is None:
        pytest.skip("GNU parallel is not installed (apt-get install parallel; .ci/run does)")
    shutil.copy(shared("spd", "mount.nff"), tmp_path / "mount.nff")
    recipe = block("sh", "parallel -S")
    assert "-S :,host1,host2" in recipe
    local = recipe.replace("-S :,host1,host2", "-S :")
    env = {**os.environ, "PATH": f"{Path(nffrt_bin).parent}{os.pathsep}{os.environ['PATH']}"}
    out = subprocess.run(
        ["bash", "-euo", "pipefail", "-c", local],
        cwd=tmp_path, env=env, capture_output=True, stdin=subprocess.DEVNULL,
    )
    assert out.returncode == 0, out.stderr.decode(errors="replace")
    assert len(list(tmp_path.glob("tile-*.png"))) == 8
    run_cli(nffrt_bin, "render", "mount.nff", "--spp", "16", "-q", "-o", "direct.png", cwd=tmp_path)
    assert (tmp_path / "mount.png").read_bytes() == (tmp_path / "direct.png").read_bytes()


@pytest.fixture
def scheduler(tmp_path: Path):
    """A Dask scheduler and a worker process of two single-thread workers, on the
    loopback interface; yields the scheduler's address."""
    pytest.importorskip("distributed", reason="dask[distributed] is not installed")
    info = tmp_path / "scheduler.json"
    dask = [sys.executable, "-m", "dask"]
    logs = open(tmp_path / "dask.log", "wb")
    procs = [
        subprocess.Popen(
            [*dask, "scheduler", "--host", "127.0.0.1", "--port", "0", "--no-dashboard",
             "--scheduler-file", str(info)],
            stdout=logs, stderr=logs, stdin=subprocess.DEVNULL,
        )
    ]
    try:
        for _ in range(600):  # wait for the scheduler to say where it listens
            if info.exists() and info.stat().st_size > 0:
                break
            assert procs[0].poll() is None, (tmp_path / "dask.log").read_text()
            time.sleep(0.1)
        address = json.loads(info.read_text())["address"]
        procs.append(
            subprocess.Popen(
                [*dask, "worker", address, "--nworkers", "2", "--nthreads", "1",
                 "--no-dashboard", "--host", "127.0.0.1"],
                stdout=logs, stderr=logs, stdin=subprocess.DEVNULL,
            )
        )
        yield address
    finally:
        for p in reversed(procs):
            p.terminate()
        for p in reversed(procs):
            try:
                p.wait(timeout=30)
            except subprocess.TimeoutExpired:
                p.kill()
        logs.close()


def test_dask_recipe_against_a_scheduler(nffrt_bin: str, scheduler: str, tmp_path: Path, monkeypatch) -> None:
    from distributed import Client

    shutil.copy(shared("spd", "mount.nff"), tmp_path / "mount.nff")
    recipe = block("python", "nffrt.dask.render")
    assert 'Client("tcp://scheduler:8786")' in recipe
    code = recipe.replace("tcp://scheduler:8786", scheduler)
    monkeypatch.chdir(tmp_path)
    with Client(scheduler) as c:
        c.wait_for_workers(2, timeout=120)
    namespace: dict = {}
    exec(compile(code, "docs/command-line.md (Dask recipe)", "exec"), namespace)
    namespace["client"].close()
    run_cli(nffrt_bin, "render", "mount.nff", "--spp", "16", "-q", "-o", "direct.png", cwd=tmp_path)
    assert (tmp_path / "mount.png").read_bytes() == (tmp_path / "direct.png").read_bytes()
