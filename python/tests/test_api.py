"""The Python API on SPD, P3F and hand-written scenes: what a Scene tells about
itself, checked against the files themselves (token counts, header comments), and
what render, gen, save, tiles and merge give."""

from __future__ import annotations

import re
from pathlib import Path

import numpy as np
import pytest

import nffrt
from helpers import DATA, header_values, read_pfm, shared

SMALL = (
    "v from 0 0 6 at 0 0 0 up 0 1 0 angle 40 hither 1 resolution 23 17\n"
    "b 0.1 0.2 0.3\nl 2 3 8\nf 1 0 0 0.8 0.2 20 0 1\ns 0 0 0 1.2\n"
    "f 0.5 0.5 0.5 0.5 0.5 10 0 1\npl 0 0 -2 1 0 -2 0 1 -2\n"
)


def keyword_counts(path: Path) -> dict[str, int]:
    """Counts keyword tokens with no parser: comments stripped, whitespace split
    (numbers never spell a keyword)."""
    tokens = []
    for line in path.read_text(errors="replace").splitlines():
        tokens += line.split("#")[0].split()
    names = {"s": "spheres", "p": "polygons", "pp": "patches", "c": "cones", "l": "lights"}
    counts = dict.fromkeys(names.values(), 0)
    for t in tokens:
        if t in names:
            counts[names[t]] += 1
    return counts


@pytest.mark.parametrize("name", ["balls", "gears", "mount", "rings", "teapot", "tetra", "tree"])
def test_spd_scene_describes_itself(name: str) -> None:
    path = shared("spd", f"{name}.nff")
    scene = nffrt.load(path)
    want = keyword_counts(path)
    counts = scene.counts
    for key, n in want.items():
        assert counts[key] == n, key
    assert scene.path == str(path)
    assert scene.format == "nff"
    assert (scene.width, scene.height) == (512, 512)
    assert scene.camera["width"] == 512 and scene.camera["angle"] > 0
    assert len(scene.lights) == want["lights"]
    lo, hi = scene.bounds
    assert all(a < b for a, b in zip(lo, hi))
    assert scene.warnings == []
    assert repr(scene).startswith(f"<nffrt.Scene {path}: ")


def test_mount_camera_and_light_are_the_files() -> None:
    path = shared("spd", "mount.nff")
    text = path.read_text()
    numbers = lambda key: tuple(float(v) for v in re.search(rf"^{key} (.*)$", text, re.M).group(1).split())
    scene = nffrt.load(path)
    cam = scene.camera
    for key in ("from", "at", "up"):
        assert cam[key] == pytest.approx(numbers(key), rel=1e-6)
    assert cam["angle"] == pytest.approx(numbers("angle")[0])
    light = re.search(r"^l (.*)$", text, re.M).group(1).split()
    assert scene.lights[0]["position"] == pytest.approx(tuple(float(v) for v in light[:3]))
    assert scene.background == pytest.approx(numbers("b"), rel=1e-6)


@pytest.mark.parametrize(
    "rel, dialect",
    [("2019/dof.p3f", "p3f-2019"), ("2025/dof.p3f", "p3f-2025"), ("2019/balls_area_low.p3f", "p3f-2019")],
)
def test_p3f_scene_loads_by_extension(rel: str, dialect: str) -> None:
    path = shared("p3f", *rel.split("/"))
    scene = nffrt.load(path)
    assert scene.format == dialect
    want = keyword_counts(path)
    assert scene.counts["spheres"] == want["spheres"]
    assert scene.counts["polygons"] == want["polygons"]
    text = path.read_text()
    spp = re.search(r"^spp (\d+)", text, re.M)
    assert scene.spp == (int(spp.group(1)) if spp else None)
    res = re.search(r"^resolution (\d+) (\d+)", text, re.M)
    assert (scene.width, scene.height) == (int(res.group(1)), int(res.group(2)))
    aperture = re.search(r"^aperture (\S+)", text, re.M)
    if aperture:
        assert scene.camera["aperture"] == pytest.approx(float(aperture.group(1)))


def test_p3f_area_light_has_its_extent() -> None:
    scene = nffrt.load(shared("p3f", "2019", "balls_area_low.p3f"))
    area = [l for l in scene.lights if "v1" in l]
    assert area, scene.lights
    assert all(l["grid"] >= 1 for l in area)


