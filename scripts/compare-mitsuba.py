#!/usr/bin/env python3
"""nffrt's path tracer against Mitsuba 3 on the same scenes (scripts/mitsuba_scenes.py
builds Mitsuba's side of examples/cornell.p3f and examples/glass-mirror.p3f).

Each side renders the scene twice, independently (nffrt with --seed 1 and 2, Mitsuba
with unrelated seeds), SPP / 2 samples each, to linear EXR. The two halves averaged
are the side's picture; their difference measures its sampling error: for a pixel p,
(A_p - B_p)^2 / 4 estimates the variance of the average, and the pixels' errors are
independent, so a block's or the whole picture's mean has the summed variance over
its pixels divided by their number squared (64 degrees of freedom for an 8 x 8 block).

Reported, per scene: each channel's mean on both sides, their difference in percent
and in standard errors; over the 8 x 8 blocks, the z-score of each block's difference
(difference / combined standard error) for each channel: its mean (a bias shows as a
mean far from 0), its root mean square (about 1 when the sides agree up to noise),
the shares beyond 2 and 3 (about 4.6 % and 0.3 % for normal noise) and the largest.
A side-by-side PNG shows nffrt, Mitsuba, their difference (x4) and the blocks' z
(red: nffrt brighter, blue: darker, full at |z| = 4).

    scripts/compare-mitsuba.sh [--spp 2048] [--size 256] [--scenes cornell glass-mirror]
"""

import argparse
import os
import subprocess
import sys
import time
from pathlib import Path

import numpy as np
import mitsuba as mi

ROOT = Path(__file__).resolve().parent.parent
sys.path.insert(0, str(ROOT / "scripts"))

BLOCK = 8
# Mitsuba renders in passes of this many samples: one wavefront of 256 x 256 x 2048
# samples would hold gigabytes.
PASS_SPP = 64


def parse_args():
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    p.add_argument("--nffrt", default=str(ROOT / "target/release/nffrt"))
    p.add_argument("--spp", type=int, default=2048, help="samples per pixel per side (two halves)")
    p.add_argument("--size", type=int, default=256, help="square picture's side in pixels")
    p.add_argument("--variant", default="llvm_ad_rgb", help="Mitsuba variant")
    p.add_argument("--scenes", nargs="+", default=["cornell", "glass-mirror"])
    p.add_argument("--out", default=str(ROOT / "target/mitsuba-compare"))
    return p.parse_args()


def read_exr(path):
    """A linear RGB float32 array (rows top first) from an EXR, through Mitsuba."""
    return np.array(mi.Bitmap(str(path)), dtype=np.float64)[..., :3]


def render_nffrt(args, name, seed, spp, out):
    """One nffrt render of examples/NAME.p3f; returns (picture, wall seconds)."""
    import mitsuba_scenes

    cmd = [
        args.nffrt, "render", str(ROOT / "examples" / f"{name}.p3f"),
        "--integrator", "path", "--spp", str(spp),
        "--max-depth", str(mitsuba_scenes.MAX_DEPTH[name]),
        "--width", str(args.size), "--height", str(args.size),
        "--seed", str(seed), "-q", "-o", str(out),
    ]
    t0 = time.perf_counter()
    subprocess.run(cmd, check=True)
    return read_exr(out), time.perf_counter() - t0


