//! No NaN or infinite pixel, ever: property tests over hostile materials (ior 0 or
//! absurd, huge shine, huge Ks), zero-length patch normals, grazing rays, rays that
//! start on a surface, and extreme scales; plus the regressions the fuzzer found and
//! the deepest ray tree the command line allows, on a small stack.
//!
//! Every material here has `Kd * C > 0`, every weight is non-negative and the
//! background is not black, so every correct pixel is strictly positive in each
//! channel: a zero pixel means the tracer's last-resort NaN guard fired, and the tests
//! reject that too.

use nffrt::image::Image;
use nffrt::load::Assets;
use nffrt::nff::parse;
use nffrt::options::{RenderOptions, Sampling};
use nffrt::prepare;
use nffrt::render::{render, Stats};
use proptest::prelude::*;

fn render_src(src: &str, size: u32, max_depth: u32, sampling: Sampling) -> (Image, Stats) {
    let scene = parse(src).unwrap_or_else(|e| panic!("{e}\n{src}"));
    let scene = prepare(scene, &Assets::default());
    let opts = RenderOptions {
        width: size,
        height: size,
        max_depth,
        sampling,
        ..Default::default()
    };
    render(&scene, scene.view(), &opts).unwrap()
}

/// Every pixel finite and strictly positive (see the module docs).
fn all_positive_and_finite(img: &Image) -> Result<(), String> {
    for (i, p) in img.pixels.iter().enumerate() {
        if !(p.is_finite() && p.x > 0.0 && p.y > 0.0 && p.z > 0.0) {
            return Err(format!("pixel {i} is {p:?}"));
        }
    }
    Ok(())
}

const BACKGROUND: &str = "b 0.2 0.3 0.4\n";

fn hostile_ior() -> impl Strategy<Value = f32> {
    prop_oneof![
        Just(0.0f32),
        Just(-1.0),
        Just(1e-30),
        Just(0.5),
        Just(1.5),
        Just(1e30),
        0.01f32..10.0
    ]
}

fn hostile_shine() -> impl Strategy<Value = f32> {
    prop_oneof![
        Just(0.0f32),
        Just(-5.0),
        Just(1e6),
        Just(1e30),
        Just(f32::MAX),
        0.0f32..200.0
    ]
}

/// `f` line: positive diffuse colour, Ks and T in [0, 1], hostile shine and ior.
fn material() -> impl Strategy<Value = String> {
    (
        0.1f32..1.0,
        0.1f32..1.0,
        0.0f32..=1.0,
        hostile_shine(),
        0.0f32..=1.0,
        hostile_ior(),
    )
        .prop_map(|(c, kd, ks, shine, t, ior)| format!("f {c} {c} 1 {kd} {ks} {shine} {t} {ior}\n"))
}

/// A unit vector or exactly zero (the degenerate `pp` normal).
fn normal() -> impl Strategy<Value = (f32, f32, f32)> {
    prop_oneof![
        Just((0.0f32, 0.0, 0.0)),
        (-1.0f32..1.0, -1.0f32..1.0, -1.0f32..1.0),
    ]
}