def test_p3f_text_parses_with_format() -> None:
    text = shared("p3f", "2025", "balls_low.p3f").read_text()
    # The 2025 balls name a skybox folder: parsed text finds it from the current
    # directory, so drop that line here.
    text = "\n".join(l for l in text.splitlines() if not l.startswith("env "))
    scene = nffrt.parse(text, format="p3f")
    assert scene.format == "p3f-2025" and scene.path is None
    with pytest.raises(nffrt.SceneError) as caught:
        nffrt.parse(text)  # P3F keywords are not NFF
    # The first P3F keyword gets the hint in Python's words (issue 30, items 3 and 7).
    assert caught.value.message.endswith('(the scene reads as P3F: pass format="p3f")'), caught.value.message
    # A P3F keyword in text that is not P3F either: named as one, with the same advice.
    with pytest.raises(nffrt.SceneError) as caught:
        nffrt.parse("accel bvh\ns 0 0 0\n")
    assert caught.value.message == (
        'unknown keyword "accel": it is a P3F keyword (pass format="p3f" if the scene is a P3F file)'
    ), caught.value.message


def test_camera_values_are_the_decimals_of_the_file() -> None:
    """Issue 30, item E: each f32 comes back as the decimal written in the file, not
    its binary expansion (-1.600000023841858)."""
    scene = nffrt.parse(
        "v from -1.6 0.1 5 at 0 0 0 up 0 1 0 angle 40.3 hither 0.01 resolution 8 6\n"
        "b 0.1 0.15 0.3\nl 1.2 2 3\nf 1 1 1 1 0 1 0 1\ns 0 0 0 1.2\n"
    )
    cam = scene.camera
    assert cam["from"] == (-1.6, 0.1, 5.0)
    assert (cam["angle"], cam["hither"]) == (40.3, 0.01)
    assert scene.background == (0.1, 0.15, 0.3)
    assert scene.lights[0]["position"] == (1.2, 2.0, 3.0)
    assert scene.bounds == ((-1.2, -1.2, -1.2), (1.2, 1.2, 1.2))


def ok_files() -> list[Path]:
    return sorted((DATA / "ok").glob("*.nff"))


@pytest.mark.parametrize("path", ok_files(), ids=lambda p: p.name)
def test_odd_but_valid_files_give_their_counts_and_warnings(path: Path) -> None:
    """The ``# expect: KEY=N`` and ``# warning: LINE:COL TEXT`` headers of
    tests/data/ok, read through Python."""
    scene = nffrt.load(path)
    [expect] = header_values(path, "expect")
    facts = {**scene.counts, "width": scene.width, "height": scene.height}
    for item in expect.split():
        key, n = item.split("=")
        assert facts[key] == int(n), key
    want = header_values(path, "warning")
    got = scene.warnings
    assert len(got) == len(want), got
    for (line, column, message), w in zip(got, want):
        pos, text = w.split(" ", 1)
        assert f"{line}:{column}" == pos and text in message


def test_render_shape_dtype_and_stats() -> None:
    scene = nffrt.parse(SMALL)
    assert scene.last_stats is None
    image = scene.render()
    assert image.shape == (17, 23, 3) and image.dtype == np.float32
    assert image.flags.writeable and image.flags.c_contiguous
    stats = scene.last_stats
    assert stats["eye_rays"] == 23 * 17
    assert stats["total_rays"] == sum(
        stats[k] for k in ("eye_rays", "reflection_rays", "refraction_rays", "shadow_rays")
    )
    # The red sphere fills the centre; without the plane, the corner is background.
    r, g, b = image[8, 11]
    assert r > 0.5 and g < r and b < r
    no_plane = nffrt.parse(SMALL.split("f 0.5")[0]).render()
    assert tuple(no_plane[0, 0]) == pytest.approx((0.1, 0.2, 0.3))
    scene.render(width=8, height=6, spp=4)
    assert scene.last_stats["eye_rays"] == 8 * 6 * 4


