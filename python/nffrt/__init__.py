"""nffrt: a fast ray tracer for NFF scenes (the Standard Procedural Databases)
and P3F scenes (the IST course's extended NFF), rendering into numpy arrays.

>>> import nffrt
>>> scene = nffrt.parse(nffrt.gen("balls", size=1))
>>> image = scene.render(width=64, height=48)      # float32, shape (48, 64, 3)
>>> nffrt.save(image, "balls.png")                 # or .ppm, .pfm

A scene is loaded (``load``) or parsed (``parse``) once, with its acceleration
structure, and renders any number of times; ``render`` releases the GIL and stops
on Ctrl-C. ``tiles`` and ``merge`` split a render into regions and put it back
together; ``nffrt.dask.render`` runs the regions on a Dask cluster. ``diff``
measures how far a picture is from a reference (NVIDIA's FLIP, MSE, PSNR...).
"""

from ._nffrt import Scene, SceneError, __version__, diff, gen, load, parse, save, to_png
from ._tiles import Region, merge, tiles

__all__ = [
    "Region",
    "Scene",
    "SceneError",
    "__version__",
    "diff",
    "gen",
    "load",
    "merge",
    "parse",
    "save",
    "tiles",
    "to_png",
]
