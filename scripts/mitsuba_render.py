#!/usr/bin/env python3
"""Renders one of scripts/mitsuba_scenes.py's scenes with Mitsuba 3 to a linear EXR,
as one whole process for scripts/bench-mitsuba.sh to time: import, scene loading,
one mi.render call (Mitsuba splits the work into passes itself), writing.

    mitsuba_render.py VARIANT SCENE SIZE SPP OUT.exr [SEED [SAMPLER]]

SAMPLER is Mitsuba's sampler plugin, `independent` (the default) or `stratified`.
"""

import sys
from pathlib import Path

import mitsuba as mi


def main():
    variant, name, size, spp, out = sys.argv[1:6]
    seed = int(sys.argv[6]) if len(sys.argv) > 6 else 0
    sampler = sys.argv[7] if len(sys.argv) > 7 else "independent"
    mi.set_variant(variant)
    sys.path.insert(0, str(Path(__file__).resolve().parent))
    import mitsuba_scenes

    scene = mi.load_dict(mitsuba_scenes.SCENES[name](int(size), int(spp), sampler=sampler))
    image = mi.render(scene, spp=int(spp), seed=seed)
    mi.Bitmap(image).write(out)


if __name__ == "__main__":
    main()