/// A small scene at scale `k`: sphere, patch, polygon and box around the origin,
/// a light possibly lying exactly on the sphere, and a camera possibly exactly on
/// the sphere or in the polygon's plane (grazing rays).
fn scene() -> impl Strategy<Value = String> {
    (
        prop::collection::vec(material(), 4),
        prop::collection::vec(normal(), 3),
        0usize..4,
        prop_oneof![Just(1.0f32), Just(1e-15), Just(1e15), 1e-3f32..1e3],
        (-1.0f32..1.0, -1.0f32..1.0),
    )
        .prop_map(|(m, nrm, camera, k, (jx, jy))| {
            let from = match camera {
                // On the sphere's surface, looking in.
                0 => (0.0, 0.0, 1.0),
                // In the plane y = -1 of the polygon and box top: grazing rays.
                1 => (5.0, -1.0, 0.5),
                // Inside the glass sphere.
                2 => (0.1, 0.1, 0.1),
                _ => (3.0 + jx, 2.0 + jy, 6.0),
            };
            let at = if camera == 1 {
                (0.0, -1.0, 0.0)
            } else {
                (jx * 0.1, jy * 0.1, 0.0)
            };
            let v = |(x, y, z): (f32, f32, f32)| format!("{} {} {}", x * k, y * k, z * k);
            let n = |(x, y, z): (f32, f32, f32)| format!("{x} {y} {z}");
            format!(
                "v from {} at {} up 0 1 0 angle 60 hither 0 resolution 6 6\n{BACKGROUND}\
                 l {}\nl {} 0.9 0.8 0.7\n\
                 {}s 0 0 0 {}\n\
                 {}pp 3 {} {} {} {} {} {}\n\
                 {}p 4 {} {} {} {}\n\
                 {}aabb {} {} {} {} {} {}\n",
                v(from),
                v(at),
                v((0.0, 1.0, 0.0)),
                v((4.0, 4.0, 4.0)),
                m[0],
                k,
                m[1],
                v((-2.0, 0.0, -1.0)),
                n(nrm[0]),
                v((2.0, 0.0, -1.0)),
                n(nrm[1]),
                v((0.0, 2.0, -1.0)),
                n(nrm[2]),
                m[2],
                v((-3.0, -1.0, -3.0)),
                v((3.0, -1.0, -3.0)),
                v((3.0, -1.0, 3.0)),
                v((-3.0, -1.0, 3.0)),
                m[3],
                -4.0 * k,
                -3.5 * k,
                -2.0 * k,
                -k,
                -k,
                k,
            )
        })
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(96))]

    #[test]
    fn hostile_scenes_give_finite_positive_pixels(src in scene()) {
        for sampling in [Sampling::PixelCenters, Sampling::SpdCorners] {
            let (img, _) = render_src(&src, 6, 8, sampling);
            prop_assert!(all_positive_and_finite(&img).is_ok(), "{:?}\n{}", all_positive_and_finite(&img), src);
        }
    }
}

/// Found by the property test above: shine 1e30, where a highlight cosine that
/// rounds to just above 1 made (n.h)^shine infinite and the pixel black.
#[test]
fn a_highlight_cosine_rounding_above_one_stays_finite() {
    let src = "v from 100000000000000 100000000000000 100000000000000 at 93603710000000 -6043547000000 0 \
               up 0 1 0 angle 60 hither 0 resolution 6 6\nb 0.2 0.3 0.4\nl 0 1000000000000000 0\n\
               l 4000000000000000 4000000000000000 4000000000000000 0.9 0.8 0.7\n\
               f 0.1 0.1 1 0.1 0.91454345 1000000000000000000000000000000 0 0\ns 0 0 0 1000000000000000\n";
    let (img, _) = render_src(src, 6, 8, Sampling::PixelCenters);
    assert_eq!(all_positive_and_finite(&img), Ok(()));
}

/// Found by the `parse_render` fuzz target: Ks = 7.8e19 makes corners of about 1e38,
/// whose four-corner sum in the SPD protocol overflowed to infinity.
#[test]
fn huge_ks_corners_average_without_overflow() {
    let src = "f 0 1 1 0.05 077777777777777777777.1 77200 0.9 1.5\ns -1.6 -0.8 1 3\n";
    for sampling in [Sampling::PixelCenters, Sampling::SpdCorners] {
        let (img, _) = render_src(src, 8, 4, sampling);
        assert!(img.pixels.iter().all(|p| p.is_finite()), "{sampling:?}");
    }
}

/// Glass with ior 0 (read as 1), ior -1 and huge shine, all at once: finite and
/// positive, and the refraction rays are really traced.
#[test]
fn ior_zero_and_huge_shine_are_harmless() {
    for ior in ["0", "-1", "1e-30", "1e30"] {
        let src = format!(
            "v from 0 0 5 at 0 0 0 up 0 1 0 angle 40 hither 1 resolution 8 8\n{BACKGROUND}l 0 3 5\n\
             f 0.5 0.5 0.5 0.5 0.5 1e6 0.9 {ior}\ns 0 0 0 1\n"
        );
        let (img, stats) = render_src(&src, 8, 5, Sampling::PixelCenters);
        assert_eq!(all_positive_and_finite(&img), Ok(()), "ior {ior}");
        assert!(stats.refraction_rays + stats.reflection_rays > 0, "ior {ior}");
    }
}