def test_region_is_the_full_renders_crop_and_threads_do_not_matter() -> None:
    scene = nffrt.parse(SMALL)
    full = scene.render(spp=3, threads=2)
    assert np.array_equal(full, scene.render(spp=3, threads=1))
    crop = scene.render(spp=3, region=(5, 2, 19, 11))
    assert crop.shape == (9, 14, 3)
    assert crop.tobytes() == full[2:11, 5:19].tobytes()
    assert np.array_equal(scene.render(region=nffrt.Region(0, 0, 23, 17)), scene.render())


def test_one_side_given_keeps_the_files_aspect() -> None:
    scene = nffrt.parse(SMALL)  # 23 x 17
    assert scene.image_size() == (23, 17)
    assert scene.image_size(46) == (46, 34)
    assert scene.image_size(height=4) == (5, 4)  # 23 * 4 / 17 = 5.4
    assert scene.image_size(10, 10) == (10, 10)
    assert scene.render(width=46).shape == (34, 46, 3)


def test_spd_protocol_and_spp_are_exclusive() -> None:
    scene = nffrt.parse(SMALL)
    scene.render(spd=True)
    assert scene.last_stats["eye_rays"] == 24 * 18  # the pixel corners
    with pytest.raises(ValueError, match="(?i)spd"):
        scene.render(spd=True, spp=4)


def test_gen_is_the_spd_scene() -> None:
    # The SPD's tetrahedron of level n is 4^n triangles (each level splits a
    # tetrahedron into four); level 1 is one tetrahedron.
    assert nffrt.parse(nffrt.gen("tetra", size=1)).counts["polygons"] == 4
    assert nffrt.parse(nffrt.gen("tetra", size=2)).counts["polygons"] == 16
    assert "b " in nffrt.gen("balls", size=1)
    with pytest.raises(ValueError, match="no SPD scene"):
        nffrt.gen("teapots")
    with pytest.raises(ValueError, match="size=99: .* from 1 to 7 for balls"):
        nffrt.gen("balls", size=99)


def test_gen_at_the_default_size_is_the_published_file() -> None:
    path = shared("spd", "gears.nff")
    generated = nffrt.parse(nffrt.gen("gears"))
    assert generated.counts == nffrt.load(path).counts
    assert generated.camera == nffrt.load(path).camera


def test_save_pfm_holds_the_array_and_png_matches_to_png(tmp_path: Path) -> None:
    image = nffrt.parse(SMALL).render()
    image[0, 0] = (2.5, -1.0, 0.25)  # unclamped values survive in PFM
    nffrt.save(image, tmp_path / "x.pfm")
    assert read_pfm(tmp_path / "x.pfm").tobytes() == image.tobytes()
    nffrt.save(image, tmp_path / "x.png")
    assert (tmp_path / "x.png").read_bytes() == nffrt.to_png(image)
    nffrt.save(image, str(tmp_path / "x.PPM"))
    ppm = (tmp_path / "x.PPM").read_bytes()
    header = b"P6\n23 17\n255\n"
    assert ppm.startswith(header)
    pixels = np.frombuffer(ppm[len(header) :], dtype=np.uint8).reshape(17, 23, 3)
    want = np.floor(np.clip(image, 0, 1) * 255 + 0.5).astype(np.uint8)
    assert np.array_equal(pixels, want)
    assert [p.name for p in tmp_path.iterdir() if p.name.startswith(".")] == []


def test_repr_png_is_a_small_preview() -> None:
    png = nffrt.parse(SMALL)._repr_png_()
    assert png.startswith(b"\x89PNG\r\n\x1a\n")
    width, height = int.from_bytes(png[16:20], "big"), int.from_bytes(png[20:24], "big")
    assert (width, height) == (23, 17)
    big = nffrt.parse(SMALL.replace("resolution 23 17", "resolution 1000 500"))._repr_png_()
    assert (int.from_bytes(big[16:20], "big"), int.from_bytes(big[20:24], "big")) == (256, 128)


def test_tiles_are_even_bands() -> None:
    bands = nffrt.tiles(61, 47, 5)
    assert [b.height for b in bands] == [9, 9, 10, 9, 10]
    assert all((b.x0, b.x1) == (0, 61) for b in bands)
    assert bands[0].y0 == 0 and bands[-1].y1 == 47
    assert all(a.y1 == b.y0 for a, b in zip(bands, bands[1:]))
    with pytest.raises(ValueError, match="from 1 to the height"):
        nffrt.tiles(61, 47, 48)


