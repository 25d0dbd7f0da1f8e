#!/usr/bin/env python3
"""Writes examples/weekend.p3f, SCENE 0 of the course's 2024/25 path-tracing template
(Shirley's "Ray Tracing in One Weekend" on a floor quad), or examples/course2021.p3f,
the 2020/21 template's scene (the same, with its own glass), their random choices
fixed.

The template places its small spheres at run time with its own hash: for the grid
cell (x, y), x and y in -5..4, the seed is the float32 `x + y / 1000`, and
`hash3(seed)` (seed += 0.1 twice, the two float32 values' bits through `baseHash`,
then the 31-bit multiplicative generators 16807 and 48271) gives the jitter of the
centre and the material choice; the material's colour and roughness come from the
same seed's next draws. This script repeats that arithmetic exactly (float32
rounding at every step, 32-bit unsigned wrapping), so the file has the spheres the
template draws.

One departure, because the template cannot be repeated there: a moving sphere's rise
is `hash1(gSeed) * 0.5`, and gSeed is the pixel's per-frame random state, so the
template's moving spheres end at a different height in every pixel and every frame.
Here the rise is the sphere's own seed's next `hash1`, drawn after its colour.

    python3 scripts/gen_weekend.py 2025 > examples/weekend.p3f
    python3 scripts/gen_weekend.py 2021 > examples/course2021.p3f
"""

import math
import struct
import sys

MASK32 = 0xFFFFFFFF


def f32(x):
    """x rounded to the nearest float32 (GLSL's float arithmetic)."""
    return struct.unpack("<f", struct.pack("<f", x))[0]


def float_bits(x):
    """GLSL floatBitsToUint."""
    return struct.unpack("<I", struct.pack("<f", x))[0]


def base_hash(px, py):
    """The template's baseHash(uvec2 p), on 32-bit unsigned integers."""
    qx = (1103515245 * ((px >> 1) ^ py)) & MASK32
    qy = (1103515245 * ((py >> 1) ^ px)) & MASK32
    h32 = (1103515245 * (qx ^ (qy >> 3))) & MASK32
    return h32 ^ (h32 >> 16)


class Seed:
    """A float32 seed advanced as the template's `inout float seed`."""

    def __init__(self, value):
        self.value = f32(value)

    def _next_hash(self):
        # vec2(seed += 0.1, seed += 0.1): two increments, each rounded to float32.
        a = self.value = f32(self.value + f32(0.1))
        b = self.value = f32(self.value + f32(0.1))
        return base_hash(float_bits(a), float_bits(b))

    def hash1(self):
        n = self._next_hash()
        return f32(f32(float(n)) / f32(float(MASK32)))

    def hash3(self):
        n = self._next_hash()
        rz = (n, (n * 16807) & MASK32, (n * 48271) & MASK32)
        scale = f32(float(0x7FFFFFFF))
        return tuple(f32(f32(float(c & 0x7FFFFFFF)) / scale) for c in rz)


def mul(a, b):
    return tuple(f32(x * y) for x, y in zip(a, b))


def fmt(*values):
    return " ".join(f"{v:.6g}" for v in values)


def glass_2025(seed):
    """2024/25: createDielectricMaterial(hash3(seed), 1.33, 0), hash3 the absorption.

    The template's refractColor is Beer's absorption coefficient; P3F's glass
    absorbs 1 - C, so C = 1 - refractColor.
    """
    colour = tuple(1.0 - a for a in seed.hash3())
    return f"mat {fmt(*colour)} 0 1 1 1 0 1 1 1.33"


def glass_2021(seed):
    """2020/21: createDialectricMaterial(hash3(seed), 1.5), hash3 an albedo that
    multiplies every reflected or refracted ray; here it tints the reflection (S) and
    absorbs inside (C), a paler tint than the template's two products per crossing.
    """
    c = fmt(*seed.hash3())
    return f"mat {c} 0 {c} 0 1 1 1.5"


