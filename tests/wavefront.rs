//! The wavefront path tracer against the scalar one: every example scene, and the
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

/// The scene of `path` (NFF or P3F by its extension), prepared.
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
