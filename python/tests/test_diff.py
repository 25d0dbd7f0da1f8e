"""``nffrt diff`` and ``nffrt.diff``: FLIP's means held to NVIDIA's own
implementation, ``flip-evaluator`` (PyPI), within 0.001 on pictures made here (a
course picture against nffrt's render of its scene, pictures against blurred
copies, LDR and HDR); the Python function against the command line; its errors.

``scripts/test-all.sh`` installs flip-evaluator; without it these checks skip,
saying so, except under CI (``NFFRT_REQUIRE_FLIP=1``, set by ``.ci/run``), where
that is a failure."""

from __future__ import annotations

import json
import os
import subprocess
from pathlib import Path

import numpy as np
import pytest

import nffrt
from helpers import shared, shared_path

# flip-evaluator's means and nffrt's agree within this (the bound; they
# agree within 1e-5 in practice, their maps within 1e-7 per pixel).
AGREEMENT = 1e-3


@pytest.fixture(scope="module")
def flip():
    """NVIDIA's flip_evaluator module, or a skip (a failure under CI)."""
    try:
        import flip_evaluator
    except ImportError:
        reason = "flip-evaluator is not installed (pip install flip-evaluator)"
        if os.environ.get("NFFRT_REQUIRE_FLIP") == "1":
            pytest.fail(f"NFFRT_REQUIRE_FLIP=1 but {reason}")
        pytest.skip(reason)
    return flip_evaluator


def blurred(image: np.ndarray, radius: int = 2) -> np.ndarray:
    """A box blur of ``(2 radius + 1)²`` pixels, edges repeated."""
    padded = np.pad(image.astype(np.float64), ((radius, radius), (radius, radius), (0, 0)), mode="edge")
    h, w = image.shape[:2]
    total = sum(
        padded[dy : dy + h, dx : dx + w] for dy in range(2 * radius + 1) for dx in range(2 * radius + 1)
    )
    return total / (2 * radius + 1) ** 2


def to_8bit(linear: np.ndarray) -> np.ndarray:
    """The bytes nffrt writes for linear values: clamped, times 255, rounded."""
    return np.round(np.clip(linear, 0.0, 1.0) * 255.0).astype(np.uint8)


def cli_diff(nffrt_bin: str, test: Path, ref: Path, *flags: str) -> dict:
    out = subprocess.run([nffrt_bin, "diff", str(test), str(ref), "--json", *flags], capture_output=True)
    assert out.returncode == 0, out.stderr.decode()
    return json.loads(out.stdout)


def nvidia(flip, reference, test, dynamic_range: str) -> float:
    """flip-evaluator's mean FLIP error (8-bit arrays as floats in [0, 1], sRGB)."""
    if isinstance(reference, np.ndarray):
        as_float = lambda a: np.ascontiguousarray(a / 255.0 if a.dtype == np.uint8 else a, dtype=np.float32)
        reference, test = as_float(reference), as_float(test)
    else:
        reference, test = str(reference), str(test)
    _, mean, _ = flip.evaluate(reference, test, dynamic_range, applyMagma=False)
    return float(mean)


def test_course_picture_against_our_render_agrees_with_nvidia(flip, tmp_path, nffrt_bin) -> None:
    """LDR: the course's Whitted picture of balls_low against nffrt's render of it,
    files and arrays; HDR: the render's linear values against a 4-spp render."""
    reference = shared_path("reference/p3f/balls_low-whitted.png")
    scene = nffrt.load(shared("p3f", "2025", "balls_low.p3f"))
    ours = scene.render()
    nffrt.save(ours, tmp_path / "ours.png")
    theirs = nvidia(flip, reference, tmp_path / "ours.png", "LDR")
    from_cli = cli_diff(nffrt_bin, tmp_path / "ours.png", reference)
    assert from_cli["flip"]["mode"] == "ldr"
    value = from_cli["results"][0]["value"]
    assert abs(value - theirs) < AGREEMENT, (value, theirs)
    assert 0.03 < theirs < 0.2, "the render is close to the course's picture, not equal"
    assert abs(nffrt.diff(tmp_path / "ours.png", reference) - value) < 1e-12
    # HDR: EXR files, as flip-evaluator reads them itself.
    nffrt.save(ours, tmp_path / "ours.exr")
    nffrt.save(scene.render(spp=4), tmp_path / "spp4.exr")
    theirs = nvidia(flip, tmp_path / "spp4.exr", tmp_path / "ours.exr", "HDR")
    from_cli = cli_diff(nffrt_bin, tmp_path / "ours.exr", tmp_path / "spp4.exr")
    assert from_cli["flip"]["mode"] == "hdr"
    assert abs(from_cli["results"][0]["value"] - theirs) < AGREEMENT, (from_cli, theirs)
    assert theirs > 0.001


