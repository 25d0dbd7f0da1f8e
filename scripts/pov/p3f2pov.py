#!/usr/bin/env python3
"""Translate a P3F scene (the subset in 2025/dof.p3f and 2019/balls_area_low.p3f) into
POV-Ray 3.7 SDL, so that POV-Ray renders what nffrt renders. See README.md beside this
file for the keyword-by-keyword translation and what does not carry over.

Usage: p3f2pov.py SCENE.p3f [--spp N] > SCENE.pov

--spp N sets blur_samples for a scene with a lens (default: the scene's `spp`, else 1);
it has no effect on a pinhole camera (POV-Ray then traces one ray per pixel with -A).
Keywords outside the subset (mesh, box, cone, glass, quad lights, ...) are an error:
the output must not silently differ from the scene.
"""

import math
import sys

AREA_GRID = 4  # nffrt's grid for 2019 `al` lights (P3F-SPEC; src/nff/p3f.rs)


def sub(a, b):
    return [x - y for x, y in zip(a, b)]


def add(a, b):
    return [x + y for x, y in zip(a, b)]


def scale(a, s):
    return [x * s for x in a]


def dot(a, b):
    return sum(x * y for x, y in zip(a, b))


def cross(a, b):
    return [a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]]


def unit(a):
    return scale(a, 1.0 / math.sqrt(dot(a, a)))


def num(x):
    """Shortest exact form (POV-Ray checks the camera vectors' perpendicularity closely)."""
    return repr(x + 0.0)


def vec(v):
    return "<%s>" % ", ".join(num(x) for x in v)


class Scene:
    """The parsed subset: camera, background, skybox folder, lights, materials, objects."""

    def __init__(self):
        self.cam = {"aperture": 0.0, "focal": 1.0}
        self.spp = None
        self.bclr = [0.0, 0.0, 0.0]
        self.env = None
        self.lights = []  # (position, colour, None) or (centre, colour, (edge1, edge2))
        self.materials = []
        self.objects = []  # (kind, data, material index)


def parse(text):
    """Tokens of `text` without comments, read into a Scene."""
    words = []
    for line in text.splitlines():
        words.extend(line.split("#", 1)[0].split())
    words.reverse()
    s = Scene()

    def num():
        return float(words.pop())

    def nums(n):
        return [num() for _ in range(n)]

    def camera(names):
        while words and words[-1] in names:
            key = names[words.pop()]
            if key in ("from", "at", "up"):
                s.cam[key] = nums(3)
            elif key == "resolution":
                s.cam[key] = (int(num()), int(num()))
            else:
                s.cam[key] = num()

    while words:
        kw = words.pop()
        if kw == "v":
            keys = ["from", "at", "up", "angle", "hither", "resolution", "aperture", "focal"]
            camera({k: k for k in keys})
        elif kw == "camera":
            keys = ["at", "up", "angle", "hither", "resolution", "aperture", "focal"]
            camera(dict({"eye": "from"}, **{k: k for k in keys}))
        elif kw == "accel":
            words.pop()
        elif kw == "spp":
            s.spp = int(num())
        elif kw == "bclr":
            s.bclr = nums(3)
        elif kw == "env":
            s.env = words.pop()
        elif kw == "l":
            pos = nums(3)
            colour = nums(3) if words and is_number(words[-1]) else [1.0, 1.0, 1.0]
            s.lights.append((pos, colour, None))
        elif kw == "light":
            kind = words.pop()
            if kind != "punctual":
                sys.exit("light %s: not translated" % kind)
            s.lights.append((nums(3), nums(3), None))
            while words and is_number(words[-1]):  # 2025/dragon's stray numbers
                words.pop()
        elif kw == "al":
            centre, facing, (w, h) = nums(3), nums(3), nums(2)
            colour = nums(3) if words and is_number(words[-1]) else [1.0, 1.0, 1.0]
            s.lights.append((centre, colour, area_edges(centre, facing, w, h)))
        elif kw in ("f", "mat"):
            s.materials.append(nums(11))
        elif kw == "s":
            s.objects.append(("sphere", nums(4), len(s.materials) - 1))
        elif kw == "p":
            n = int(num())
            s.objects.append(("polygon", [nums(3) for _ in range(n)], len(s.materials) - 1))
        else:
            sys.exit("keyword %r: not translated (see README.md)" % kw)
    return s


def is_number(w):
    try:
        float(w)
        return True
    except ValueError:
        return False


def area_edges(centre, facing, w, h):
    """nffrt's reading of `al` (src/nff/p3f.rs): the w side along the axis least aligned
    with the facing direction crossed with it, the h side perpendicular to both."""
    n = unit(sub(facing, centre))
    axes = [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]]
    axis = axes[min(range(3), key=lambda i: abs(n[i]))]
    u = unit(cross(axis, n))
    v = cross(n, u)
    return scale(u, w), scale(v, h)


def camera_block(s, spp):
    """Explicit POV-Ray vectors for the P3F camera (P3F-SPEC, Semantics)."""
    c = s.cam
    xres, yres = c["resolution"]
    eye, at = c["from"], c["at"]
    d = math.sqrt(dot(sub(at, eye), sub(at, eye)))
    forward = unit(sub(at, eye))
    right = unit(cross(forward, c["up"]))  # right-handed: screen right = view x up
    up = cross(right, forward)
    height = 2.0 * math.tan(math.radians(c["angle"]) / 2.0)  # view plane at distance 1
    lines = [
        "camera {",
        "    perspective",
        "    location  %s" % vec(eye),
        "    direction %s" % vec(forward),
        "    right     %s" % vec(scale(right, height * xres / yres)),
        "    up        %s" % vec(scale(up, height)),
    ]
    if c["aperture"] > 0.0:
        # P3F: lens diameter = aperture pixels of the view plane at distance d.
        diameter = c["aperture"] * (d * height / yres)
        # POV-Ray 3.7 (tracepixel.cpp, JitterCameraRay): the eye moves by
        # aperture/2 * (grid point + jitter), grid points within a disc of radius 1/2:
        # a lens of diameter aperture/2. Its focal plane is perpendicular to the view
        # at |focal_point - location|.
        lines += [
            "    aperture     %.9g   // lens diameter %.6g = %g px of the view plane"
            % (2.0 * diameter, diameter, c["aperture"]),
            "    blur_samples %d, %d // all of them, no early stop" % (spp, spp),
            "    focal_point  %s // focal %g x d = %.6g along the view"
            % (vec(add(eye, scale(sub(at, eye), c["focal"]))), c["focal"], c["focal"] * d),
        ]
    lines.append("}")
    return lines


