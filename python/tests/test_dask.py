"""``nffrt.dask.render`` on a ``LocalCluster`` of two worker processes gives the
array a local render gives, byte for byte: with several samples per pixel, the
SPD protocol, uneven bands, scene text and scene files."""

from __future__ import annotations

import os

import numpy as np
import pytest

import nffrt
from helpers import shared

distributed = pytest.importorskip("distributed", reason="dask[distributed] is not installed")
import nffrt.dask  # noqa: E402  (after the skip)


@pytest.fixture(scope="module")
def client():
    cluster = distributed.LocalCluster(
        n_workers=2, threads_per_worker=1, processes=True, dashboard_address=":0"
    )
    with distributed.Client(cluster) as c:
        yield c
    cluster.close()


def test_text_scene_with_spp_and_uneven_bands(client) -> None:
    text = nffrt.gen("balls", size=2)
    opts = {"width": 61, "height": 47, "spp": 4}
    local = nffrt.parse(text).render(**opts)
    # 47 rows in 7 bands: 6 or 7 rows each.
    remote = nffrt.dask.render(text, client, tiles=7, **opts)
    assert remote.dtype == np.float32 and remote.shape == (47, 61, 3)
    assert remote.tobytes() == local.tobytes()
    # The work ran in the worker processes, which kept the scene for later tiles.
    cached = client.run(lambda: (os.getpid(), len(nffrt.dask._cache)))
    assert all(pid != os.getpid() for pid, _ in cached.values())
    assert sum(n for _, n in cached.values()) >= 1


def test_scene_file_at_its_own_resolution_with_the_spd_protocol(client) -> None:
    path = shared("spd", "tetra.nff")
    local = nffrt.load(path).render(spd=True)
    remote = nffrt.dask.render(path, client, tiles=5, spd=True)
    assert remote.shape == (512, 512, 3)
    assert remote.tobytes() == local.tobytes()


def test_p3f_file_with_a_skybox_lens_and_default_tiles(client) -> None:
    path = shared("p3f", "2019", "dof.p3f")
    opts = {"width": 50, "spp": 3, "max_depth": 3}  # the height follows the file's aspect
    local = nffrt.load(path).render(**opts)
    remote = nffrt.dask.render(str(path), client, **opts)
    assert remote.tobytes() == local.tobytes()


def test_worker_errors_come_back_as_themselves(client) -> None:
    with pytest.raises(nffrt.SceneError) as caught:
        nffrt.dask.render("v from 0 0 5\nat 0 0 0 up x\n", client, tiles=2)
    assert (caught.value.line, caught.value.path) == (2, None)
    with pytest.raises(ValueError, match="max depth"):
        nffrt.dask.render(nffrt.gen("tetra", size=1), client, tiles=2, max_depth=0)
    with pytest.raises(ValueError, match="no region"):
        nffrt.dask.render(nffrt.gen("tetra", size=1), client, region=(0, 0, 1, 1))


def test_a_scene_object_travels_as_its_text(client, tmp_path) -> None:
    text = nffrt.gen("tetra", size=2)
    opts = {"width": 40, "height": 30, "spp": 2}
    # Parsed as a file no worker (nor anyone) can open: its text is what travels.
    parsed = nffrt.parse(text, path="/nonexistent/folder/tetra.nff")
    local = parsed.render(**opts)
    assert nffrt.dask.render(parsed, client, tiles=3, **opts).tobytes() == local.tobytes()
    # Loaded from a file: the file is read where the client runs.
    path = tmp_path / "tetra.nff"
    path.write_text(text)
    loaded = nffrt.load(path)
    assert nffrt.dask.render(loaded, client, tiles=3, **opts).tobytes() == local.tobytes()
    with pytest.raises(ValueError, match="read as 'nff'"):
        nffrt.dask.render(loaded, client, format="p3f")


def test_p3f_text_needs_its_format(client) -> None:
    from test_errors import P3F_TEXT

    local = nffrt.parse(P3F_TEXT, format="p3f").render()
    assert nffrt.dask.render(P3F_TEXT, client, tiles=2, format="p3f").tobytes() == local.tobytes()
    assert nffrt.dask.render(nffrt.parse(P3F_TEXT, format="p3f"), client, tiles=2).tobytes() == local.tobytes()
    with pytest.raises(nffrt.SceneError, match='pass format="p3f"'):
        nffrt.dask.render(P3F_TEXT, client, tiles=2)


# A small P3F room for the path tracer: an emissive sphere (the 14-number `f`'s
# last three) above a diffuse floor and a glass ball.
PATH_TEXT = """bclr 0 0 0
v
from 0 -5 2
at 0 0 0.5
up 0 0 1
angle 45
hither 1
resolution 40 30
f 0.8 0.8 0.8 1 0 0 0 0 10 0 1
pl 0 0 0 1 0 0 0 1 0
f 1 1 1 0 1 1 1 0 10 1 1.5
s 0.6 0 0.6 0.6
f 1 1 1 1 0 0 0 0 10 0 1 4 4 3
s -0.8 0.5 2 0.4
"""


def test_path_tracing_tiles_and_threads_agree_byte_for_byte(client) -> None:
    scene = nffrt.parse(PATH_TEXT, format="p3f")
    opts = {"integrator": "path", "spp": 8, "max_depth": 6}
    local = scene.render(**opts)
    assert local.shape == (30, 40, 3) and local.mean() > 0.01
    # Light comes only from the emissive sphere: Whitted's picture differs.
    assert local.tobytes() != scene.render(spp=8).tobytes()
    assert scene.render(threads=1, **opts).tobytes() == local.tobytes()
    remote = nffrt.dask.render(PATH_TEXT, client, tiles=3, format="p3f", **opts)
    assert remote.tobytes() == local.tobytes()