def render_mitsuba(args, name, seed, spp, out):
    """One Mitsuba render of the same scene, in passes of PASS_SPP samples with seeds
    seed * 100000 + pass; returns (picture, wall seconds, loading excluded)."""
    import mitsuba_scenes

    passes = max(1, spp // PASS_SPP)
    scene = mi.load_dict(mitsuba_scenes.SCENES[name](args.size, PASS_SPP))
    t0 = time.perf_counter()
    total = np.zeros((args.size, args.size, 3))
    for k in range(passes):
        total += np.array(mi.render(scene, spp=min(spp, PASS_SPP), seed=seed * 100000 + k))[..., :3]
    picture = total / passes
    seconds = time.perf_counter() - t0
    mi.Bitmap(picture.astype(np.float32)).write(str(out))
    return picture, seconds


def blocks(a, size=BLOCK):
    """Per-block sums of an (H, W, C) array: (H / size, W / size, C)."""
    h, w, c = a.shape
    return a.reshape(h // size, size, w // size, size, c).sum(axis=(1, 3))


class Side:
    """One renderer's two halves: the average, and the variances of its means."""

    def __init__(self, a, b, seconds):
        self.picture = (a + b) / 2
        # Per pixel, the variance of the average of two independent estimates.
        self.pixel_var = (a - b) ** 2 / 4
        self.seconds = seconds

    def mean(self):
        return self.picture.mean(axis=(0, 1))

    def mean_var(self):
        n = self.picture.shape[0] * self.picture.shape[1]
        return self.pixel_var.sum(axis=(0, 1)) / n**2

    def block_means(self):
        return blocks(self.picture) / BLOCK**2

    def block_vars(self):
        return blocks(self.pixel_var) / BLOCK**4


def block_z(ours, theirs):
    """z-scores of the blocks' differences, (H / 8, W / 8, 3)."""
    var = ours.block_vars() + theirs.block_vars()
    return (ours.block_means() - theirs.block_means()) / np.sqrt(np.maximum(var, 1e-30))


def to_srgb8(linear):
    c = np.clip(linear, 0, 1)
    s = np.where(c <= 0.0031308, 12.92 * c, 1.055 * c ** (1 / 2.4) - 0.055)
    return (s * 255 + 0.5).astype(np.uint8)


def z_picture(z, size):
    """The blocks' z (mean over channels) as colours: red above 0, blue below."""
    zz = np.clip(z.mean(axis=2) / 4, -1, 1)
    rgb = np.stack([np.maximum(zz, 0), np.zeros_like(zz), np.maximum(-zz, 0)], axis=2)
    rgb = np.repeat(np.repeat(rgb, BLOCK, axis=0), BLOCK, axis=1)[:size, :size]
    return (rgb * 255).astype(np.uint8)


def side_by_side(path, ours, theirs, z, title):
    from PIL import Image, ImageDraw

    size = ours.picture.shape[0]
    diff = to_srgb8(np.abs(ours.picture - theirs.picture) * 4)
    panels = [
        ("nffrt", to_srgb8(ours.picture)),
        ("Mitsuba 3", to_srgb8(theirs.picture)),
        ("|difference| x 4", diff),
        ("8x8 blocks: z (|z|=4 full)", z_picture(z, size)),
    ]
    pad, top = 4, 16
    sheet = Image.new("RGB", (len(panels) * (size + pad) + pad, size + top + pad + 14), "white")
    draw = ImageDraw.Draw(sheet)
    for i, (label, rgb) in enumerate(panels):
        x = pad + i * (size + pad)
        sheet.paste(Image.fromarray(rgb), (x, top))
        draw.text((x, 2), label, fill="black")
    draw.text((pad, top + size + 2), title, fill="black")
    sheet.save(path)


def report(name, ours, theirs, z):
    """Prints the scene's table; returns the worst channel's mean difference in %."""
    mo, mt = ours.mean(), theirs.mean()
    se = np.sqrt(ours.mean_var() + theirs.mean_var())
    print(f"\n== {name}")
    print(f"{'channel':8} {'nffrt':>10} {'Mitsuba':>10} {'diff %':>8} {'diff/se':>8}")
    worst = 0.0
    for c, ch in enumerate("RGB"):
        pct = 100 * (mo[c] - mt[c]) / mt[c]
        worst = max(worst, abs(pct))
        print(f"{ch:8} {mo[c]:10.5f} {mt[c]:10.5f} {pct:8.2f} {(mo[c] - mt[c]) / se[c]:8.2f}")
    flat = z.reshape(-1, 3)
    print(f"8x8 blocks ({flat.shape[0]} per channel), z = block difference / its standard error:")
    print(f"{'channel':8} {'mean z':>8} {'rms z':>8} {'|z|>2 %':>8} {'|z|>3 %':>8} {'max |z|':>8}")
    for c, ch in enumerate("RGB"):
        zc = flat[:, c]
        print(
            f"{ch:8} {zc.mean():8.3f} {np.sqrt((zc**2).mean()):8.3f} "
            f"{100 * (np.abs(zc) > 2).mean():8.2f} {100 * (np.abs(zc) > 3).mean():8.2f} "
            f"{np.abs(zc).max():8.2f}"
        )
    print(f"time: nffrt {ours.seconds:.1f} s, Mitsuba ({mi.variant()}) {theirs.seconds:.1f} s")
    return worst


def compare(args, name, out):
    half = args.spp // 2
    a, ta = render_nffrt(args, name, 1, half, out / f"{name}-nffrt-1.exr")
    b, tb = render_nffrt(args, name, 2, half, out / f"{name}-nffrt-2.exr")
    ours = Side(a, b, ta + tb)
    a, ta = render_mitsuba(args, name, 1, half, out / f"{name}-mitsuba-1.exr")
    b, tb = render_mitsuba(args, name, 2, half, out / f"{name}-mitsuba-2.exr")
    theirs = Side(a, b, ta + tb)
    z = block_z(ours, theirs)
    worst = report(name, ours, theirs, z)
    png = out / f"{name}-side-by-side.png"
    side_by_side(
        png, ours, theirs, z,
        f"{name}: {args.size}x{args.size}, {args.spp} spp per side, worst channel mean {worst:.2f} %",
    )
    print(f"picture: {png}")
    return worst


def main():
    args = parse_args()
    mi.set_variant(args.variant)
    out = Path(args.out)
    out.mkdir(parents=True, exist_ok=True)
    print(f"nffrt {args.nffrt}; Mitsuba {mi.__version__} {mi.variant()}; "
          f"{args.size}x{args.size}, {args.spp} spp per side in two independent halves; "
          f"{os.cpu_count()} cores")
    worst = max(compare(args, name, out) for name in args.scenes)
    verdict = "within" if worst <= 2.0 else "BEYOND"
    print(f"\nworst channel mean difference {worst:.2f} %: {verdict} the 2 % goal")


if __name__ == "__main__":
    main()
