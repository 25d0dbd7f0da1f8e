//! Anti-aliasing and `--pixel` through the library: supersampling is deterministic
//! across runs and thread counts, averages an edge as its coverage says, crops equal
//! the full render, and the traced pixel is the rendered one.

use nffrt::image::{Image, Region};
use nffrt::load::Assets;
use nffrt::nff::parse;
use nffrt::options::{RenderLimits, RenderOptions, Sampling};
use nffrt::prepare;
use nffrt::render::debug::trace_pixel;
use nffrt::render::{render, render_region, Silent};
use nffrt::{RenderScene, Scene};

fn showcase() -> RenderScene {
    let src = std::fs::read_to_string(concat!(env!("CARGO_MANIFEST_DIR"), "/examples/showcase.nff")).unwrap();
    prepare(parse(&src).unwrap(), &Assets::default())
}

fn opts(sampling: Sampling) -> RenderOptions {
    RenderOptions {
        width: 48,
        height: 36,
        max_depth: 5,
        sampling,
        ..Default::default()
    }
}

fn render_on(threads: usize, scene: &RenderScene, o: &RenderOptions) -> Image {
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(threads)
        .build()
        .unwrap();
    pool.install(|| render(scene, scene.view(), o).unwrap().0)
}

#[test]
fn spp4_is_identical_across_runs_and_thread_counts() {
    let scene = showcase();
    let o = opts(Sampling::Stratified { spp: 4 });
    let first = render_on(1, &scene, &o);
    for threads in [1, 2, 3, 8] {
        for _ in 0..2 {
            assert!(render_on(threads, &scene, &o) == first, "{threads} threads");
        }
    }
    // The jitter really moved the samples: edges differ from the 1-spp image.
    let centres = render_on(2, &scene, &opts(Sampling::PixelCenters));
    let differing = first
        .pixels
        .iter()
        .zip(&centres.pixels)
        .filter(|(a, b)| a != b)
        .count();
    assert!(differing > 100, "{differing}");
}

#[test]
fn one_sample_per_pixel_is_the_pixel_centre() {
    let scene = showcase();
    let a = render_on(2, &scene, &opts(Sampling::Stratified { spp: 1 }));
    let b = render_on(2, &scene, &opts(Sampling::PixelCenters));
    assert!(a == b);
}

/// A matte white square (ambient only: no lights, so A = 1 and the colour is
/// Kd * C = 1) covering world x < 0, seen head-on on a black background, 3 pixels
/// wide: the edge x = 0 runs down the middle of pixel column 1.
fn half_covered() -> Scene {
    parse(
        "b 0 0 0\nv from 0 0 10 at 0 0 0 up 0 1 0 angle 10 hither 1 resolution 3 1\n\
         f 1 1 1 1 0 1 0 1\np 4 -50 -50 0 0 -50 0 0 50 0 -50 50 0\n",
    )
    .unwrap()
}

#[test]
fn supersampling_averages_an_edge_by_its_coverage() {
    let scene = half_covered();
    let scene = prepare(scene, &Assets::default());
    let value = |spp| {
        let o = RenderOptions {
            sampling: Sampling::Stratified { spp },
            ..RenderOptions::from_view(scene.view())
        };
        let img = render(&scene, scene.view(), &o).unwrap().0;
        // The outer columns are fully inside and fully outside.
        assert_eq!((img.get(0, 0).x, img.get(2, 0).x), (1.0, 0.0), "spp {spp}");
        img.get(1, 0).x
    };
    // With 2, 4 (2x2) or 16 (4x4) strata, the edge is a stratum boundary: exactly
    // half the samples fall on the square whatever the jitter.
    for spp in [2, 4, 16] {
        assert_eq!(value(spp), 0.5, "spp {spp}");
    }
    // With 3 strata across (3x1) the middle one straddles the edge: 1/3 or 2/3.
    let v = value(3);
    assert!(
        (v - 1.0 / 3.0).abs() < 1e-6 || (v - 2.0 / 3.0).abs() < 1e-6,
        "{v}"
    );
}

#[test]
fn a_region_has_exactly_the_full_renders_pixels() {
    let scene = showcase();
    for sampling in [
        Sampling::PixelCenters,
        Sampling::SpdCorners,
        Sampling::Stratified { spp: 6 },
    ] {
        let o = opts(sampling);
        let full = render(&scene, scene.view(), &o).unwrap().0;
        let r = Region {
            x0: 7,
            y0: 3,
            x1: 30,
            y1: 36,
        };
        let crop = render_region(&scene, scene.view(), &o, &r, &RenderLimits::default(), &Silent)
            .unwrap()
            .0;
        assert_eq!((crop.width, crop.height), (23, 33));
        for y in 0..crop.height {
            for x in 0..crop.width {
                assert_eq!(
                    crop.get(x, y),
                    full.get(x + r.x0, y + r.y0),
                    "{sampling} ({x}, {y})"
                );
            }
        }
    }
}

#[test]
fn a_traced_pixel_is_the_rendered_pixel() {
    let scene = showcase();
    for (sampling, rays) in [
        (Sampling::PixelCenters, 1),
        (Sampling::SpdCorners, 4),
        (Sampling::Stratified { spp: 5 }, 5),
    ] {
        let o = opts(sampling);
        let full = render(&scene, scene.view(), &o).unwrap().0;
        for (x, y) in [(0, 0), (13, 20), (30, 17), (47, 35)] {
            let t = trace_pixel(&scene, scene.view(), &o, x, y).unwrap();
            assert_eq!(t.value, full.get(x, y), "{sampling} ({x}, {y})");
            assert_eq!(t.samples.len(), rays);
            assert_eq!(t.stats.eye_rays, rays as u64);
        }
    }
}

#[test]
fn a_seed_gives_another_pattern_as_deterministic_and_seed_zero_is_the_default() {
    let scene = showcase();
    let o = opts(Sampling::Stratified { spp: 4 });
    let default = render_on(2, &scene, &o);
    let zero = RenderOptions { seed: 0, ..o };
    assert_eq!(render_on(1, &scene, &zero), default);
    let seven = RenderOptions { seed: 7, ..o };
    let a = render_on(1, &scene, &seven);
    assert_eq!(render_on(2, &scene, &seven), a, "seed 7 on 1 and 2 threads");
    assert_ne!(a, default);
    // The same scene, independent noise: the two patterns differ on many pixels, not
    // in the mean (both estimate the same picture).
    let differing = a
        .pixels
        .iter()
        .zip(&default.pixels)
        .filter(|(p, q)| p != q)
        .count();
    assert!(differing > a.pixels.len() / 10, "{differing} pixels differ");
    let mean = |i: &Image| i.pixels.iter().map(|p| p.x + p.y + p.z).sum::<f32>() / i.pixels.len() as f32;
    assert!((mean(&a) - mean(&default)).abs() < 0.01 * mean(&default));
}
