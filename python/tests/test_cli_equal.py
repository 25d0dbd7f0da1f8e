"""``Scene.render`` gives exactly what the command line writes: the array equals
the PFM of ``nffrt render`` (decoded here, rows bottom first) bit for bit, and
``nffrt.save`` writes the same PNG bytes."""

from __future__ import annotations

from pathlib import Path

import pytest

import nffrt
from helpers import read_pfm, run_cli, shared

CASES = [
    # (scene under ../shared/scenes, render() arguments, the same as flags)
    ("spd/mount.nff", {}, []),
    # One side given: the other follows the file's aspect ratio.
    ("p3f/2025/balls_low.p3f", {"width": 100, "spp": 1}, ["--width", "100", "--spp", "1"]),
    ("spd/gears.nff", {"width": 96, "height": 72, "spp": 4}, ["--width", "96", "--height", "72", "--spp", "4"]),
    ("spd/balls.nff", {"width": 64, "height": 64, "spd": True}, ["--width", "64", "--height", "64", "--spd"]),
    ("spd/teapot.nff", {"width": 80, "height": 60, "max_depth": 2}, ["--width", "80", "--height", "60", "--max-depth", "2"]),
    # P3F: the file's spp (4) as default, a lens, area lights, a skybox.
    ("p3f/2025/dof.p3f", {"width": 80, "height": 60}, ["--width", "80", "--height", "60"]),
    ("p3f/2019/dof.p3f", {"width": 64, "height": 64, "spp": 2, "aperture": 4.0, "focal": 1.1},
     ["--width", "64", "--height", "64", "--spp", "2", "--aperture", "4", "--focal", "1.1"]),
    ("p3f/2019/balls_area_low.p3f", {"width": 64, "height": 48}, ["--width", "64", "--height", "48"]),
]


@pytest.mark.parametrize("rel, kwargs, flags", CASES, ids=[c[0] for c in CASES])
def test_array_equals_the_clis_pfm(nffrt_bin: str, tmp_path: Path, rel: str, kwargs: dict, flags: list) -> None:
    path = shared(*rel.split("/"))
    out = tmp_path / "cli.pfm"
    run_cli(nffrt_bin, "render", str(path), "-q", "-o", str(out), *flags)
    want = read_pfm(out)
    got = nffrt.load(path).render(**kwargs)
    assert got.shape == want.shape
    assert got.tobytes() == want.tobytes()


@pytest.mark.parametrize("ext", ["png", "exr"])
def test_saved_file_is_the_clis_file(nffrt_bin: str, tmp_path: Path, ext: str) -> None:
    path = shared("spd", "rings.nff")
    cli = tmp_path / f"cli.{ext}"
    run_cli(nffrt_bin, "render", str(path), "-q", "--width", "100", "--height", "75", "-o", str(cli))
    nffrt.save(nffrt.load(path).render(width=100, height=75), tmp_path / f"py.{ext}")
    assert (tmp_path / f"py.{ext}").read_bytes() == cli.read_bytes()


def test_a_region_is_the_full_renders_crop_in_8_bits_too(nffrt_bin: str, tmp_path: Path) -> None:
    """A crop equals the full render's pixels there, in floats and, written as PPM,
    in the CLI's 8-bit bytes."""
    path = shared("spd", "tree.nff")
    scene = nffrt.load(path)
    crop = scene.render(width=90, height=70, spp=3, region=(10, 5, 61, 44))
    assert crop.tobytes() == scene.render(width=90, height=70, spp=3)[5:44, 10:61].tobytes()
    nffrt.save(crop, tmp_path / "crop.ppm")
    flags = ["--width", "90", "--height", "70", "--spp", "3"]
    run_cli(nffrt_bin, "render", str(path), "-q", *flags, "-o", str(tmp_path / "full.ppm"))
    header = b"P6\n90 70\n255\n"
    full = (tmp_path / "full.ppm").read_bytes()
    assert full.startswith(header)
    rows = [full[len(header) + (y * 90 + 10) * 3 : len(header) + (y * 90 + 61) * 3] for y in range(5, 44)]
    assert (tmp_path / "crop.ppm").read_bytes() == b"P6\n51 39\n255\n" + b"".join(rows)
