"""The render-farm recipes of docs/command-line.md (the blocks tagged
``<!-- test: by python/tests/test_farm_recipes.py -->``), run on this machine as
written there, each result compared with a direct render byte for byte:

- GNU parallel (``parallel`` from Debian), with this machine alone (``-S :``
  instead of ``-S :,host1,host2``; parallel then copies nothing);
- Slurm, with a stand-in for ``sbatch`` on the PATH that runs a script's array
  tasks one after the other (``SLURM_ARRAY_TASK_ID``, ``SLURM_CPUS_PER_TASK`` set
  from its ``#SBATCH`` lines) and a ``--wrap`` command after them;
- Dask, against a real scheduler: ``dask scheduler`` and ``dask worker`` started
  here as processes, their address put in place of the page's.

The scene, ``mount.nff``, is made as the first recipe makes it
(``nffrt gen mount -o mount.nff``).
"""

from __future__ import annotations

import json
import os
import shutil
import subprocess
import sys
import time
from pathlib import Path

import pytest

from doc_blocks import run_by
from helpers import run_cli

BLOCKS = run_by("test_farm_recipes.py")

# The stand-in for Slurm's sbatch: `sbatch --parsable SCRIPT` runs the script once
# per task of its `#SBATCH --array=A-B`, with the task's variables, and prints a job
# id; `sbatch --dependency=afterok:ID --wrap 'COMMAND'` runs the command.
SBATCH = r'''#!/usr/bin/env python3
import os, re, subprocess, sys
args = sys.argv[1:]
if "--wrap" in args:
    sys.exit(subprocess.run(["bash", "-c", args[args.index("--wrap") + 1]]).returncode)
script = args[-1]
text = open(script).read()
first, last = map(int, re.search(r"^#SBATCH --array=(\d+)-(\d+)$", text, re.M).groups())
cpus = re.search(r"^#SBATCH --cpus-per-task=(\d+)$", text, re.M).group(1)
for task in range(first, last + 1):
    env = {**os.environ, "SLURM_ARRAY_TASK_ID": str(task), "SLURM_CPUS_PER_TASK": cpus}
    if subprocess.run(["bash", script], env=env).returncode != 0:
        sys.exit(1)
print(1)
'''


def block(language: str, containing: str) -> str:
    """The code of the tagged ``language`` block that contains ``containing``."""
    found = [b.code for b in BLOCKS if b.language == language and containing in b.code]
    assert len(found) == 1, f"{len(found)} tagged {language} blocks contain {containing!r}"
    return found[0]


def test_every_recipe_block_is_run_here() -> None:
    # parallel, the Slurm script and its submission, Dask.
    assert len(BLOCKS) == 4, [b.name for b in BLOCKS]


def bash(code: str, cwd: Path, nffrt_bin: str, extra_path: Path | None = None) -> None:
    """Runs ``code`` with bash in ``cwd``, nffrt (and ``extra_path``) on the PATH."""
    dirs = [str(Path(nffrt_bin).parent)] + ([str(extra_path)] if extra_path else [])
    env = {**os.environ, "PATH": os.pathsep.join([*dirs, os.environ["PATH"]])}
    out = subprocess.run(
        ["bash", "-euo", "pipefail", "-c", code],
        cwd=cwd, env=env, capture_output=True, stdin=subprocess.DEVNULL,
    )
    assert out.returncode == 0, out.stderr.decode(errors="replace")


def make_mount(nffrt_bin: str, cwd: Path) -> None:
    """``mount.nff`` as the first recipe makes it."""
    assert "nffrt gen mount -o mount.nff" in block("sh", "parallel -S")
    run_cli(nffrt_bin, "gen", "mount", "-o", "mount.nff", cwd=cwd)


def direct_render_is(nffrt_bin: str, cwd: Path, picture: Path) -> None:
    """``picture`` is byte for byte ``nffrt render mount.nff --spp 16``'s."""
    run_cli(nffrt_bin, "render", "mount.nff", "--spp", "16", "-q", "-o", "direct.png", cwd=cwd)
    assert picture.read_bytes() == (cwd / "direct.png").read_bytes()


def test_gnu_parallel_recipe(nffrt_bin: str, tmp_path: Path) -> None:
    if shutil.which("parallel") is None:
        pytest.skip("GNU parallel is not installed (apt-get install parallel; .ci/run does)")
    recipe = block("sh", "parallel -S")
    assert "-S :,host1,host2" in recipe
    bash(recipe.replace("-S :,host1,host2", "-S :"), tmp_path, nffrt_bin)
    assert len(list(tmp_path.glob("tile-*.png"))) == 8
    direct_render_is(nffrt_bin, tmp_path, tmp_path / "mount.png")


def test_slurm_recipe_with_a_stand_in_for_sbatch(nffrt_bin: str, tmp_path: Path) -> None:
    script = block("sh", "#SBATCH")
    assert "# tiles.sh:" in script
    (tmp_path / "tiles.sh").write_text(script)
    bin_dir = tmp_path / "bin"
    bin_dir.mkdir()
    (bin_dir / "sbatch").write_text(SBATCH.replace("#!/usr/bin/env python3", f"#!{sys.executable}", 1))
    (bin_dir / "sbatch").chmod(0o755)
    make_mount(nffrt_bin, tmp_path)
    bash(block("sh", "sbatch --parsable"), tmp_path, nffrt_bin, extra_path=bin_dir)
    assert len(list((tmp_path / "tiles").glob("mount-*.png"))) == 16
    direct_render_is(nffrt_bin, tmp_path, tmp_path / "mount.png")


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

    make_mount(nffrt_bin, tmp_path)
    recipe = block("python", "nffrt.dask.render")
    assert 'Client("tcp://scheduler:8786")' in recipe
    code = recipe.replace("tcp://scheduler:8786", scheduler)
    monkeypatch.chdir(tmp_path)
    with Client(scheduler) as c:
        c.wait_for_workers(2, timeout=120)
    namespace: dict = {}
    exec(compile(code, "docs/command-line.md (Dask recipe)", "exec"), namespace)
    namespace["client"].close()
    direct_render_is(nffrt_bin, tmp_path, tmp_path / "mount.png")
