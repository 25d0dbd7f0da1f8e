//! The path tracer against values known without it: white furnaces (a sphere lit
//! only by a uniform background of radiance 1 reflects its albedo, and a smooth
//! non-absorbing glass sphere lets everything through: the picture is the
//! background's), a diffuse sphere inside an emitting sphere (radiance albedo x
//! emitted: next-event estimation and BSDF sampling weighted by MIS must add up),
//! and the picture the same on any thread count and in tiles.

use nffrt::image::{Image, Region};
use nffrt::load::Assets;
use nffrt::nff::{parse_format, Format};
use nffrt::options::{RenderLimits, RenderOptions, Sampling};
use nffrt::prepare::{prepare, RenderScene};
use nffrt::render::{render, render_region, Silent};
use nffrt::scene::IntegratorKind;

fn p3f(text: &str) -> RenderScene {
    let scene = parse_format(text.as_bytes(), Format::P3f, &Default::default()).unwrap();
    prepare(scene, &Assets::default())
}

fn path_opts(scene: &RenderScene, spp: u32, max_depth: u32) -> RenderOptions {
    RenderOptions {
        sampling: Sampling::Stratified { spp },
        max_depth,
        integrator: IntegratorKind::Path,
        ..RenderOptions::from_view(scene.view())
    }
}

/// Every channel of every pixel within `tolerance` of `want`, and the image's mean
/// within `mean_tolerance`.
fn assert_everywhere(image: &Image, want: f32, tolerance: f32, mean_tolerance: f32, what: &str) {
    let mut sum = 0.0f64;
    for (i, p) in image.pixels.iter().enumerate() {
        for c in p.to_array() {
            assert!(
                (c - want).abs() <= tolerance,
                "{what}: pixel {i} is {p:?}, want {want}"
            );
            sum += c as f64;
        }
    }
    let mean = sum / (3 * image.pixels.len()) as f64;
    assert!(
        (mean - want as f64).abs() <= mean_tolerance as f64,
        "{what}: mean {mean}, want {want}"
    );
}

const CAMERA: &str = "camera eye 0 0 5 at 0 0 0 up 0 1 0 angle 30 hither 1 resolution 16 16\n";

/// A Lambertian sphere of albedo 1 under a white background of radiance 1 renders 1
/// everywhere; of albedo 0.5, 0.5 on the sphere (every path leaves a convex sphere
/// at its first bounce and sees the background: exactly so, up to rounding).
#[test]
fn a_white_furnace_returns_the_albedo() {
    let one = p3f(&format!(
        "{CAMERA}bclr 1 1 1\nmat 1 1 1 1 0 0 0 0 1 0 1\ns 0 0 0 1\n"
    ));
    let (image, _) = render(&one, one.view(), &path_opts(&one, 16, 8)).unwrap();
    assert_everywhere(&image, 1.0, 1e-5, 1e-6, "albedo 1");
    let half = p3f(&format!(
        "{CAMERA}bclr 1 1 1\nmat 1 1 1 0.5 0 0 0 0 1 0 1\ns 0 0 0 1.5\n"
    ));
    let (image, _) = render(&half, half.view(), &path_opts(&half, 16, 8)).unwrap();
    // The sphere of radius 1.5 at distance 5 fills the centre of the 30-degree view.
    for y in 6..10 {
        for x in 6..10 {
            let p = image.get(x, y);
            for c in p.to_array() {
                assert!((c - 0.5).abs() < 1e-5, "({x}, {y}): {p:?}");
            }
        }
    }
}

/// A smooth glass sphere (index 1.5, white: no absorption) under a white background
/// renders 1 within sampling error: Fresnel splits, refraction scales radiance by
/// 1/eta^2 going in and eta^2 coming out, and every path ends in the background.
#[test]
fn a_smooth_dielectric_sphere_in_the_furnace_renders_one() {
    let glass = p3f(&format!(
        "{CAMERA}bclr 1 1 1\nmat 1 1 1 0 1 1 1 0 1 1 1.5\ns 0 0 0 1\n"
    ));
    let (image, _) = render(&glass, glass.view(), &path_opts(&glass, 256, 64)).unwrap();
    assert_everywhere(&image, 1.0, 0.03, 0.002, "glass");
    let rough = p3f(&format!(
        "{CAMERA}bclr 1 1 1\nmat 1 1 1 0 1 1 1 0 1 1 1.5 roughness 0.3\ns 0 0 0 1\n"
    ));
    let (image, _) = render(&rough, rough.view(), &path_opts(&rough, 256, 64)).unwrap();
    // Rough: single scattering on microfacets loses a little (Walter et al.'s model
    // has no multiple scattering between facets), never gains.
    let mean = image.pixels.iter().map(|p| p.x as f64).sum::<f64>() / image.pixels.len() as f64;
    assert!(mean > 0.95 && mean < 1.005, "rough glass mean {mean}");
}

/// A diffuse sphere of albedo 0.5 inside a black sphere that emits radiance 2
/// inwards: it sees 2 from every direction, so it reflects 0.5 x 2 = 1. Light
/// samples (the emitter by area) and BSDF samples (which meet it too) are combined by
/// the power heuristic; either alone would also give 1, a wrong weight would not.
#[test]
fn an_emitting_enclosure_lights_a_diffuse_sphere_to_albedo_times_radiance() {
    let scene = p3f(
        "camera eye 0 0 3 at 0 0 0 up 0 1 0 angle 20 hither 1 resolution 16 16\n\
         bclr 0 0 0\nmat 0 0 0 0 0 0 0 0 1 0 1 2 2 2\ns 0 0 0 -6\n\
         mat 1 1 1 0.5 0 0 0 0 1 0 1\ns 0 0 0 1.5\n",
    );
    let (image, _) = render(&scene, scene.view(), &path_opts(&scene, 256, 4)).unwrap();
    assert_everywhere(&image, 1.0, 0.05, 0.003, "enclosure");
}

/// Path-traced pictures are deterministic: the same bytes on 1 and 2 threads, and a
/// region has exactly the full picture's pixels.
#[test]
fn path_pictures_are_the_same_on_any_thread_count_and_in_tiles() {
    let scene = p3f(&format!(
        "{CAMERA}bclr 0.2 0.3 0.5\nlight quad -1 3 -1 1 1 1 1 3 -1 -1 3 1 2\n\
         mat 0 0 0 0 0 0 0 0 1 0 1 4 4 4\np 4 -0.5 2.5 -0.5 0.5 2.5 -0.5 0.5 2.5 0.5 -0.5 2.5 0.5\n\
         mat 0.8 0.3 0.3 0.9 1 1 1 0.3 10 0 1 roughness 0.4\ns -0.6 0 0 0.6\n\
         mat 0.9 0.9 1 0 1 1 1 0 10 1 1.5 roughness 0.1\ns 0.6 0 0 0.5\n"
    ));
    let opts = path_opts(&scene, 8, 6);
    let on = |threads: usize| {
        let pool = rayon::ThreadPoolBuilder::new()
            .num_threads(threads)
            .build()
            .unwrap();
        pool.install(|| render(&scene, scene.view(), &opts).unwrap().0)
    };
    let full = on(1);
    assert_eq!(on(2), full);
    let r = Region {
        x0: 3,
        y0: 5,
        x1: 11,
        y1: 13,
    };
    let (crop, _) =
        render_region(&scene, scene.view(), &opts, &r, &RenderLimits::default(), &Silent).unwrap();
    for y in 0..crop.height {
        for x in 0..crop.width {
            assert_eq!(crop.get(x, y), full.get(x + r.x0, y + r.y0));
        }
    }
}