def material_block(i, m):
    colour, kd, spec, ks, shine, t = m[0:3], m[3], m[4:7], m[7], m[8], m[9]
    if t > 0.0:
        sys.exit("transmissive material %d: not translated" % i)
    finish = ["ambient 0", "emission 0", "diffuse %.9g" % kd]
    if ks > 0.0:
        if shine <= 0.0:
            sys.exit("material %d: shine %g has no POV-Ray roughness" % (i, shine))
        if max(spec) != min(spec):
            sys.exit("material %d: coloured highlights are not translated" % i)
        # Blinn-Phong Ks * S * (n.h)^shine: POV-Ray's `specular` is the half-vector
        # highlight with exponent 1/roughness (its `phong` uses the mirror vector).
        finish += ["specular %.9g" % (ks * spec[0]), "roughness %.9g" % (1.0 / shine)]
        finish.append("reflection { rgb %s }" % vec(scale(spec, ks)))
    return [
        "#declare M%d = texture {" % i,
        "    pigment { rgb %s }" % vec(colour),
        "    finish { %s }" % " ".join(finish),
        "}",
    ]


# Skybox faces (P3F-SPEC, Skybox): image name and the world point of image coordinates
# (s, t), t = 0 the bottom row, on the face at distance L.
FACES = {
    "left": lambda s, t, L: [L, (2 * t - 1) * L, (2 * s - 1) * L],
    "right": lambda s, t, L: [-L, (2 * t - 1) * L, -(2 * s - 1) * L],
    "top": lambda s, t, L: [-(2 * s - 1) * L, L, -(2 * t - 1) * L],
    "bottom": lambda s, t, L: [-(2 * s - 1) * L, -L, (2 * t - 1) * L],
    "front": lambda s, t, L: [-(2 * s - 1) * L, (2 * t - 1) * L, L],
    "back": lambda s, t, L: [(2 * s - 1) * L, (2 * t - 1) * L, -L],
}


def skybox_block(folder, L=1.0e4):
    """Six unlit squares at distance L carrying the images (POV-Ray's image_map spans
    the unit square of x, y with the image's bottom row at y = 0); a matrix takes the
    unit square onto the face so that image coordinates land where P3F looks them up."""
    out = ["// Skybox `env %s`: the images are read from the working directory's %s/." % (folder, folder)]
    for name, at in FACES.items():
        o, ex, ey = at(0, 0, L), sub(at(1, 0, L), at(0, 0, L)), sub(at(0, 1, L), at(0, 0, L))
        ez = unit(cross(ex, ey))
        m = ex + ey + ez + o
        out += [
            "polygon { 5, <0,0>, <1,0>, <1,1>, <0,1>, <0,0>",
            '    texture { pigment { image_map { jpeg "%s/%s.jpg" gamma 1.0 } }' % (folder, name),
            "              finish { ambient 0 diffuse 0 emission 1 } }",
            "    matrix <%s>" % ", ".join(num(x) for x in m),
            "    no_shadow",
            "}",
        ]
    return out


def main():
    args = sys.argv[1:]
    if not args or args[0] in ("-h", "--help"):
        sys.exit("usage: p3f2pov.py SCENE.p3f [--spp N] > SCENE.pov")
    path = args[0]
    s = parse(open(path).read())
    spp = int(args[args.index("--spp") + 1]) if "--spp" in args else (s.spp or 1)
    out = [
        "// Generated by scripts/pov/p3f2pov.py from %s (--spp %d); see scripts/pov/README.md." % (path, spp),
        "// Render: povray +I<this> +W%d +H%d -A +WT2 File_Gamma=1.0 (linear output, as nffrt's)."
        % s.cam["resolution"],
        "#version 3.7;",
        "global_settings { assumed_gamma 1.0 ambient_light 0 max_trace_level 5 }",
        "background { rgb %s }" % vec(s.bclr),
    ]
    out += camera_block(s, spp)
    for pos, colour, area in s.lights:
        light = "light_source { %s color rgb %s" % (vec(pos), vec(colour))
        if area:
            light += "\n    area_light %s, %s, %d, %d jitter adaptive 0" % (
                vec(area[0]), vec(area[1]), AREA_GRID, AREA_GRID)
        out.append(light + " }")
    for i, m in enumerate(s.materials):
        out += material_block(i, m)
    for kind, data, mi in s.objects:
        if kind == "sphere":
            out.append("sphere { %s, %.9g texture { M%d } }" % (vec(data[:3]), data[3], mi))
        elif len(data) == 3:
            out.append("triangle { %s texture { M%d } }" % (", ".join(vec(p) for p in data), mi))
        else:
            pts = data + [data[0]]
            out.append("polygon { %d, %s texture { M%d } }" % (len(pts), ", ".join(vec(p) for p in pts), mi))
    if s.env:
        out += skybox_block(s.env)
    print("\n".join(out))


if __name__ == "__main__":
    main()