/// A patch whose vertex normals are all zero shades with its geometric normal's
/// lighting gone, but never NaN.
#[test]
fn zero_length_patch_normals_are_harmless() {
    let src = format!(
        "v from 0 0 5 at 0 0 0 up 0 1 0 angle 40 hither 1 resolution 8 8\n{BACKGROUND}l 0 0 5\n\
         f 1 1 1 1 0.5 20 0 1\npp 3 -2 -2 0 0 0 0 2 -2 0 0 0 0 0 2 0 0 0 0\n"
    );
    let (img, stats) = render_src(&src, 8, 5, Sampling::PixelCenters);
    assert!(stats.eye_hits > 0);
    assert_eq!(all_positive_and_finite(&img), Ok(()));
}

/// The deepest tree `--max-depth` allows (64) inside a mirror box, where every ray
/// bounces until the limit, traced on a 512 KiB stack: a quarter of the 2 MiB that
/// rayon's worker threads get by default.
#[test]
fn depth_64_in_a_mirror_box_fits_a_small_stack() {
    // From the exact centre: symmetric eye rays strike the box's edges, which must
    // keep them inside as well (see the next test).
    let src = "v from 0 0 0 at 0.3 -0.2 -1 up 0 1 0 angle 60 hither 0 resolution 4 4\n\
               l 0.5 0.5 0.5\nf 0.5 0.5 0.5 0.2 1 20 0 1\naabb -1 1 -1 1 -1 1\n";
    let scene = parse(src).unwrap();
    let scene = prepare(scene, &Assets::default());
    let opts = RenderOptions {
        width: 4,
        height: 4,
        max_depth: 64,
        sampling: Sampling::PixelCenters,
        ..Default::default()
    };
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(1)
        .stack_size(512 * 1024)
        .build()
        .unwrap();
    let (img, stats) = pool.install(|| render(&scene, scene.view(), &opts)).unwrap();
    assert_eq!(stats.eye_hits, 16);
    assert_eq!(stats.reflection_rays, 16 * 63);
    assert_eq!(stats.secondary_hits, 16 * 63);
    assert!(img.pixels.iter().all(|p| p.is_finite() && p.x > 0.0));
}

/// Rays that strike a box exactly on an edge or a corner stay inside it. From the
/// exact centre of a mirror box, a 3x3 image with a 90-degree angle between the
/// outer pixel centres sends its eye rays along (±1, ±1, -1), (±1, 0, -1), ... :
/// eight of the nine meet an edge or a corner of the box exactly. A secondary ray
/// must not start on a face it is about to leave through, so every ray of every
/// bounce hits the box again (the box is closed): 9 eye hits, 9 x 15 secondary hits.
#[test]
fn mirror_box_edges_and_corners_keep_every_ray_inside() {
    let src = "v from 0 0 0 at 0 0 -1 up 0 1 0 angle 90 hither 0 resolution 3 3\n\
               l 0.5 0.5 0.5\nf 0.5 0.5 0.5 0.2 1 20 0 1\naabb -1 1 -1 1 -1 1\n";
    let scene = parse(src).unwrap();
    let scene = prepare(scene, &Assets::default());
    let opts = RenderOptions {
        width: 3,
        height: 3,
        max_depth: 16,
        sampling: Sampling::PixelCenters,
        ..Default::default()
    };
    let (img, stats) = render(&scene, scene.view(), &opts).unwrap();
    assert_eq!(stats.eye_hits, 9);
    assert_eq!(stats.reflection_rays, 9 * 15);
    assert_eq!(stats.secondary_hits, 9 * 15, "a ray escaped the closed box");
    assert!(img.pixels.iter().all(|p| p.is_finite() && p.x > 0.0));
}
