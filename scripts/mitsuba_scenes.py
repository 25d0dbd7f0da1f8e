"""Mitsuba 3 scene dictionaries equivalent to nffrt's examples/cornell.p3f and
examples/glass-mirror.p3f, for scripts/compare-mitsuba.py and bench-mitsuba.sh.

The mapping is docs/path-tracing.md's, each P3F material as the Mitsuba BSDF nffrt's
path tracer implements:
- `mat C 1 0 0 0 0 1 0 1` (diffuse)        -> `diffuse`, reflectance C
- `mat 0 0 0 0 S 1 1 0 1` (smooth mirror)   -> `conductor`, material none (a perfect
                                              mirror), specular_reflectance S
- `mat 1 1 1 0 1 1 1 0 1 1 ior` (glass)     -> `dielectric`, int_ior ior, ext_ior 1
- the 14-number emissive form               -> an `area` emitter (one-sided, as ours)
                                              of the same radiance on the same shape
and the camera is the same `perspective` sensor (fov_axis 'smaller', the vertical
field of view of a square picture, as P3F's `angle`). The film's reconstruction
filter is a box of one pixel, as nffrt's samples each land in their own pixel (the
Cornell dictionary's default is a Gaussian, which would blur Mitsuba's side).
`max_depth` counts as nffrt's --max-depth does (the camera ray is segment 1).

The Cornell box is Mitsuba's own `mi.cornell_box()` (examples/cornell.p3f is written
from it by scripts/gen_cornell.py); glass-mirror replaces its two boxes by the two
spheres of examples/glass-mirror.p3f, whose numbers are repeated here.
"""

import mitsuba as mi

# examples/glass-mirror.p3f's spheres.
GLASS = {"center": [-0.42, -0.6, 0.15], "radius": 0.4, "ior": 1.5}
MIRROR = {"center": [0.45, -0.65, -0.35], "radius": 0.35, "reflectance": [0.95, 0.85, 0.6]}

# The max_depth each example is compared at (its file's comment says the same).
MAX_DEPTH = {"cornell": 8, "glass-mirror": 12}


def _with_film(scene, size, spp, max_depth, sampler="independent"):
    """The scene at size x size pixels, spp samples from `sampler` (Mitsuba's
    `independent` by default, as its Cornell box; `stratified` jitters strata as nffrt
    does), a one-pixel box filter and max_depth."""
    sensor = scene["sensor"]
    sensor["film"]["width"] = size
    sensor["film"]["height"] = size
    sensor["film"]["rfilter"] = {"type": "box"}
    sensor["sampler"] = {"type": sampler, "sample_count": spp}
    scene["integrator"] = {"type": "path", "max_depth": max_depth}
    return scene


def cornell(size=256, spp=64, max_depth=MAX_DEPTH["cornell"], sampler="independent"):
    """Mitsuba's Cornell box as examples/cornell.p3f has it."""
    return _with_film(mi.cornell_box(), size, spp, max_depth, sampler)


def glass_mirror(size=256, spp=64, max_depth=MAX_DEPTH["glass-mirror"], sampler="independent"):
    """examples/glass-mirror.p3f: the Cornell walls and light, a smooth glass sphere
    and a smooth tinted mirror sphere instead of the boxes."""
    scene = mi.cornell_box()
    del scene["small-box"], scene["large-box"]
    scene["glass"] = {
        "type": "sphere",
        "center": GLASS["center"],
        "radius": GLASS["radius"],
        "bsdf": {"type": "dielectric", "int_ior": GLASS["ior"], "ext_ior": 1.0},
    }
    scene["mirror"] = {
        "type": "sphere",
        "center": MIRROR["center"],
        "radius": MIRROR["radius"],
        "bsdf": {
            "type": "conductor",
            "material": "none",
            "specular_reflectance": {"type": "rgb", "value": MIRROR["reflectance"]},
        },
    }
    return _with_film(scene, size, spp, max_depth, sampler)


SCENES = {"cornell": cornell, "glass-mirror": glass_mirror}
