#!/usr/bin/env python3
"""The Python module against the command line, and Dask against one thread.

1. Overhead of the Python call: ``Scene.render()`` on a prepared scene (timed
   around the call: GIL release, the render, the copy into a numpy array) against
   the render time ``nffrt render --stats-json`` reports for the same scene
   (``render_s``: the render alone, parse and BVH build excluded on both sides),
   runs interleaved, medians compared. The goal is at most 5 %.
2. Dask's speed-up: ``nffrt.dask.render`` on a LocalCluster of two single-thread
   worker processes against one thread rendering locally (and, for scale, one
   worker, and two local threads), runs interleaved, after a warm-up that has every
   worker load the scene (and checks the result against the local render).

Usage (with the module installed, e.g. scripts/test-all.sh's target/py-venv):

    target/py-venv/bin/python scripts/bench-python.py [--scene ../shared/scenes/spd/mount.nff]
        [--nffrt target/release/nffrt] [--runs 15] [--spp 16] [--tiles 16]

Prints a Markdown table for BENCHMARKS.md. Timings on a shared machine are noisy:
compare medians of several runs, and say what else was running.
"""

from __future__ import annotations

import argparse
import json
import os
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import nffrt

REPO = Path(__file__).resolve().parents[1]


def cli_render_s(binary: str, scene: Path, out_dir: Path, extra: list[str]) -> tuple[float, float]:
    """One CLI run: its own render time and the wall time of the whole process."""
    stats = out_dir / "stats.json"
    t0 = time.perf_counter()
    subprocess.run(
        [binary, "render", str(scene), "-q", "-o", str(out_dir / "cli.pfm"), "--stats-json", str(stats), *extra],
        check=True,
    )
    wall = time.perf_counter() - t0
    return json.loads(stats.read_text())["render_s"], wall


def python_process_s(scene: Path, out_dir: Path) -> float:
    """Wall time of a Python process that imports nffrt, loads, renders and saves a PFM."""
    code = (
        "import sys, nffrt; s = nffrt.load(sys.argv[1]); "
        "nffrt.save(s.render(), sys.argv[2])"
    )
    t0 = time.perf_counter()
    subprocess.run([sys.executable, "-c", code, str(scene), str(out_dir / "py.pfm")], check=True)
    return time.perf_counter() - t0


def median_time(f, runs: int) -> float:
    times = []
    for _ in range(runs):
        t0 = time.perf_counter()
        f()
        times.append(time.perf_counter() - t0)
    return statistics.median(times)


def overhead(binary: str, scene_path: Path, runs: int) -> None:
    scene = nffrt.load(scene_path)
    scene.render()  # warm-up: pages, thread pool
    with tempfile.TemporaryDirectory() as d:
        out = Path(d)
        cli, cli_wall, py, py_proc = [], [], [], []
        for _ in range(runs):
            r, wall = cli_render_s(binary, scene_path, out, [])
            cli.append(r)
            cli_wall.append(wall)
            t0 = time.perf_counter()
            image = scene.render()
            py.append(time.perf_counter() - t0)
            py_proc.append(python_process_s(scene_path, out))
        nffrt.save(image, out / "py.pfm")
        same = (out / "py.pfm").read_bytes() == (out / "cli.pfm").read_bytes()
    c, p = statistics.median(cli), statistics.median(py)
    print(f"## Python call against the CLI: {scene_path.name}, {runs} interleaved runs, medians")
    print()
    print("| measure | CLI | Python | Python / CLI |")
    print("|---|---|---|---|")
    print(f"| render (CLI `render_s`; Python `Scene.render()` call) | {c:.4f} s | {p:.4f} s | {p / c - 1:+.1%} |")
    cw, pw = statistics.median(cli_wall), statistics.median(py_proc)
    print(f"| whole process (parse, build, render, write PFM; Python imports numpy) | {cw:.3f} s | {pw:.3f} s | {pw / cw - 1:+.1%} |")
    tiny = median_time(lambda: scene.render(width=1, height=1), 200)
    print(f"| fixed cost of a call (a 1x1 render, 200 calls) | | {tiny * 1e3:.3f} ms | |")
    print()
    print(f"(min render: CLI {min(cli):.4f} s, Python {min(py):.4f} s; PFM files identical: {same})")
    print()


def dask_speedup(scene_path: Path, spp: int, tiles: int, runs: int) -> None:
    import distributed
    import nffrt.dask

    scene = nffrt.load(scene_path)
    want = scene.render(spp=spp).tobytes()
    path = str(scene_path)
    with distributed.LocalCluster(
        n_workers=1, threads_per_worker=1, processes=True, dashboard_address=":0"
    ) as one, distributed.LocalCluster(
        n_workers=2, threads_per_worker=1, processes=True, dashboard_address=":0"
    ) as two, distributed.Client(one) as c1, distributed.Client(two) as c2:
        for c in (c1, c2):  # warm-up: every worker loads the scene; checked against local
            assert nffrt.dask.render(path, c, tiles=tiles, spp=spp).tobytes() == want
            assert nffrt.dask.render(path, c, tiles=tiles, spp=spp).tobytes() == want
        runners = {
            "local, 1 thread": lambda: scene.render(spp=spp, threads=1),
            "local, 2 threads": lambda: scene.render(spp=spp, threads=2),
            "Dask, 1 worker process x 1 thread": lambda: nffrt.dask.render(path, c1, tiles=tiles, spp=spp),
            "Dask, 2 worker processes x 1 thread": lambda: nffrt.dask.render(path, c2, tiles=tiles, spp=spp),
        }
        times: dict[str, list[float]] = {name: [] for name in runners}
        for _ in range(runs):  # interleaved, so that a change of load hits every row
            for name, run in runners.items():
                t0 = time.perf_counter()
                run()
                times[name].append(time.perf_counter() - t0)
    base = statistics.median(times["local, 1 thread"])
    print(f"## Dask: {scene_path.name}, spp {spp}, {tiles} bands, {runs} interleaved runs, medians")
    print()
    print("| run | time (median; min) | speed-up over one local thread |")
    print("|---|---|---|")
    for name, t in times.items():
        m = statistics.median(t)
        print(f"| {name} | {m:.3f} s; {min(t):.3f} s | {base / m:.2f}x |")
    print()


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--scene", type=Path, default=REPO.parent / "shared" / "scenes" / "spd" / "mount.nff")
    ap.add_argument("--nffrt", default=str(REPO / "target" / "release" / "nffrt"))
    ap.add_argument("--runs", type=int, default=15)
    ap.add_argument("--spp", type=int, default=16)
    ap.add_argument("--tiles", type=int, default=16)
    ap.add_argument("--skip-dask", action="store_true")
    a = ap.parse_args()
    print(f"nffrt {nffrt.__version__}, {os.cpu_count()} CPUs, load average {os.getloadavg()[0]:.2f} at start")
    print()
    overhead(a.nffrt, a.scene, a.runs)
    if not a.skip_dask:
        dask_speedup(a.scene, a.spp, a.tiles, max(3, a.runs // 3))
    print(f"load average {os.getloadavg()[0]:.2f} at the end")


if __name__ == "__main__":
    main()
