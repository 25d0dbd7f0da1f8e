//! Whole-render tests through the library: determinism across thread counts, an
//! analytic pixel, shadow logic, and depth limits.

use nffrt::image::Image;
use nffrt::load::Assets;
use nffrt::nff::parse;
use nffrt::options::{RenderOptions, Sampling};
use nffrt::prepare;
use nffrt::render::{render, Stats};

fn render_with_threads(src: &str, threads: usize, sampling: Sampling) -> (Image, Stats) {
    let scene = parse(src).unwrap();
    let scene = prepare(scene, &Assets::default());
    let opts = RenderOptions {
        sampling,
        ..RenderOptions::from_view(scene.view())
    };
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(threads)
        .build()
        .unwrap();
    pool.install(|| render(&scene, scene.view(), &opts)).unwrap()
}

fn example() -> String {
    std::fs::read_to_string(concat!(env!("CARGO_MANIFEST_DIR"), "/examples/showcase.nff")).unwrap()
}

/// The same floats bit for bit (not only the same 8-bit picture) and the same ray
/// counts on one thread and on two, with each sampling.
#[test]
fn one_and_two_threads_give_identical_images() {
    let bits = |image: &Image| -> Vec<[u32; 3]> {
        image
            .pixels
            .iter()
            .map(|p| p.to_array().map(f32::to_bits))
            .collect()
    };
    for sampling in [
        Sampling::PixelCenters,
        Sampling::SpdCorners,
        Sampling::Stratified { spp: 3 },
    ] {
        let (a, sa) = render_with_threads(&example(), 1, sampling);
        let (b, sb) = render_with_threads(&example(), 2, sampling);
        assert!(bits(&a) == bits(&b), "{sampling}: the floats differ");
        assert_eq!(sa, sb);
    }
}

/// One sphere of radius 1 at the origin, one white light on the camera axis, and a
/// camera on the z axis: the centre pixel sees the sphere's pole with n = l = v, so
/// colour = A*Kd*C + I*(Kd*C*1 + Ks*1^shine) with A = I = sqrt(1)/(2*1) = 0.5.
#[test]
fn centre_pixel_matches_the_hand_computed_value() {
    let src = "v from 0 0 10 at 0 0 0 up 0 1 0 angle 20 hither 1 resolution 9 9\n\
               l 0 0 20\nf 0.8 0.4 0.2 0.5 0.25 10 0 1\ns 0 0 0 1\n";
    let (img, stats) = render_with_threads(src, 1, Sampling::PixelCenters);
    let p = img.get(4, 4);
    // Kd*C = (0.4, 0.2, 0.1); ambient 0.5*(0.4,0.2,0.1) + 0.5*((0.4,0.2,0.1) + 0.25)
    // plus the reflection ray (Ks = 0.25) seeing the black background.
    let want = [0.2 + 0.125 + 0.2, 0.1 + 0.125 + 0.1, 0.05 + 0.125 + 0.05];
    for (got, want) in [p.x, p.y, p.z].iter().zip(want) {
        assert!((got - want).abs() < 1e-4, "{p:?} vs {want:?}");
    }
    assert_eq!(stats.eye_rays, 81);
    // The corner pixels miss the sphere (angle 20: the corners look 12.5 degrees off axis,
    // beyond the sphere's 5.7-degree radius).
    assert_eq!(img.get(0, 0).x, 0.0);
}

/// A light behind the surface casts no shadow ray; a light blocked by a sphere counts
/// one blocked shadow ray per lit hit.
#[test]
fn shadow_rays_follow_the_spd_rules() {
    let src = "v from 0 0 10 at 0 0 0 up 0 1 0 angle 1 hither 1 resolution 1 1\n\
               l 0 0 -20\nf 1 1 1 1 0 1 0 1\np 4 -5 -5 0 5 -5 0 5 5 0 -5 5 0\n";
    let (_, st) = render_with_threads(src, 1, Sampling::PixelCenters);
    assert_eq!((st.eye_hits, st.shadow_rays), (1, 0));
    let blocked = "v from 0 0 10 at 0 0 0 up 0 1 0 angle 1 hither 1 resolution 1 1\n\
                   l 0 0 20\nf 1 1 1 1 0 1 0 1\np 4 -5 -5 0 5 -5 0 5 5 0 -5 5 0\ns 0 0 15 1\n";
    let (img, st) = render_with_threads(blocked, 1, Sampling::PixelCenters);
    assert_eq!((st.shadow_rays, st.shadow_blocked), (1, 1));
    // Only the ambient term remains: A * Kd * C = 0.5.
    assert!((img.get(0, 0).x - 0.5).abs() < 1e-6);
}

/// Two parallel mirrors facing each other: the ray tree is a chain, so depth d gives
/// exactly d - 1 reflection rays.
#[test]
fn max_depth_bounds_the_ray_tree() {
    let src = "v from 0 0 5 at 0 0 0 up 0 1 0 angle 1 hither 1 resolution 1 1\n\
               f 1 1 1 0 1 1 0 1\np 4 -5 -5 0 5 -5 0 5 5 0 -5 5 0\np 4 -5 -5 6 -5 5 6 5 5 6 5 -5 6\n";
    for depth in [1, 2, 5, 9] {
        let scene = parse(src).unwrap();
        let scene = prepare(scene, &Assets::default());
        let opts = RenderOptions {
            max_depth: depth,
            ..RenderOptions::from_view(scene.view())
        };
        let (_, st) = render(&scene, scene.view(), &opts).unwrap();
        assert_eq!(st.reflection_rays, depth as u64 - 1, "depth {depth}");
    }
}
