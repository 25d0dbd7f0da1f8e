#!/usr/bin/env python3
"""Times `nffrt diff` beside NVIDIA's own FLIP tool (`flip`, from PyPI's
flip-evaluator) on the same pairs: the course's balls_low picture against nffrt's
render (512x512, PNG: LDR-FLIP), that render against a 4-spp one (512x512, EXR:
HDR-FLIP), and the two renders at 1920x1080 in PNG and EXR. Each time is the
median of RUNS runs of the whole command (reading both files included), neither
writing a map. BENCHMARKS.md has a run.

    scripts/bench-diff.py [NFFRT [FLIP]]   (default: target/release/nffrt and the
                                            `flip` of target/py-venv, which
                                            scripts/test-all.sh installs)
"""

import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path

REPO = Path(__file__).resolve().parents[1]
SHARED = REPO.parent / "shared"
RUNS = 7


def median_seconds(command: list[str]) -> float:
    times = []
    for _ in range(RUNS):
        start = time.perf_counter()
        subprocess.run(command, check=True, capture_output=True)
        times.append(time.perf_counter() - start)
    return statistics.median(times)


def main() -> None:
    nffrt = sys.argv[1] if len(sys.argv) > 1 else str(REPO / "target/release/nffrt")
    flip = sys.argv[2] if len(sys.argv) > 2 else str(REPO / "target/py-venv/bin/flip")
    scene = SHARED / "scenes/p3f/2025/balls_low.p3f"
    work = Path(tempfile.mkdtemp(prefix="bench-diff-"))
    render = lambda out, *opts: subprocess.run([nffrt, "render", str(scene), "-q", "-o", str(work / out), *opts], check=True)
    render("t512.png")
    (work / "r512.png").write_bytes((SHARED / "reference/p3f/balls_low-whitted.png").read_bytes())
    render("t512.exr")
    render("r512.exr", "--spp", "4")
    for ext in ("png", "exr"):
        render(f"t1080.{ext}", "--width", "1920", "--height", "1080")
        render(f"r1080.{ext}", "--width", "1920", "--height", "1080", "--spp", "4")
    print(f"median of {RUNS} runs, seconds")
    print("pair            nffrt diff   flip   flip / nffrt")
    for size, label in (("512", "512x512"), ("1080", "1920x1080")):
        for ext, kind in (("png", "LDR"), ("exr", "HDR")):
            test, ref = str(work / f"t{size}.{ext}"), str(work / f"r{size}.{ext}")
            ours = median_seconds([nffrt, "diff", test, ref])
            theirs = median_seconds([flip, "-r", ref, "-t", test, "-v", "0", "-nerm", "-nexm", "-d", str(work)])
            print(f"{label:>9} {kind}   {ours:9.3f}  {theirs:6.3f}   {theirs / ours:5.2f}")


if __name__ == "__main__":
    main()