def small_spheres(glass):
    """The template's 10 x 10 grid of small spheres, as P3F lines; `glass` writes a
    glass sphere's material from its seed."""
    lines = []
    for x in range(-5, 5):
        for y in range(-5, 5):
            fx, fy = float(x), float(y)
            seed = Seed(f32(fx + f32(fy / 1000.0)))
            rand1 = seed.hash3()
            center = (f32(fx + f32(0.9 * rand1[0])), 0.2, f32(fy + f32(0.9 * rand1[1])))
            choose = rand1[2]
            if math.dist(center, (4.0, 0.2, 0.0)) <= 0.9:
                continue
            lines.append(f"# cell ({x}, {y}): choice {choose:.3f}")
            if choose < 0.3:
                albedo = mul(seed.hash3(), seed.hash3())
                rise = f32(seed.hash1() * 0.5)
                end = (center[0], f32(center[1] + rise), center[2])
                lines.append(f"mat {fmt(*albedo)} 1 0 0 0 0 1 0 1")
                lines.append(f"sm {fmt(*center)}  {fmt(*end)}  0.2  0 1")
            elif choose < 0.5:
                albedo = mul(seed.hash3(), seed.hash3())
                lines.append(f"mat {fmt(*albedo)} 1 0 0 0 0 1 0 1")
                lines.append(f"s {fmt(*center)} 0.2")
            elif choose < 0.9:
                spec = tuple(f32((c + 1.0) * 0.5) for c in seed.hash3())
                rough = seed.hash1() if choose >= 0.7 else 0.0
                suffix = f" roughness {rough:.6g}" if rough > 0 else ""
                lines.append(f"mat 0 0 0 0 {fmt(*spec)} 1 1 0 1{suffix}")
                lines.append(f"s {fmt(*center)} 0.2")
            else:
                lines.append(glass(seed))
                lines.append(f"s {fmt(*center)} 0.2")
    return lines


HEADER_2025 = """\
# Shirley's "Ray Tracing in One Weekend" scene: SCENE 0 of the IST Programacao 3D
# course's 2024/25 path-tracing template (assignment2-2025-template/P3D_RT.glsl,
# hit_world and main), numbers transcribed; written by scripts/gen_weekend.py 2025,
# which repeats the template's hash to fix its random small spheres (see the script).
"""

HEADER_2021 = """\
# The scene of the IST Programacao 3D course's 2020/21 path-tracing template
# (assignment2-2021-template/P3D_RT.glsl, hit_world and main: Shirley's "Ray Tracing
# in One Weekend" on a floor of two triangles), numbers transcribed; written by
# scripts/gen_weekend.py 2021, which repeats the template's hash to fix its random
# small spheres (see the script).
"""

# What P3F cannot say as the templates do, and what the file says instead.
DEPARTURES = """\
#
# Departures from the template, each because P3F cannot say it otherwise:
# - camera: the template's eye is (mouse.x * 10, mouse.y * 5, 8) with mouse.x mapped
#   to [-1, 1]; this is the mouse at the window's centre, eye (0, 2.5, 8), looking at
#   (0, 0, -1), vertical field of view 60, aperture 0 (a pinhole); 16:9.
# - sky: the template's background is mix(white, (0.5, 0.7, 1), 0.8 (dir.y + 1)), a
#   gradient; P3F has one colour, here the gradient's cosine-weighted mean over the
#   upper hemisphere (0.333, 0.6, 1), which lights an upward face as the sky does.
# - the three white point lights of the template's rayColor (its "direct lighting
#   with 3 white point lights") are here as `light punctual` of intensity 1: faint,
#   as they fall off with 1/d^2 (the course's Whitted shading has no falloff).
# - the hollow glass sphere's inner surface (the template's negative radius,
#   Shirley's bubble trick) is a sphere of the same positive radius with the inverse
#   index, relative to the glass around it: a negative radius in P3F is a sphere
#   seen only from inside.
# - {glass}
#   Metal fuzz is given as P3F roughness (GGX, alpha = roughness^2): the same range,
#   not the same lobe.
# - the moving spheres rise by their own seed's draw (the template's differs per pixel).
# - MAX_BOUNCES 10: render with --max-depth 10 (the same count of segments).
#
#   nffrt render examples/{name}.p3f --max-depth 10 -o {name}.png
camera eye 0 2.5 8 at 0 0 -1 up 0 1 0 angle 60 hither 0.001 resolution 480 270
spp 16
integrator path
shutter 0 1
bclr 0.333 0.6 1
light punctual -10 15 0 1 1 1
light punctual 8 15 3 1 1 1
light punctual 1 15 -9 1 1 1
"""

