"""Rendering on a Dask distributed cluster: one task per tile, merged into the
array a local render gives, byte for byte.

>>> from distributed import Client
>>> import nffrt.dask
>>> client = Client("tcp://scheduler:8786")
>>> image = nffrt.dask.render("mount.nff", client, tiles=16, spp=16)

``scene`` is scene text (``str`` with a line break, or ``bytes``), sent to the
workers once, or a path (``os.PathLike``, or a ``str`` without a line break),
which every worker opens itself: it must be readable there at the same absolute
path (a shared filesystem, as for the Slurm recipe in the README), and so must the
skybox a P3F file names. Each worker process loads a scene once and keeps it for
the next tiles of the same scene. Each task renders one band of rows on one thread
unless ``threads`` says otherwise: the workers' threads are the parallelism.
"""

from __future__ import annotations

import hashlib
import os
import threading
from collections import OrderedDict
from typing import Any, Optional, Union

import numpy as np

from . import Scene, load, merge, parse, tiles as split

# A worker keeps this many prepared scenes (each with its BVH), most recent first.
_KEEP = 4
_cache: "OrderedDict[tuple, Scene]" = OrderedDict()
_cache_lock = threading.Lock()

SceneSource = Union[str, bytes, "os.PathLike[str]"]


def _is_text(scene: SceneSource) -> bool:
    return isinstance(scene, bytes) or (isinstance(scene, str) and "\n" in scene)


def _prepared(key: tuple, scene: SceneSource, format: Optional[str]) -> Scene:
    """The worker's prepared scene for ``key``, loaded or parsed on first use."""
    with _cache_lock:
        if key in _cache:
            _cache.move_to_end(key)
            return _cache[key]
    if key[0] == "text":
        prepared = parse(scene, format or "nff")
    else:
        prepared = load(scene, format)
    with _cache_lock:
        _cache[key] = prepared
        while len(_cache) > _KEEP:
            _cache.popitem(last=False)
    return prepared


def _size(
    key: tuple, scene: SceneSource, format: Optional[str], width: Optional[int], height: Optional[int]
) -> tuple[int, int]:
    """Task: the image size ``render(width=width, height=height)`` makes."""
    return _prepared(key, scene, format).image_size(width, height)


def _render_tile(
    key: tuple, scene: SceneSource, format: Optional[str], region: tuple, options: dict
) -> np.ndarray:
    """Task: one region of the full image."""
    return _prepared(key, scene, format).render(region=region, **options)


def render(
    scene: SceneSource,
    client: Any,
    tiles: Optional[int] = None,
    format: Optional[str] = None,
    **render_options: Any,
) -> np.ndarray:
    """Renders ``scene`` on the cluster behind ``client`` (a ``distributed.Client``)
    in ``tiles`` bands of rows, one task each (default: four per worker thread),
    and merges them: the ``float32`` array ``Scene.render(**render_options)``
    gives, byte for byte.

    ``render_options`` are those of ``Scene.render`` but ``region``; ``threads``
    (per task) defaults to 1. ``format`` is ``"nff"`` or ``"p3f"`` (default: NFF
    for text, by the extension for a path). Errors raised on a worker (``SceneError``,
    ``OSError``, ``ValueError``) are raised here.
    """
    if "region" in render_options:
        raise ValueError("nffrt.dask.render renders the whole image: no region")
    options = {"threads": 1, **render_options}
    if _is_text(scene):
        data = scene.encode() if isinstance(scene, str) else bytes(scene)
        key: tuple = ("text", hashlib.sha256(data).hexdigest(), format)
        source: Any = client.scatter(data, broadcast=True, hash=True)
    else:
        path = os.path.abspath(os.fspath(scene))
        stat = os.stat(path)
        key = ("path", path, format, stat.st_mtime_ns, stat.st_size)
        source = path
    width, height = options.get("width"), options.get("height")
    if width is None or height is None:
        width, height = client.submit(_size, key, source, format, width, height, pure=False).result()
    if tiles is None:
        threads = sum(client.nthreads().values()) or 1
        tiles = min(4 * threads, int(height))
    regions = split(int(width), int(height), tiles)
    opts = {**options, "width": width, "height": height}
    futures = [
        client.submit(_render_tile, key, source, format, tuple(r), opts, pure=False) for r in regions
    ]
    arrays = client.gather(futures)
    return merge(zip(regions, arrays))
