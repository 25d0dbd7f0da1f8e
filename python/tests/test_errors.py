"""Bad input through Python: every malformed scene of the project's corpus is a
``SceneError`` at the place its header promises, and no argument, however wrong,
gets past an ordinary exception (a Rust panic would surface as
``pyo3_runtime.PanicException``, a ``BaseException`` these tests do not catch)."""

from __future__ import annotations

import math
import os
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

import nffrt
from helpers import DATA, header_values

BAD = sorted((DATA / "bad").glob("*.nff")) + sorted((DATA / "bad").glob("*.p3f"))
# What every bad call may raise: never PanicException, never a crash.
ORDINARY = (ValueError, TypeError, OverflowError, OSError)


def expectation(path: Path) -> tuple[int, int, str]:
    [value] = header_values(path, "expect")
    pos, text = value.split(" ", 1)
    line, column = pos.split(":")
    return int(line), int(column), text


def test_the_corpus_is_there() -> None:
    assert len(BAD) >= 40


@pytest.mark.parametrize("path", BAD, ids=lambda p: p.name)
def test_bad_file_is_a_scene_error_with_its_location(path: Path) -> None:
    line, column, text = expectation(path)
    with pytest.raises(nffrt.SceneError) as caught:
        nffrt.load(path)
    e = caught.value
    assert isinstance(e, ValueError)
    assert (e.path, e.line, e.column) == (str(path), line, column)
    assert str(e) == f"{path}:{line}:{column}: {e.message}"
    assert text in e.message


@pytest.mark.parametrize("path", BAD, ids=lambda p: p.name)
def test_bad_text_is_a_scene_error_with_its_location(path: Path) -> None:
    line, column, _ = expectation(path)
    fmt = "p3f" if path.suffix == ".p3f" else "nff"
    with pytest.raises(nffrt.SceneError) as caught:
        nffrt.parse(path.read_bytes(), format=fmt)
    e = caught.value
    assert (e.path, e.line, e.column) == (None, line, column)
    assert str(e).startswith(f"<string>:{line}:{column}: ")


def test_scene_error_survives_pickling() -> None:
    """Dask sends a worker's exceptions back to the client pickled."""
    import pickle

    with pytest.raises(nffrt.SceneError) as caught:
        nffrt.parse("s 1 2 x 4\n")
    back = pickle.loads(pickle.dumps(caught.value))
    assert type(back) is nffrt.SceneError
    assert (back.path, back.line, back.column) == (None, 1, 7)
    assert back.message == caught.value.message and str(back) == str(caught.value)


def test_unreadable_files_are_os_errors(tmp_path: Path) -> None:
    with pytest.raises(FileNotFoundError) as caught:
        nffrt.load(tmp_path / "missing.nff")
    assert caught.value.filename == str(tmp_path / "missing.nff")
    with pytest.raises(IsADirectoryError):
        nffrt.load(tmp_path)
    # A P3F file whose skybox folder is missing: an OSError naming it.
    (tmp_path / "sky.p3f").write_text("env nowhere\ns 0 0 0 1\n")
    with pytest.raises(OSError, match="nowhere"):
        nffrt.load(tmp_path / "sky.p3f")


def test_unknown_kernels_in_nffrt_simd_are_a_value_error() -> None:
    # The variable is read once per process: a fresh interpreter for each value.
    code = (
        "import nffrt\n"
        "try:\n"
        "    nffrt.parse('s 0 0 0 1\\n')\n"
        "except ValueError as e:\n"
        "    print('ValueError:', e)\n"
        "else:\n"
        "    print('parsed')\n"
    )
    def run(value: str) -> str:
        env = dict(os.environ, NFFRT_SIMD=value)
        done = subprocess.run([sys.executable, "-c", code], env=env, capture_output=True, text=True, check=True)
        return done.stdout.strip()
    assert run("avx512") == (
        "ValueError: NFFRT_SIMD=avx512: unknown kernels; use auto, avx2 or portable "
        "(nffrt's widest kernels are AVX2)"
    )
    assert run("portable") == "parsed"


SCENE = "v from 0 0 5 at 0 0 0 up 0 1 0 angle 40 hither 1 resolution 16 12\nl 0 0 9\ns 0 0 0 1\n"


