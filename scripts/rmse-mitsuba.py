#!/usr/bin/env python3
"""Time to equal error: nffrt and Mitsuba 3 on the Cornell box against a converged
reference, for scripts/bench-mitsuba.sh.

The reference is the mean of the four independent halves scripts/compare-mitsuba.sh
leaves in target/mitsuba-compare/ (cornell-{nffrt,mitsuba}-{1,2}.exr: 2 x 2 x SPP/2
samples per pixel from both renderers, unbiased if both are; their own RMS error is
printed, a floor under every RMSE below). Each renderer then renders the same
picture, as a whole process, at rising sample counts (nffrt with its default
pattern, --seed 0, Mitsuba with seed 0: neither shares a sample with the reference);
the table gives the medians of RUNS alternating runs' wall and CPU seconds (CPU time,
user and system of the process and its threads, suffers less from another job on the
cores) and the RMSE over all pixels and channels. Mitsuba runs
with its `independent` sampler (its Cornell box's) and, on the first variant named,
also with `stratified`, jittered strata as nffrt's samples are. Last, the
time each Mitsuba variant needs to reach the RMSE nffrt reaches at the largest count,
from its own RMSE falling as 1/sqrt(time) past its largest measured point (log-log
interpolation between measured points when they bracket it).

    rmse-mitsuba.py NFFRT MITSUBA_PY VARIANT... [--spp 16 64 256]
"""

import argparse
import resource
import subprocess
import tempfile
import time
from pathlib import Path

import numpy as np
import mitsuba as mi

ROOT = Path(__file__).resolve().parent.parent
REF_DIR = ROOT / "target/mitsuba-compare"
DEPTH = 8


def read_exr(path):
    return np.array(mi.Bitmap(str(path)), dtype=np.float64)[..., :3]


def reference():
    """The four halves' mean, and its own RMS error estimated from the halves'
    spread (per pixel, the variance of one half is about the mean square of the
    pairwise differences over 2; the mean of four has a quarter of it)."""
    halves = [read_exr(REF_DIR / f"cornell-{side}-{k}.exr") for side in ("nffrt", "mitsuba") for k in (1, 2)]
    ref = sum(halves) / 4
    one_half_var = ((halves[0] - halves[1]) ** 2 + (halves[2] - halves[3]) ** 2) / 4
    return ref, np.sqrt((one_half_var / 4).mean())


def timed(cmd, out):
    """Runs cmd; returns (wall seconds, CPU seconds of it and its children, picture)."""
    before = resource.getrusage(resource.RUSAGE_CHILDREN)
    t0 = time.perf_counter()
    subprocess.run(cmd, check=True, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
    wall = time.perf_counter() - t0
    after = resource.getrusage(resource.RUSAGE_CHILDREN)
    cpu = (after.ru_utime - before.ru_utime) + (after.ru_stime - before.ru_stime)
    return wall, cpu, read_exr(out)


def nffrt_cmd(args, size, spp, out):
    return [args.nffrt, "render", str(ROOT / "examples/cornell.p3f"), "--integrator", "path",
            "--spp", str(spp), "--max-depth", str(DEPTH), "--width", str(size),
            "--height", str(size), "-q", "-o", str(out)]


def mitsuba_cmd(args, variant, size, spp, out, sampler="independent"):
    return [args.mitsuba_py, str(ROOT / "scripts/mitsuba_render.py"), variant, "cornell",
            str(size), str(spp), str(out), "0", sampler]


def time_to(points, target):
    """Seconds to reach RMSE `target` from (seconds, rmse) points, sorted by time:
    log-log interpolation where two points bracket it, else 1/sqrt(time) onwards
    from the last point."""
    for (t0, e0), (t1, e1) in zip(points, points[1:]):
        if e0 >= target >= e1:
            f = np.log(e0 / target) / np.log(e0 / e1)
            return float(np.exp(np.log(t0) + f * np.log(t1 / t0)))
    t, e = points[-1] if target < points[-1][1] else points[0]
    return t * (e / target) ** 2


def main():
    p = argparse.ArgumentParser()
    p.add_argument("nffrt")
    p.add_argument("mitsuba_py")
    p.add_argument("variants", nargs="+")
    p.add_argument("--spp", type=int, nargs="+", default=[16, 64, 256])
    p.add_argument("--runs", type=int, default=3, help="median of this many, alternating")
    args = p.parse_args()
    mi.set_variant("scalar_rgb")
    ref, ref_rmse = reference()
    size = ref.shape[0]
    print(f"== time to equal RMSE: Cornell box {size}x{size}, max depth {DEPTH}, whole processes;"
          f" reference {REF_DIR.name}/cornell-*.exr, its own RMS error ~{ref_rmse:.5f}")
    print(f"{'renderer':28} {'spp':>6} {'wall s':>8} {'CPU s':>8} {'RMSE':>9}")
    with tempfile.TemporaryDirectory() as tmp:
        out = Path(tmp) / "x.exr"
        runners = [("nffrt", lambda spp: nffrt_cmd(args, size, spp, out))]
        for v in args.variants:
            runners.append((f"mitsuba {v}", lambda spp, v=v: mitsuba_cmd(args, v, size, spp, out)))
            subprocess.run(mitsuba_cmd(args, v, size, 4, out), check=True)  # kernel cache
        v = args.variants[0]
        runners.append((f"mitsuba {v} strat.", lambda spp: mitsuba_cmd(args, v, size, spp, out, "stratified")))
        subprocess.run(mitsuba_cmd(args, v, size, 4, out, "stratified"), check=True)
        # (runner, spp) -> wall and CPU seconds of each run, and the RMSE (every run
        # of a seed gives the same picture).
        walls, cpus, rmses = {}, {}, {}
        for _ in range(args.runs):
            for spp in args.spp:
                for name, cmd in runners:
                    wall, cpu, img = timed(cmd(spp), out)
                    walls.setdefault((name, spp), []).append(wall)
                    cpus.setdefault((name, spp), []).append(cpu)
                    rmses[name, spp] = float(np.sqrt(((img - ref) ** 2).mean()))
    curves = {}
    for name, _ in runners:
        points = []
        for spp in args.spp:
            wall, cpu = np.median(walls[name, spp]), np.median(cpus[name, spp])
            points.append((wall, cpu, rmses[name, spp]))
            print(f"{name:28} {spp:6} {wall:8.2f} {cpu:8.2f} {rmses[name, spp]:9.5f}")
        curves[name] = points
    target = curves["nffrt"][-1][2]
    wall_n, cpu_n = curves["nffrt"][-1][:2]
    print(f"to RMSE {target:.5f} (nffrt's at {args.spp[-1]} spp: {wall_n:.2f} s wall, {cpu_n:.2f} s CPU), medians of {args.runs}:")
    for name, points in curves.items():
        if name != "nffrt":
            wall = time_to([(w, e) for w, _, e in points], target)
            cpu = time_to([(c, e) for _, c, e in points], target)
            print(f"  {name:28} {wall:8.2f} s wall ({wall / wall_n:.2f}x nffrt's), "
                  f"{cpu:8.2f} s CPU ({cpu / cpu_n:.2f}x)")

if __name__ == "__main__":
    main()
