#!/usr/bin/env python3
"""Writes examples/cornell.p3f from Mitsuba 3's own Cornell box, `mi.cornell_box()`.

Every number comes from that dictionary, through Mitsuba's own transforms: the
rectangles' corners (Mitsuba's rectangle is [-1, 1]^2 in z = 0, facing +z, its
corners listed counter-clockwise about +z so that P3F's winding normal is Mitsuba's
normal), the two boxes' vertices and triangles (Mitsuba's `cube` mesh, moved by its
`to_world`), the diffuse reflectances, the light's radiance and the camera.

Needs the Python package `mitsuba` (scripts/compare-mitsuba.sh makes a venv):

    target/mitsuba-venv/bin/python scripts/gen_cornell.py > examples/cornell.p3f
"""

import mitsuba as mi

mi.set_variant("scalar_rgb")

# Mitsuba's rectangle, counter-clockwise seen from its normal (+z).
RECTANGLE = [(-1, -1, 0), (1, -1, 0), (1, 1, 0), (-1, 1, 0)]

# The scene's shapes in the order the file lists them.
RECTANGLES = ["floor", "ceiling", "back", "green-wall", "red-wall"]
BOXES = ["small-box", "large-box"]


def number(c):
    # Mitsuba's rotations leave -4.4e-08 where a coordinate is 0; six digits hold every number of the dictionary.
    return "0" if abs(c) < 1e-6 else f"{c:.6g}"


def fmt(values):
    return "  ".join(" ".join(number(c) for c in v) for v in values)


def transformed(to_world, points):
    return [to_world @ mi.ScalarPoint3f(*p) for p in points]


def diffuse_mat(reflectance, emission=None):
    """P3F's diffuse material (Kd 1, no mirror, no glass), emitting if asked."""
    line = f"mat {fmt([reflectance])} 1 0 0 0 0 1 0 1"
    if emission is not None:
        line += f" {fmt([emission])}"
    return line


def cube_mesh(to_world):
    """Mitsuba's cube (24 vertices, 12 outward triangles) moved by to_world, as a
    P3F mesh (indices from 1)."""
    cube = mi.load_dict({"type": "cube", "to_world": to_world})
    params = mi.traverse(cube)
    pos = list(params["vertex_positions"])
    faces = list(params["faces"])
    verts = [pos[i : i + 3] for i in range(0, len(pos), 3)]
    tris = [faces[i : i + 3] for i in range(0, len(faces), 3)]
    lines = [f"mesh {len(verts)} {len(tris)}"]
    lines += [fmt([v]) for v in verts]
    lines += [" ".join(str(i + 1) for i in t) for t in tris]
    return lines


def camera_line(sensor, size):
    """P3F's camera from Mitsuba's perspective sensor: its look_at origin, a target
    one unit along its view direction (+z of its to_world), its up (+y), and its fov
    (fov_axis 'smaller' on a square image: the vertical field of view)."""
    m = sensor["to_world"].matrix
    origin = [m[i][3] for i in range(3)]
    forward = [m[i][2] for i in range(3)]
    up = [m[i][1] for i in range(3)]
    target = [o + f for o, f in zip(origin, forward)]
    return (
        f"camera eye {fmt([origin])} at {fmt([target])} up {fmt([up])} "
        f"angle {sensor['fov']} hither {sensor['near_clip']} resolution {size} {size}"
    )


def main():
    box = mi.cornell_box()
    colours = {k: box[k]["reflectance"]["value"] for k in ("white", "green", "red")}
    light = box["light"]
    lines = [
        "# The Cornell box of Mitsuba 3 (`mitsuba.cornell_box()`, Mitsuba "
        + mi.__version__
        + "), every number",
        "# from its dictionary: written by scripts/gen_cornell.py. Diffuse walls, two",
        "# rotated white boxes (Mitsuba's `cube` meshes), a one-sided light of radiance",
        "# (18.387, 13.9873, 6.75357) just under the ceiling (also white diffuse, as",
        "# Mitsuba's), the same camera. Mitsuba's dictionary has max_depth 8:",
        "#",
        "#   nffrt render examples/cornell.p3f --max-depth 8 -o cornell.png",
        "# scripts/compare-mitsuba.sh renders it on both sides and compares.",
        camera_line(box["sensor"], box["sensor"]["film"]["width"]),
        "spp 16",
        "integrator path",
        "bclr 0 0 0",
    ]
    for name in RECTANGLES:
        shape = box[name]
        lines.append(f"# {name}")
        lines.append(diffuse_mat(colours[shape["bsdf"]["id"]]))
        lines.append(f"p 4 {fmt(transformed(shape['to_world'], RECTANGLE))}")
    lines.append("# light: white diffuse, emitting on the side of its normal (down)")
    lines.append(diffuse_mat(colours["white"], light["emitter"]["radiance"]["value"]))
    lines.append(f"p 4 {fmt(transformed(light['to_world'], RECTANGLE))}")
    for name in BOXES:
        lines.append(f"# {name}")
        lines.append(diffuse_mat(colours[box[name]["bsdf"]["id"]]))
        lines += cube_mesh(box[name]["to_world"])
    print("\n".join(lines))


if __name__ == "__main__":
    main()