@pytest.mark.parametrize(
    "kwargs",
    [
        {"width": 0},
        {"height": -3},
        {"width": 40000},
        {"width": 2**40},
        {"width": 8192 * 2, "height": 8192 * 2},
        {"max_depth": 0},
        {"max_depth": 65},
        {"max_depth": 10**6},
        {"spp": 0},
        {"spp": 5000},
        {"spp": -1},
        {"aperture": math.nan},
        {"aperture": -1.0},
        {"focal": 0.0},
        {"focal": math.inf},
        {"region": (0, 0, 17, 12)},
        {"region": (5, 0, 5, 12)},
        {"region": (0, 0, 1)},
        {"region": "0,0,4,4"},
        {"threads": 0},
        {"threads": 100000},
        {"width": "wide"},
        {"spd": True, "spp": 2},
    ],
)
def test_bad_render_arguments_raise_ordinary_exceptions(kwargs: dict) -> None:
    with pytest.raises(ORDINARY):
        nffrt.parse(SCENE).render(**kwargs)


@pytest.mark.parametrize(
    "call",
    [
        lambda: nffrt.parse(12),
        lambda: nffrt.parse("s 0 0 0 1", format="obj"),
        lambda: nffrt.parse("\udcff"),
        lambda: nffrt.load("x.nff", format="pov"),
        lambda: nffrt.load(None),
        lambda: nffrt.gen("balls", size=0),
        lambda: nffrt.gen("balls", size=-1),
        lambda: nffrt.gen(""),
        lambda: nffrt.tiles(0, 10, 1),
        lambda: nffrt.tiles(10, 10, 0),
        lambda: nffrt.tiles(10, 10, -1),
        lambda: nffrt.save(np.zeros((2, 2, 3)), "x.gif"),
        lambda: nffrt.save(np.zeros((2, 2, 4)), "x.png"),
        lambda: nffrt.save(np.zeros((0, 2, 3)), "x.png"),
        lambda: nffrt.save(np.zeros((2, 3)), "x.png"),
        lambda: nffrt.save("not an image", "x.png"),
        lambda: nffrt.save(np.zeros((2, 2, 3)), "/nonexistent-dir/x.png"),
        lambda: nffrt.to_png([[1, 2], [3]]),
        lambda: nffrt.merge([("region", np.zeros((1, 1, 3)))]),
        lambda: nffrt.merge([((0, 0, 1, 1),)]),
    ],
)
def test_bad_calls_raise_ordinary_exceptions(call) -> None:
    with pytest.raises(ORDINARY):
        call()


def test_non_finite_pixels_are_saved_not_refused(tmp_path: Path) -> None:
    image = np.full((2, 2, 3), np.nan, dtype=np.float32)
    image[0, 0] = np.inf
    nffrt.save(image, tmp_path / "x.png")
    nffrt.save(image, tmp_path / "x.pfm")


# A P3F scene (its `bclr` and its eleven-number material are P3F's alone).
P3F_TEXT = (
    "bclr 0.1 0.1 0.1\n"
    "v from 0 0 5 at 0 0 0 up 0 1 0 angle 40 hither 1 resolution 16 12\n"
    "l 0 0 10\n"
    "f 1 0 0 1 1 1 1 0.5 10 0 1\n"
    "s 0 0 0 1\n"
)


def test_p3f_text_read_as_nff_says_to_pass_its_format() -> None:
    with pytest.raises(nffrt.SceneError) as caught:
        nffrt.parse(P3F_TEXT)
    e = caught.value
    assert (e.line, e.column) == (1, 1)
    assert e.message == 'unknown keyword "bclr" (the scene reads as P3F: pass format="p3f")'
    assert nffrt.parse(P3F_TEXT, format="p3f").format == "p3f-2019"
    # An NFF error that is not P3F either gets no such hint.
    with pytest.raises(nffrt.SceneError) as caught:
        nffrt.parse("s 0 0 0\n")
    assert "P3F" not in caught.value.message


def test_text_parsed_as_a_file_names_it_and_takes_its_format(tmp_path: Path) -> None:
    path = tmp_path / "scene.p3f"
    scene = nffrt.parse(P3F_TEXT, path=path)
    assert (scene.format, scene.path, scene.text) == ("p3f-2019", str(path), P3F_TEXT)
    assert nffrt.load(DATA / "ok" / "tabs.nff").text is None
    with pytest.raises(nffrt.SceneError) as caught:
        nffrt.parse(P3F_TEXT.replace("s 0 0 0 1", "s 0 0 zero 1"), path=path)
    assert str(caught.value).startswith(f"{path}:5:7: ")
