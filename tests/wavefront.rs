//! The wavefront path tracer against the scalar one: every example scene, textured
//! AFF surfaces (a small scene, and the kitchen), and the
//! course's path-traced ones where `../shared` has them, rendered both ways. A
//! render traces its paths in queues and its rays in packets; `--pixel` traces each
//! sample's path alone, one query at a time, reporting every event (the reference
//! kept for that). Each pixel must come out bit for bit the same, with the same ray
//! counts in all.

mod common;

use std::path::{Path, PathBuf};

use common::skip;
use nffrt::load::{load, LoadOptions, Source};
use nffrt::options::{RenderOptions, Sampling};
use nffrt::prepare::{prepare, RenderScene};
use nffrt::render::debug::trace_pixel;
use nffrt::render::{render, Stats};
use nffrt::scene::IntegratorKind;

/// The scene of `path` (NFF, P3F or AFF by its extension; AFF: its frame 0), prepared.
fn scene(path: &Path) -> RenderScene {
    let loaded = load(Source::File(path), &LoadOptions::default())
        .unwrap_or_else(|e| panic!("{}: {e}", path.display()));
    prepare(loaded.scene, &loaded.assets)
}

/// Renders `scene` small with the path tracer, then traces every pixel alone, and
/// asserts the two agree bit for bit, ray counts included.
fn assert_both_ways_agree(scene: &RenderScene, what: &str) {
    let view = scene.view();
    let width = 20;
    let opts = RenderOptions {
        width,
        height: (width * view.height / view.width).max(1),
        sampling: Sampling::Stratified { spp: 3 },
        max_depth: 8,
        integrator: IntegratorKind::Path,
        ..RenderOptions::from_view(view)
    };
    let (image, stats) = render(scene, view, &opts).unwrap();
    let mut alone = Stats::default();
    for y in 0..opts.height {
        for x in 0..opts.width {
            let trace = trace_pixel(scene, view, &opts, x, y).unwrap();
            let (got, want) = (image.get(x, y), trace.value);
            assert!(
                got.to_array().map(f32::to_bits) == want.to_array().map(f32::to_bits),
                "{what} ({x}, {y}): rendered {got:?}, alone {want:?}"
            );
            alone += trace.stats;
        }
    }
    assert_eq!(stats, alone, "{what}: ray counts");
    assert!(
        stats.total_rays() > stats.eye_rays,
        "{what}: paths went past their eye rays"
    );
}

#[test]
fn every_example_renders_the_same_in_queues_as_path_by_path() {
    let dir = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("examples");
    let mut seen = 0;
    for entry in std::fs::read_dir(&dir).unwrap() {
        let path = entry.unwrap().path();
        if path.extension().is_some_and(|e| e == "p3f" || e == "nff") {
            assert_both_ways_agree(&scene(&path), &path.display().to_string());
            seen += 1;
        }
    }
    assert!(seen >= 6, "{seen} example scenes");
}

#[test]
fn the_course_scenes_render_the_same_in_queues_as_path_by_path() {
    // Point lights, a skybox, meshes, glass and moving spheres.
    for name in ["2025/balls_low.p3f", "2019/dof.p3f", "2019/balls_area_low.p3f"] {
        let Some(path) = skip::shared(&format!("scenes/p3f/{name}")) else {
            return;
        };
        assert_both_ways_agree(&scene(&path), name);
    }
}

/// A 4 x 4 texture of strong, different colours (texel (x, y): 80 x, 80 y, 255 -
/// 80 (x + y) / 2).
fn checker_ppm() -> Vec<u8> {
    let mut bytes = b"P6\n4 4\n255\n".to_vec();
    for y in 0..4u8 {
        for x in 0..4u8 {
            bytes.extend([80 * x, 80 * y, 255 - 40 * (x + y)]);
        }
    }
    bytes
}

#[test]
fn textured_aff_surfaces_render_the_same_in_queues_as_path_by_path() {
    // A textured floor (a mesh with texture coordinates past 1, which wrap) and a
    // textured wall (`tt` triangles) under a point light, with an untextured mirror
    // ball and a matte one of the same material as the floor: textured and plain
    // vertices of one material in the same queues.
    let dir = common::scratch_dir("wavefront", "textured");
    std::fs::write(dir.join("checker.ppm"), checker_ppm()).unwrap();
    let text = "v from 0 2 6 at 0 0 0 up 0 1 0 angle 45 hither 0.1 resolution 40 30\n\
                b 0.2 0.3 0.4\nl 2 4 3\n\
                fm 0 0 0  0.8 0.8 0.8  0.1 0.1 0.1  10 0 1\n\
                m vertices 4  -3 -1 -3  3 -1 -3  3 -1 3  -3 -1 3\n\
                texturecoords 4 checker.ppm  0 0  3 0  3 3  0 3\n\
                triangles 2  0 1 2  0 1 2   0 2 3  0 2 3\n\
                s -1 0 0 0.8\n\
                tt checker.ppm -3 -1 -2 0 1   3 -1 -2 1 1   3 3 -2 1 0\n\
                tt checker.ppm -3 -1 -2 0 1   3 3 -2 1 0   -3 3 -2 0 0\n\
                fm 0 0 0  0 0 0  0.9 0.9 0.9  50 0 1\n\
                s 1.2 0 0.5 0.7\n";
    let path = dir.join("textured.aff");
    std::fs::write(&path, text).unwrap();
    assert_both_ways_agree(&scene(&path), "textured AFF scene");
    if let Some(kitchen) = skip::shared("scenes/bart/kitchen/aff/kitchen.aff") {
        assert_both_ways_agree(&scene(&kitchen), "kitchen frame 0");
    }
}