def test_pictures_against_blurred_copies_agree_with_nvidia(flip, tmp_path, nffrt_bin) -> None:
    """A generated scene (no ../shared needed) against a 5x5 box blur of itself:
    8-bit (LDR-FLIP) and linear floats brightened past 1 (HDR-FLIP, several
    exposures), as arrays and as files through the command line."""
    image = nffrt.parse(nffrt.gen("mount", size=2)).render(width=160, height=120)
    sharp, soft = to_8bit(image), to_8bit(blurred(image))
    theirs = nvidia(flip, sharp, soft, "LDR")
    assert 0.02 < theirs < 0.5, theirs
    assert abs(nffrt.diff(soft, sharp) - theirs) < AGREEMENT
    nffrt.save(sharp / 255.0, tmp_path / "sharp.png")
    nffrt.save(soft / 255.0, tmp_path / "soft.png")
    value = cli_diff(nffrt_bin, tmp_path / "soft.png", tmp_path / "sharp.png")["results"][0]["value"]
    assert abs(value - theirs) < AGREEMENT
    # HDR: a range of 16 (bright highlights) and a mostly black picture.
    bright = (image * 16.0).astype(np.float32)
    soft_bright = blurred(bright).astype(np.float32)
    theirs = nvidia(flip, bright, soft_bright, "HDR")
    assert abs(nffrt.diff(soft_bright, bright) - theirs) < AGREEMENT
    dark = bright.copy()
    dark[: 3 * dark.shape[0] // 4] = 0.0  # the median luminance is 0
    soft_dark = blurred(dark).astype(np.float32)
    theirs = nvidia(flip, dark, soft_dark, "HDR")
    nffrt.save(dark, tmp_path / "dark.pfm")
    nffrt.save(soft_dark, tmp_path / "soft_dark.pfm")
    from_cli = cli_diff(nffrt_bin, tmp_path / "soft_dark.pfm", tmp_path / "dark.pfm")
    assert abs(from_cli["results"][0]["value"] - theirs) < AGREEMENT, (from_cli, theirs)
    assert from_cli["flip"]["exposures"] > 20, "a median of 0 spans many exposures"


def test_diff_takes_paths_or_arrays_and_every_metric(tmp_path, nffrt_bin) -> None:
    """The same numbers from paths and arrays, and from Python and the command
    line; the map's mean is FLIP's value; MSE by hand."""
    a = np.zeros((4, 6, 3), np.uint8)
    b = a.copy()
    b[1, 2] = [255, 0, 0]
    nffrt.save(a / 255.0, tmp_path / "a.png")
    nffrt.save(b / 255.0, tmp_path / "b.png")
    # One channel of 72 is 1 off: MSE 1/72, PSNR 10 log10(72).
    assert nffrt.diff(b, a, metric="mse") == pytest.approx(1 / 72, rel=1e-6)
    assert nffrt.diff(b, a, metric="psnr") == pytest.approx(10 * np.log10(72), rel=1e-6)
    assert nffrt.diff(a, a, metric="psnr") == float("inf")
    for metric in ["flip", "mse", "rmse", "relmse", "mae", "psnr"]:
        from_arrays = nffrt.diff(b, a, metric=metric)
        assert nffrt.diff(tmp_path / "b.png", str(tmp_path / "a.png"), metric) == from_arrays
        cli = cli_diff(nffrt_bin, tmp_path / "b.png", tmp_path / "a.png", "--metric", metric)
        assert cli["results"][0]["value"] == pytest.approx(from_arrays, rel=1e-12), metric
    value, error_map = nffrt.diff(b, a, map=True)
    assert error_map.shape == (4, 6) and error_map.dtype == np.float32
    assert float(error_map.mean(dtype=np.float64)) == pytest.approx(value, rel=1e-6)
    assert error_map[1, 2] == error_map.max() > 0.5


def test_diff_errors_say_what_is_wrong(tmp_path) -> None:
    a = np.zeros((4, 6, 3), np.uint8)
    with pytest.raises(ValueError, match="4x4 and the reference 6x4"):
        nffrt.diff(np.zeros((4, 4, 3), np.uint8), a)
    with pytest.raises(ValueError, match="a float picture and the reference an 8-bit picture"):
        nffrt.diff(np.zeros((4, 6, 3), np.float32), a)
    with pytest.raises(ValueError, match="dtype int64"):
        nffrt.diff(np.zeros((4, 6, 3), np.int64), a)
    with pytest.raises(ValueError, match='no metric "ssim"'):
        nffrt.diff(a, a, metric="ssim")
    with pytest.raises(ValueError, match=r"shape \(H, W, 3\)"):
        nffrt.diff(np.zeros((4, 6), np.uint8), a)
    with pytest.raises(ValueError, match="not a number FLIP can compare"):
        nffrt.diff(np.full((4, 6, 3), np.nan, np.float32), np.zeros((4, 6, 3), np.float32))
    with pytest.raises(FileNotFoundError):
        nffrt.diff(tmp_path / "missing.png", a)
    (tmp_path / "bad.png").write_bytes(b"not a png")
    with pytest.raises(ValueError, match="bad.png: not a usable picture"):
        nffrt.diff(tmp_path / "bad.png", a)
