"""AFF scenes from Python: ``Scene.frames``, ``render(frame=..)`` and
``render(time=..)`` give the arrays ``nffrt render --frame``/``--time`` writes,
bit for bit; a keyed sphere moves between frames; bad requests raise
``ValueError``; ``nffrt.dask.render_frames`` gives the local frames byte for byte."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

import nffrt
from helpers import read_pfm, run_cli, shared

# A white ball of radius 0.2 keyed along x (keys x = 0, 0, 2, 2 at times -1, 0, 1,
# 2), four frames over t = 0..1, shown by the ambient light on black.
BALL = (
    "v from 0 0 10 at 0 0 0 up 0 1 0 angle 28.072486935852957 hither 1 resolution 41 41\n"
    "b 0 0 0\nam 1 1 1\nfm 1 1 1  0 0 0  0 0 0  1 0 1\na 0 1 4\n"
    "x ball { s 0 0 0 0.2 }\n"
    "k ball { transl 4  -1 0 0 0 0 0 0   0 0 0 0 0 0 0   1 2 0 0 0 0 0   2 2 0 0 0 0 0 }\n"
)


def ball_file(tmp_path: Path) -> Path:
    path = tmp_path / "ball.aff"
    path.write_text(BALL)
    return path


def test_frames_and_times_are_the_clis(nffrt_bin: str, tmp_path: Path) -> None:
    path = ball_file(tmp_path)
    scene = nffrt.load(path)
    assert scene.format == "aff" and scene.frames == 4
    assert scene.frame_time(2) == 0.5
    for flags, kwargs in [(["--frame", "1"], {"frame": 1}), (["--time", "0.75"], {"time": 0.75}), ([], {})]:
        out = tmp_path / "cli.pfm"
        run_cli(nffrt_bin, "render", str(path), "-q", "-o", str(out), *flags)
        assert scene.render(**kwargs).tobytes() == read_pfm(out).tobytes(), flags
    # Parsed text (format="aff") renders the same frames; the ball moves right.
    text = nffrt.parse(BALL, format="aff")
    frames = [text.render(frame=n) for n in range(4)]
    assert frames[1].tobytes() == scene.render(frame=1).tobytes()
    columns = [np.argwhere(f[:, :, 0] > 0.5)[:, 1].mean() for f in frames]
    assert columns == sorted(columns) and columns[3] - columns[0] > 10


def test_bad_frame_requests_raise(tmp_path: Path) -> None:
    scene = nffrt.load(ball_file(tmp_path))
    with pytest.raises(ValueError, match="has 4 frames"):
        scene.render(frame=4)
    with pytest.raises(ValueError, match="not both"):
        scene.render(frame=1, time=0.5)
    with pytest.raises(ValueError, match="finite"):
        scene.render(time=float("nan"))
    still = nffrt.parse("v from 0 0 5 at 0 0 0 up 0 1 0 angle 40 hither 1 resolution 4 4\ns 0 0 0 1\n")
    assert still.frames is None
    with pytest.raises(ValueError, match="for AFF scenes"):
        still.render(frame=0)


def test_museum_frames_differ() -> None:
    scene = nffrt.load(shared("bart", "museum", "aff", "museum5.aff"))
    assert scene.frames == 300
    a, b = scene.render(width=64, frame=0), scene.render(width=64, frame=150)
    assert a.shape == (48, 64, 3) and a.std() > 0.05
    assert a.tobytes() != b.tobytes()


def test_dask_render_frames_gives_the_local_frames(tmp_path: Path) -> None:
    distributed = pytest.importorskip("distributed", reason="dask[distributed] is not installed")
    import nffrt.dask

    path = ball_file(tmp_path)
    scene = nffrt.load(path)
    cluster = distributed.LocalCluster(n_workers=2, threads_per_worker=1, processes=True, dashboard_address=":0")
    with distributed.Client(cluster) as client:
        remote = nffrt.dask.render_frames(path, client, frames=[3, 0, 2], width=21)
        everything = nffrt.dask.render_frames(scene, client)
        with pytest.raises(ValueError, match="does not move"):
            nffrt.dask.render_frames("v from 0 0 5 at 0 0 0 up 0 1 0 angle 40 hither 1 resolution 4 4\n", client)
    cluster.close()
    for n, got in zip([3, 0, 2], remote):
        assert got.tobytes() == scene.render(frame=n, width=21).tobytes(), n
    assert len(everything) == 4
    assert all(got.tobytes() == scene.render(frame=n).tobytes() for n, got in enumerate(everything))
