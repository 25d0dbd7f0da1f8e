//! Distribution ray tracing against independent values: the thin lens's focal plane
//! and circle of confusion, the penumbra of a straight edge under a quad light, and
//! the error of stratified against independent sampling.

use nffrt::load::Assets;
use nffrt::math::{Ray, Vec3};
use nffrt::nff::{parse_format, Format};
use nffrt::options::{RenderLimits, RenderOptions, Sampling};
use nffrt::prepare;
use nffrt::render::{render, Camera, CameraSample, NoRecord, RowTracer, SampleId, TraceContext};
use nffrt::Scene;

fn p3f(src: &str) -> Scene {
    parse_format(src.as_bytes(), Format::P3f, &Default::default()).expect("a valid P3F scene")
}

/// Where `ray` crosses the plane `dot(p - origin, forward) = depth`.
fn at_depth(ray: &Ray, origin: Vec3, forward: Vec3, depth: f32) -> Vec3 {
    let t = (depth - (ray.origin - origin).dot(forward)) / ray.dir.dot(forward);
    ray.at(t)
}

/// A P3F camera 10 units from its target, 90 degrees edge to edge over 100 rows:
/// the view plane at d = 10 is 20 units high, a pixel 0.2 units; aperture 8 pixels
/// makes a lens 1.6 units across (radius 0.8); focal 1.5 puts sharp focus at 15.
const LENS_CAMERA: &str = "camera eye 0 0 10 at 0 0 0 up 0 1 0 angle 90 hither 1 resolution 100 100 \
                           aperture 8 focal 1.5\nmat 1 1 1 1 1 1 1 0 10 0 1\ns 0 0 0 1\n";

#[test]
fn lens_rays_meet_on_the_focal_plane_and_spread_by_the_circle_of_confusion_off_it() {
    let scene = p3f(LENS_CAMERA);
    let opts = RenderOptions::from_view(&scene.view);
    let camera = Camera::new(&scene.view, &opts);
    assert!(camera.has_lens());
    let (eye, forward) = (Vec3::new(0.0, 0.0, 10.0), Vec3::new(0.0, 0.0, -1.0));
    let lens_radius = 0.8f32;
    let focal = 15.0f32;
    // Lens positions all over the disc, its rim included ((1, 0.5) maps to the rim).
    let lens: Vec<(f32, f32)> = (0..=8)
        .flat_map(|i| (0..=8).map(move |j| (i as f32 / 8.0, j as f32 / 8.0)))
        .chain([(1.0, 0.5), (0.0, 0.5), (0.5, 1.0), (0.5, 0.0)])
        .collect();
    for raster in [(50.0, 50.0), (13.5, 71.25), (99.0, 0.5)] {
        let rays: Vec<Ray> = lens
            .iter()
            .map(|&l| {
                camera.ray(&CameraSample {
                    raster,
                    lens: l,
                    time: 0.5,
                })
            })
            .collect();
        // On the focal plane every lens ray of one raster position meets one point:
        // the pinhole ray's.
        let pinhole = camera.ray(&CameraSample::at(raster.0, raster.1));
        let sharp = at_depth(&pinhole, eye, forward, focal);
        for r in &rays {
            let p = at_depth(r, eye, forward, focal);
            assert!((p - sharp).length() < 1e-4, "{raster:?}: {p:?} vs {sharp:?}");
        }
        // Off it, at depth z, they spread over a disc of diameter 2 r |1 - z / f|.
        for z in [5.0f32, 10.0, 30.0] {
            let pts: Vec<Vec3> = rays.iter().map(|r| at_depth(r, eye, forward, z)).collect();
            let spread = pts
                .iter()
                .flat_map(|a| pts.iter().map(move |b| (*a - *b).length()))
                .fold(0.0f32, f32::max);
            let want = 2.0 * lens_radius * (1.0 - z / focal).abs();
            assert!(
                (spread - want).abs() < 1e-3 * want.max(1.0),
                "{raster:?} z {z}: {spread} vs {want}"
            );
        }
    }
}

