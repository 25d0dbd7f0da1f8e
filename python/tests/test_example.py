"""The notebook under examples/python/ runs: its code cells, executed in order in
one namespace (with a stand-in for ``IPython.display`` where IPython is absent),
make the picture it shows."""

from __future__ import annotations

import json
import sys
import types

import numpy as np

from helpers import REPO

NOTEBOOK = REPO / "examples" / "python" / "spd_notebook.ipynb"


def test_notebook_cells_run_and_show_the_render(monkeypatch) -> None:
    try:
        import IPython.display  # noqa: F401
    except ImportError:
        display = types.ModuleType("IPython.display")
        display.Image = lambda data: types.SimpleNamespace(data=data)
        ipython = types.ModuleType("IPython")
        ipython.display = display
        monkeypatch.setitem(sys.modules, "IPython", ipython)
        monkeypatch.setitem(sys.modules, "IPython.display", display)
    cells = json.loads(NOTEBOOK.read_text())["cells"]
    sources = ["".join(c["source"]) for c in cells if c["cell_type"] == "code"]
    namespace: dict = {}
    for k, source in enumerate(sources):
        exec(compile(source, f"{NOTEBOOK.name} cell {k}", "exec"), namespace)
    scene, image = namespace["scene"], namespace["image"]
    assert scene.counts["spheres"] == 1 + 9 + 81 + 729  # the sphereflake of size 3
    assert image.shape == (320, 320, 3) and np.isfinite(image).all()
    png = scene._repr_png_()
    assert png.startswith(b"\x89PNG")