GLASS_NOTE_2025 = """glass: the template's refractColor is Beer's absorption coefficient; P3F glass
#   absorbs exp(-(1 - C) d), so C = 1 - refractColor."""

GLASS_NOTE_2021 = """glass: the template's albedo multiplies every reflected and refracted ray;
#   here it tints the reflection (S) and absorbs inside by Beer's law (C), paler."""

BIG_2025 = """
# floor: a 20 x 20 quad at y = -0.05, diffuse 0.2
mat 0.2 0.2 0.2 1 0 0 0 0 1 0 1
p 4 -10 -0.05 10  10 -0.05 10  10 -0.05 -10  -10 -0.05 -10
# diffuse (0.2, 0.95, 0.1)
mat 0.2 0.95 0.1 1 0 0 0 0 1 0 1
s -4 1 0 1
# metal (0.7, 0.6, 0.5), smooth
mat 0 0 0 0 0.7 0.6 0.5 1 1 0 1
s 4 1 0 1
# hollow glass, index 1.33, no absorption: the shell and its air bubble (1 / 1.33)
mat 1 1 1 0 1 1 1 0 1 1 1.33
s -1.5 1 0 1
mat 1 1 1 0 1 1 1 0 1 1 0.75188
s -1.5 1 0 0.5
# glass, index 1.5, absorbing (0, 0.9, 0.9): red
mat 1 0.1 0.1 0 1 1 1 0 1 1 1.5
s 1.5 1 0 1
"""

BIG_2021 = """
# floor: two triangles at y = -0.01, 20 x 20, diffuse 0.2
mat 0.2 0.2 0.2 1 0 0 0 0 1 0 1
p 3 -10 -0.01 10  10 -0.01 10  -10 -0.01 -10
p 3 -10 -0.01 -10  10 -0.01 10  10 -0.01 -10
# diffuse (0.2, 0.95, 0.1)
mat 0.2 0.95 0.1 1 0 0 0 0 1 0 1
s -4 1 0 1
# metal (0.7, 0.6, 0.5), smooth
mat 0 0 0 0 0.7 0.6 0.5 1 1 0 1
s 4 1 0 1
# hollow glass, index 1.5, white: a thin shell (inner radius 0.95, index 1 / 1.5)
mat 1 1 1 0 1 1 1 0 1 1 1.5
s 0 1 0 1
mat 1 1 1 0 1 1 1 0 1 1 0.666667
s 0 1 0 0.95
"""

YEARS = {
    "2025": ("weekend", HEADER_2025, GLASS_NOTE_2025, BIG_2025, glass_2025),
    "2021": ("course2021", HEADER_2021, GLASS_NOTE_2021, BIG_2021, glass_2021),
}


def main():
    if len(sys.argv) != 2 or sys.argv[1] not in YEARS:
        sys.exit("usage: gen_weekend.py 2025|2021")
    name, header, glass_note, big, glass = YEARS[sys.argv[1]]
    out = sys.stdout
    out.write(header)
    out.write(DEPARTURES.format(glass=glass_note, name=name))
    out.write(big)
    out.write("\n# the small spheres\n")
    out.write("\n".join(small_spheres(glass)) + "\n")


if __name__ == "__main__":
    main()
