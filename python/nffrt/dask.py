"""Rendering on a Dask distributed cluster: one task per tile, merged into the
array a local render gives, byte for byte; or, for an animated (AFF) scene, one
task per frame (``render_frames``).

>>> from distributed import Client
>>> import nffrt, nffrt.dask
>>> client = Client("tcp://scheduler:8786")
>>> scene = nffrt.load("mount.nff")
>>> image = nffrt.dask.render(scene, client, tiles=16, spp=16)

``scene`` is a ``Scene``, a path (``os.PathLike``, or a ``str`` without a line
break) or scene text (``str`` with a line break, or ``bytes``). Whichever it is,
the scene's text is what travels: read where the client runs (a ``Scene`` parsed
from text sends that text; one loaded from a file, or a path, sends the file's
bytes as they are when ``render`` is called) and sent to the workers once, so the
workers need no copy of the scene file. Only a P3F skybox is read by the workers
themselves, from the scene file's folder at the same absolute path (a shared
filesystem, as for the Slurm recipe in docs/command-line.md), and so are an AFF
scene's includes and textures. Each worker process
parses a scene once and keeps it for the next tiles of the same scene. Each task
renders one band of rows on one thread unless ``threads`` says otherwise: the
workers' threads are the parallelism.
"""

from __future__ import annotations

import hashlib
import os
import threading
from collections import OrderedDict
from typing import Any, Optional, Union

import numpy as np

from . import Scene, merge, parse, tiles as split

# A worker keeps this many prepared scenes (each with its BVH), most recent first.
_KEEP = 4
_cache: "OrderedDict[tuple, Scene]" = OrderedDict()
_cache_lock = threading.Lock()

SceneSource = Union[Scene, str, bytes, "os.PathLike[str]"]


def _is_text(scene: SceneSource) -> bool:
    return isinstance(scene, bytes) or (isinstance(scene, str) and "\n" in scene)


def _read(path: str) -> bytes:
    with open(path, "rb") as f:
        return f.read()


def _source(scene: SceneSource, format: Optional[str]) -> tuple[bytes, Optional[str], Optional[str]]:
    """What the workers parse: the scene's bytes, its format (``None``: by the
    path's extension) and the absolute path of the file they are (``None`` for text)."""
    if isinstance(scene, Scene):
        # "p3f-2019" and "p3f-2025" are dialects of "p3f".
        own = scene.format.split("-")[0]
        if format is not None and format.lower() != own:
            raise ValueError(f"format={format!r}, but the Scene was read as {own!r}")
        path = os.path.abspath(scene.path) if scene.path is not None else None
        text = scene.text
        if text is None:
            return _read(path), own, path
        return (text.encode() if isinstance(text, str) else bytes(text)), own, path
    if _is_text(scene):
        data = scene.encode() if isinstance(scene, str) else bytes(scene)
        return data, format or "nff", None
    path = os.path.abspath(os.fspath(scene))
    return _read(path), format, path


def _prepared(key: tuple, data: bytes) -> Scene:
    """The worker's prepared scene for ``key`` (the hash of ``data``, the format and
    the path), parsed on first use."""
    with _cache_lock:
        if key in _cache:
            _cache.move_to_end(key)
            return _cache[key]
    _, format, path = key
    prepared = parse(data, format, path=path)
    with _cache_lock:
        _cache[key] = prepared
        while len(_cache) > _KEEP:
            _cache.popitem(last=False)
    return prepared


def _size(key: tuple, data: bytes, width: Optional[int], height: Optional[int]) -> tuple[int, int]:
    """Task: the image size ``render(width=width, height=height)`` makes."""
    return _prepared(key, data).image_size(width, height)


def _render_tile(key: tuple, data: bytes, region: tuple, options: dict) -> np.ndarray:
    """Task: one region of the full image."""
    return _prepared(key, data).render(region=region, **options)


def render(
    scene: SceneSource,
    client: Any,
    tiles: Optional[int] = None,
    format: Optional[str] = None,
    **render_options: Any,
) -> np.ndarray:
    """Renders ``scene`` (a ``Scene``, a path or scene text) on the cluster behind
    ``client`` (a ``distributed.Client``) in ``tiles`` bands of rows, one task each
    (default: four per worker thread), and merges them: the ``float32`` array
    ``Scene.render(**render_options)`` gives, byte for byte.

    ``render_options`` are those of ``Scene.render`` but ``region``; ``threads``
    (per task) defaults to 1. ``format`` is ``"nff"`` or ``"p3f"``: a ``Scene``
    knows its own, a path's is by the extension, and text is NFF unless told (P3F
    text read as NFF raises a ``SceneError`` saying to pass ``format="p3f"``).
    Errors raised on a worker (``SceneError``, ``OSError``, ``ValueError``) are
    raised here.
    """
    if "region" in render_options:
        raise ValueError("nffrt.dask.render renders the whole image: no region")
    options = {"threads": 1, **render_options}
    data, format, path = _source(scene, format)
    key = (hashlib.sha256(data).hexdigest(), format, path)
    # Sent to every worker once per call. (Not under its hash: a second call with the
    # same bytes could get the key of the first call's data as the scheduler was
    # releasing it, and lose it: "lost dependencies".)
    shared = client.scatter(data, broadcast=True, hash=False)
    width, height = options.get("width"), options.get("height")
    if width is None or height is None:
        width, height = client.submit(_size, key, shared, width, height, pure=False).result()
    if tiles is None:
        threads = sum(client.nthreads().values()) or 1
        tiles = min(4 * threads, int(height))
    regions = split(int(width), int(height), tiles)
    opts = {**options, "width": width, "height": height}
    futures = [client.submit(_render_tile, key, shared, tuple(r), opts, pure=False) for r in regions]
    arrays = client.gather(futures)
    return merge(zip(regions, arrays))


def _frame_count(key: tuple, data: bytes) -> Optional[int]:
    """Task: the scene's number of frames (``None``: it does not move)."""
    return _prepared(key, data).frames


def _render_frame(key: tuple, data: bytes, frame: int, options: dict) -> np.ndarray:
    """Task: one frame of an animation."""
    return _prepared(key, data).render(frame=frame, **options)


def render_frames(
    scene: SceneSource,
    client: Any,
    frames: Optional[Any] = None,
    format: Optional[str] = None,
    **render_options: Any,
) -> list:
    """Renders frames of an animated (AFF) ``scene`` on the cluster behind
    ``client``, one task per frame: a list of the ``float32`` arrays
    ``Scene.render(frame=n, **render_options)`` gives, byte for byte, in the order
    of ``frames`` (frame numbers; default: every frame of the animation).

    ``render_options`` are those of ``Scene.render`` but ``frame`` and ``time``;
    ``threads`` (per task) defaults to 1. ``scene`` and ``format`` are as for
    ``render``; the workers read an AFF scene's includes and textures from its
    folder at the same absolute path. A scene that does not move raises
    ``ValueError``.
    """
    for name in ("frame", "time"):
        if name in render_options:
            raise ValueError(f"nffrt.dask.render_frames renders the frames it is given: no {name}")
    options = {"threads": 1, **render_options}
    data, format, path = _source(scene, format)
    key = (hashlib.sha256(data).hexdigest(), format, path)
    shared = client.scatter(data, broadcast=True, hash=False)
    if frames is None:
        count = client.submit(_frame_count, key, shared, pure=False).result()
        if count is None:
            raise ValueError("nffrt.dask.render_frames: the scene does not move (not an AFF scene)")
        frames = range(count)
    futures = [client.submit(_render_frame, key, shared, int(n), options, pure=False) for n in frames]
    return client.gather(futures)