def test_merge_places_uneven_pieces_in_any_order() -> None:
    full = np.arange(47 * 61 * 3, dtype=np.float32).reshape(47, 61, 3)
    regions = [(0, 0, 30, 20), (30, 0, 61, 20), (0, 20, 61, 21), (0, 21, 7, 47), (7, 21, 61, 47)]
    pieces = [(r, full[r[1] : r[3], r[0] : r[2]]) for r in regions]
    merged = nffrt.merge(reversed(pieces))
    assert merged.dtype == np.float32 and merged.tobytes() == full.tobytes()


def test_merge_names_overlaps_gaps_and_misfits() -> None:
    z = lambda h, w: np.zeros((h, w, 3), np.float32)
    with pytest.raises(ValueError, match=r"regions 0,0,3,3 and 2,0,4,3 overlap"):
        nffrt.merge([((0, 0, 3, 3), z(3, 3)), ((2, 0, 4, 3), z(3, 2))])
    with pytest.raises(ValueError, match=r"cover 8 of the 12 .* pixel \(0, 1\)"):
        nffrt.merge([((0, 0, 4, 1), z(1, 4)), ((0, 2, 4, 3), z(1, 4))])
    with pytest.raises(ValueError, match="cannot be region"):
        nffrt.merge([((0, 0, 4, 3), z(3, 3))])
    with pytest.raises(ValueError, match="empty"):
        nffrt.merge([((2, 0, 2, 3), z(3, 0))])
    with pytest.raises(ValueError, match="no pieces"):
        nffrt.merge([])


def test_type_stubs_name_what_the_module_has() -> None:
    """_nffrt.pyi and the compiled module agree on functions, classes and Scene's
    members, and on each function's parameter names."""
    import ast
    import inspect

    from nffrt import _nffrt

    stub = ast.parse((Path(nffrt.__file__).parent / "_nffrt.pyi").read_text())
    functions = {n.name: n for n in stub.body if isinstance(n, ast.FunctionDef)}
    classes = {n.name: n for n in stub.body if isinstance(n, ast.ClassDef)}
    public = {n for n in dir(_nffrt) if not n.startswith("_")}
    assert public == set(functions) | {"Scene", "SceneError"}
    assert {"Scene", "SceneError"} <= set(classes)
    for name, node in functions.items():
        params = list(inspect.signature(getattr(_nffrt, name)).parameters)
        assert params == [a.arg for a in node.args.args], name
    members = {n.name for n in classes["Scene"].body if isinstance(n, ast.FunctionDef)}
    runtime = {n for n in dir(_nffrt.Scene) if not n.startswith("__")}
    assert members == runtime
    params = list(inspect.signature(_nffrt.Scene.render).parameters)
    stub_render = next(n for n in classes["Scene"].body if isinstance(n, ast.FunctionDef) and n.name == "render")
    assert params == [a.arg for a in stub_render.args.args]


def test_light_samples_and_seed_are_the_command_lines() -> None:
    import subprocess, tempfile, os
    text = (
        "spp 4\ncamera eye 0 -6 3 at 0 0 0.5 up 0 0 1 angle 40 hither 1 resolution 12 9\n"
        "light quad -1 -1 4 1 1 1 1 -1 4 -1 1 4 2\n"
        "mat 0.9 0.8 0.6 1 1 1 1 0 10 0 1\np 4 -10 -10 0 10 -10 0 10 10 0 -10 10 0\n"
        "mat 0.8 0.2 0.2 0.8 1 1 1 0.2 40 0 1\ns 0 0 0.8 0.8\n"
    )
    scene = nffrt.parse(text, format="p3f")
    base = scene.render()
    assert scene.render(seed=0).tobytes() == base.tobytes()
    seeded = scene.render(seed=3, light_samples=3)
    assert seeded.tobytes() != base.tobytes()
    with tempfile.TemporaryDirectory() as d:
        path = os.path.join(d, "s.p3f")
        with open(path, "w") as f:
            f.write(text)
        out = os.path.join(d, "x.pfm")
        binary = os.environ.get("NFFRT_BIN", "nffrt")
        subprocess.run([binary, "render", path, "--seed", "3", "--light-samples", "3", "-q", "-o", out], check=True)
        assert read_pfm(Path(out)).tobytes() == seeded.tobytes()
