//! The path-traced example scenes (`examples/*.p3f`): each parses without a warning,
//! asks for the path tracer, says where its numbers come from, and renders small to
//! finite, non-negative, not all black pixels. The Cornell box is checked against
//! what its geometry alone predicts: seen by camera rays alone, the light covers the
//! share of the picture its corners project to, at exactly its radiance; with light
//! transport, the red wall is on the left and the green one on the right.

use std::path::PathBuf;

use nffrt::image::Image;
use nffrt::load::Assets;
use nffrt::nff::{parse_format, Format};
use nffrt::options::{RenderOptions, Sampling};
use nffrt::prepare::{prepare, RenderScene};
use nffrt::render::render;
use nffrt::scene::IntegratorKind;

fn examples_dir() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("examples")
}

/// Every `examples/*.p3f`, sorted.
fn example_files() -> Vec<PathBuf> {
    let mut all: Vec<PathBuf> = std::fs::read_dir(examples_dir())
        .unwrap()
        .map(|e| e.unwrap().path())
        .filter(|p| p.extension().is_some_and(|e| e == "p3f"))
        .collect();
    all.sort();
    all
}

fn load(path: &PathBuf) -> RenderScene {
    let text = std::fs::read(path).unwrap();
    let scene = parse_format(&text, Format::P3f, &Default::default())
        .unwrap_or_else(|e| panic!("{}: {e}", path.display()));
    assert!(
        scene.warnings.is_empty(),
        "{}: {:?}",
        path.display(),
        scene.warnings
    );
    prepare(scene, &Assets::default())
}

/// Path tracing at `width` pixels across (the height keeps the file's aspect ratio).
fn path_render(scene: &RenderScene, width: u32, spp: u32, max_depth: u32) -> Image {
    let view = scene.view();
    let opts = RenderOptions {
        width,
        height: (width * view.height / view.width).max(1),
        sampling: Sampling::Stratified { spp },
        max_depth,
        integrator: IntegratorKind::Path,
        ..RenderOptions::from_view(view)
    };
    render(scene, view, &opts).unwrap().0
}

/// The mean of each channel over the columns `x0..x1` of the rows `y0..y1`.
fn mean_rgb(image: &Image, (x0, x1): (u32, u32), (y0, y1): (u32, u32)) -> [f64; 3] {
    let mut sum = [0.0f64; 3];
    for y in y0..y1 {
        for x in x0..x1 {
            for (s, c) in sum.iter_mut().zip(image.get(x, y).to_array()) {
                *s += c as f64;
            }
        }
    }
    let n = ((x1 - x0) * (y1 - y0)) as f64;
    sum.map(|s| s / n)
}

#[test]
fn every_example_parses_asks_for_paths_and_renders() {
    let files = example_files();
    let names: Vec<String> = files
        .iter()
        .map(|p| p.file_stem().unwrap().to_string_lossy().into_owned())
        .collect();
    for want in ["cornell", "course2021", "glass-mirror", "glass-row", "weekend"] {
        assert!(
            names.iter().any(|n| n == want),
            "examples/{want}.p3f in {names:?}"
        );
    }
    for path in &files {
        let what = path.display();
        let text = std::fs::read_to_string(path).unwrap();
        assert!(text.starts_with("# "), "{what}: starts with where it comes from");
        let scene = load(path);
        assert_eq!(scene.info().integrator, Some(IntegratorKind::Path), "{what}");
        let image = path_render(&scene, 24, 2, 4);
        assert!(
            image
                .pixels
                .iter()
                .all(|p| p.to_array().iter().all(|c| c.is_finite() && *c >= 0.0)),
            "{what}: a pixel negative or not finite"
        );
        let mean = mean_rgb(&image, (0, image.width), (0, image.height));
        assert!(mean.iter().sum::<f64>() > 0.01, "{what}: black, mean {mean:?}");
    }
}

/// The fraction of a square picture that the Cornell light's quad covers, from its
/// corners alone: the camera at z = 3.9 looks down -z with a vertical field of view
/// of 39.3077 degrees; the light spans x in [-0.23, 0.23] at y = 0.99, from z = -0.18
/// to 0.2. Its image is a trapezoid between the rows of its far and near edges.
fn cornell_light_coverage() -> f64 {
    let tan_half = (39.3077f64.to_radians() / 2.0).tan();
    // Normalised device coordinates, [-1, 1] across the picture.
    let ndc = |v: f64, z: f64| v / (3.9 - z) / tan_half;
    let (far, near) = (-0.18, 0.2);
    let height = ndc(0.99, near) - ndc(0.99, far);
    let mean_width = (ndc(0.46, far) + ndc(0.46, near)) / 2.0;
    height * mean_width / 4.0
}

#[test]
fn the_cornell_light_covers_its_projection_at_its_radiance() {
    let scene = load(&examples_dir().join("cornell.p3f"));
    // Depth 1: camera rays alone, which see emitters and nothing else. At 128 pixels
    // the light's edges cost under 0.2 % (0.9 % at 64); a field of view of 40 degrees
    // instead of 39.3 misses by 2.8 %, a light facing up by 100 %.
    let image = path_render(&scene, 128, 16, 1);
    let mean = mean_rgb(&image, (0, 128), (0, 128));
    let coverage = cornell_light_coverage();
    for (got, radiance) in mean.iter().zip([18.387, 13.9873, 6.75357]) {
        let want = coverage * radiance;
        assert!(
            (got - want).abs() < 0.01 * want,
            "mean {mean:?}: want {want} (coverage {coverage} x radiance {radiance})"
        );
    }
}

#[test]
fn the_cornell_box_has_its_red_wall_left_and_green_wall_right() {
    let scene = load(&examples_dir().join("cornell.p3f"));
    let image = path_render(&scene, 32, 8, 8);
    // The walls' middles, clear of the floor, the ceiling and the boxes. Lit by the
    // warm light, the green wall reflects about 2.7 times as much green as red.
    let [r, g, _] = mean_rgb(&image, (1, 4), (8, 24));
    assert!(r > 4.0 * g, "left strip: red {r}, green {g}");
    let [r, g, _] = mean_rgb(&image, (28, 31), (8, 24));
    assert!(g > 1.5 * r, "right strip: red {r}, green {g}");
    let all = mean_rgb(&image, (0, 32), (0, 32));
    assert!(all.iter().all(|c| c.is_finite() && *c > 0.05), "mean {all:?}");
}
