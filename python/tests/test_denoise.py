"""``Scene.render(denoise=...)``: the same picture as ``nffrt render --denoise``
(an AFF scene's frames too),
closer to a converged render than the noisy one; bad arguments and a missing
library said clearly.

The checks that need Open Image Denoise skip, saying so, without it (``pip install
pyoidn``); ``.ci/run`` installs it and sets ``NFFRT_REQUIRE_OIDN=1``, which makes
such a skip a failure."""

from __future__ import annotations

import os
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

import nffrt
from helpers import REPO, read_pfm, run_cli

CORNELL = REPO / "examples" / "cornell.p3f"


@pytest.fixture(scope="module")
def room():
    return nffrt.load(str(CORNELL))


@pytest.fixture(scope="module")
def denoiser(room):
    """Skips (fails under NFFRT_REQUIRE_OIDN=1) when the library is not installed."""
    try:
        room.render(width=8, height=8, spp=2, denoise=True)
    except OSError as e:
        reason = "Open Image Denoise is not installed (pip install pyoidn, or NFFRT_OIDN)"
        if os.environ.get("NFFRT_REQUIRE_OIDN") == "1":
            pytest.fail(f"NFFRT_REQUIRE_OIDN=1 but {reason}: {e}")
        pytest.skip(reason)


def as_shown(linear: np.ndarray) -> np.ndarray:
    """The 8-bit levels, over 255, of the course's gamma 2.2 (how the room is shown)."""
    levels = np.floor(np.clip(linear, 0, 1) ** (1 / 2.2) * 255 + 0.5)
    return levels / 255


def rmse(a: np.ndarray, b: np.ndarray) -> float:
    return float(np.sqrt(np.mean((a.astype(np.float64) - b) ** 2)))


def test_the_denoised_picture_is_the_command_lines(room, denoiser, nffrt_bin, tmp_path: Path):
    out = tmp_path / "d.pfm"
    size = ["--width", "48", "--height", "48", "--spp", "8"]
    run_cli(nffrt_bin, "render", str(CORNELL), *size, "--denoise", "-q", "-o", str(out))
    cli = read_pfm(out)
    ours = room.render(width=48, height=48, spp=8, denoise=True)
    assert np.array_equal(ours, cli)


def test_denoising_brings_the_room_closer_to_the_converged_one(room, denoiser):
    reference = as_shown(room.render(width=48, height=48, spp=1024))
    noisy = rmse(as_shown(room.render(width=48, height=48, spp=16)), reference)
    for quality in (True, "fast"):
        denoised = rmse(as_shown(room.render(width=48, height=48, spp=16, denoise=quality)), reference)
        assert denoised < 0.5 * noisy, (quality, denoised, noisy)


def test_bad_requests_are_value_errors(room):
    with pytest.raises(ValueError, match="qualities are 'fast', 'balanced' and 'high'"):
        room.render(width=8, height=8, spp=2, denoise="medium")
    with pytest.raises(ValueError, match="not with region"):
        room.render(width=8, height=8, spp=2, denoise=True, region=(0, 0, 4, 4))
    whitted = nffrt.parse(nffrt.gen("tetra", size=1))
    with pytest.raises(ValueError, match="no noise to remove"):
        whitted.render(width=8, height=8, denoise=True)
    # False and None ask for nothing.
    assert np.array_equal(room.render(width=8, height=8, spp=2, denoise=False), room.render(width=8, height=8, spp=2))


def test_a_missing_library_is_an_os_error_saying_how_to_get_it():
    code = (
        "import nffrt\n"
        f"scene = nffrt.load({str(CORNELL)!r})\n"
        "try:\n"
        "    scene.render(width=8, height=8, spp=2, denoise=True)\n"
        "except OSError as e:\n"
        "    print(e)\n"
    )
    env = {**os.environ, "NFFRT_OIDN": "/nowhere/libOpenImageDenoise.so.2"}
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, env=env, text=True)
    assert out.returncode == 0, out.stderr
    assert "/nowhere/libOpenImageDenoise.so.2 (from NFFRT_OIDN)" in out.stdout, out.stdout
    assert "pip install pyoidn" in out.stdout, out.stdout


# A white ball keyed along x over four frames (python/tests/test_aff.py's), lit by
# the ambient light on black.
BALL = (
    "v from 0 0 10 at 0 0 0 up 0 1 0 angle 28.072486935852957 hither 1 resolution 41 41\n"
    "b 0 0 0\nam 1 1 1\nfm 1 1 1  0 0 0  0 0 0  1 0 1\na 0 1 4\n"
    "x ball { s 0 0 0 0.2 }\n"
    "k ball { transl 4  -1 0 0 0 0 0 0   0 0 0 0 0 0 0   1 2 0 0 0 0 0   2 2 0 0 0 0 0 }\n"
)


def test_a_frame_is_denoised_as_the_command_line_denoises_it(denoiser, nffrt_bin, tmp_path: Path):
    path = tmp_path / "ball.aff"
    path.write_text(BALL)
    scene = nffrt.load(str(path))
    for flags, kwargs in [(["--frame", "2"], {"frame": 2}), (["--time", "0.75"], {"time": 0.75})]:
        out = tmp_path / "d.pfm"
        run_cli(nffrt_bin, "render", str(path), "--spp", "4", "--denoise", *flags, "-q", "-o", str(out))
        ours = scene.render(spp=4, denoise=True, **kwargs)
        assert np.array_equal(ours, read_pfm(out)), flags
    # Frame 2's denoised picture is its own, not frame 0's.
    assert not np.array_equal(scene.render(spp=4, denoise=True, frame=2), scene.render(spp=4, denoise=True))