#[test]
fn the_penumbra_of_a_straight_edge_matches_the_visible_fraction_of_a_quad_light() {
    // A 2-wide quad light at height H = 4 (x from -1 to 1), an opaque square at
    // height h = 2 covering x < 0, and the floor z = 0. From a floor point at x = X
    // the light point at x_l is hidden where the segment between them crosses z = h at
    // x < 0: X + (x_l - X) h / H < 0, i.e. x_l < X (1 - H / h) = -X. The hidden
    // fraction of the light is therefore clamp((-X + 1) / 2, 0, 1).
    let scene = p3f(
        "camera eye 0 -10 5 at 0 0 0 up 0 0 1 angle 40 hither 1 resolution 8 8\n\
         light quad -1 -1 4 1 1 1 1 -1 4 -1 1 4 1\n\
         mat 1 1 1 1 1 1 1 0 10 0 1\n\
         p 4 -50 -50 2 0 -50 2 0 50 2 -50 50 2\n\
         p 4 -50 -50 0 50 -50 0 50 50 0 -50 50 0\n",
    );
    let scene = prepare(scene, &Assets::default());
    let n = 256;
    let opts = RenderOptions {
        sampling: Sampling::Stratified { spp: n },
        ..RenderOptions::from_view(scene.view())
    };
    let frame = RowTracer::new(&scene, scene.view(), &opts);
    for (k, x) in [-1.5f32, -0.6, -0.25, 0.0, 0.3, 0.75, 1.4]
        .into_iter()
        .enumerate()
    {
        // The eye ray of each sample drops straight onto the floor point (x, 0.3, 0)
        // from just above it, under the occluder; sample s takes stratum pi(s) of the
        // light, so the n samples cover its n strata once each.
        let mut ctx = TraceContext::default();
        for index in 0..n {
            let id = SampleId::new(k as u32, 0, index, n, true);
            let down = Ray::new(Vec3::new(x, 0.3, 0.5), Vec3::new(0.0, 0.0, -1.0));
            frame.ray_radiance(&down, &id, &mut ctx, &mut NoRecord);
        }
        let stats = ctx.stats;
        assert_eq!(stats.shadow_rays, n as u64, "x {x}");
        let hidden = stats.shadow_blocked as f32 / n as f32;
        let want = ((-x + 1.0) / 2.0).clamp(0.0, 1.0);
        // 16 x 16 strata: a straight edge across them leaves at most one column of
        // 16 strata undecided, 1/16 of the light.
        assert!(
            (hidden - want).abs() <= 1.0 / 16.0 + 1e-6,
            "x {x}: hidden {hidden}, analytic {want}"
        );
    }
}

/// A scene with soft shadows and depth of field: a quad light, a sphere casting a
/// shadow on a floor, and a lens focused in front of the sphere.
const SOFT_SCENE: &str = "camera eye 0 -6 3 at 0 0 0.5 up 0 0 1 angle 40 hither 1 resolution 24 18 \
                          aperture 3 focal 0.7\n\
                          light quad -1.5 -1 4 1 1 1 1.5 -1 4 -1.5 1 4 4\n\
                          bclr 0.2 0.3 0.5\n\
                          mat 0.9 0.8 0.6 1 1 1 1 0 10 0 1\n\
                          p 4 -10 -10 0 10 -10 0 10 10 0 -10 10 0\n\
                          mat 0.8 0.2 0.2 0.8 1 1 1 0.2 40 0 1\n\
                          s 0 0 1 0.8\n";

fn rms(a: &[Vec3], b: &[Vec3]) -> f64 {
    let sum: f64 = a
        .iter()
        .zip(b)
        .map(|(p, q)| (*p - *q).length_squared() as f64)
        .sum();
    (sum / a.len() as f64).sqrt()
}

#[test]
fn stratified_16_spp_is_closer_to_the_converged_picture_than_16_independent_samples() {
    let scene = p3f(SOFT_SCENE);
    let scene = prepare(scene, &Assets::default());
    let with = |sampling| {
        let opts = RenderOptions {
            sampling,
            ..RenderOptions::from_view(scene.view())
        };
        render(&scene, scene.view(), &opts).unwrap().0.pixels
    };
    let reference = with(Sampling::Stratified { spp: 1024 });
    let stratified = rms(&with(Sampling::Stratified { spp: 16 }), &reference);
    let independent = rms(&with(Sampling::Independent { spp: 16 }), &reference);
    // Both estimate the same picture: the independent error is about 1/4 of a
    // pixel's spread, the stratified one well under it.
    assert!(independent > 0.0 && stratified > 0.0);
    assert!(
        stratified < 0.8 * independent,
        "stratified {stratified} vs independent {independent}"
    );
}

#[test]
fn distribution_effects_are_deterministic_across_threads_and_tiles() {
    use nffrt::image::Region;
    use nffrt::render::{render_region, Silent};
    let scene = p3f(SOFT_SCENE);
    let scene = prepare(scene, &Assets::default());
    let opts = RenderOptions {
        sampling: Sampling::Stratified { spp: 9 },
        ..RenderOptions::from_view(scene.view())
    };
    let on = |threads: usize, region: Region| {
        let pool = rayon::ThreadPoolBuilder::new()
            .num_threads(threads)
            .build()
            .unwrap();
        pool.install(|| {
            render_region(
                &scene,
                scene.view(),
                &opts,
                &region,
                &RenderLimits::default(),
                &Silent,
            )
            .unwrap()
            .0
        })
    };
    let full = on(1, Region::full(opts.width, opts.height));
    for threads in [2, 3, 8] {
        assert!(
            on(threads, Region::full(opts.width, opts.height)) == full,
            "{threads} threads"
        );
    }
    // A crop has exactly the full picture's pixels: lens, light and pixel samples
    // hash absolute pixel coordinates.
    let crop = Region {
        x0: 5,
        y0: 3,
        x1: 17,
        y1: 11,
    };
    let tile = on(2, crop);
    for y in crop.y0..crop.y1 {
        for x in crop.x0..crop.x1 {
            assert_eq!(tile.get(x - crop.x0, y - crop.y0), full.get(x, y), "({x}, {y})");
        }
    }
}
