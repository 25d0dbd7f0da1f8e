//! No effect a scene or a flag asks for vanishes silently: a lens without a sample
//! count renders with enough samples to show its blur, and says so; an explicit
//! single sample takes one jittered lens sample (noisy, not sharp).

mod common;

use std::path::Path;

use common::{nffrt, scratch_dir};
use nffrt::image::decode_png;

/// A white sphere at z = 5, half-way between the camera (z = 10) and its look-at
/// point (the origin, where `focal 1` puts sharp focus), lit from the camera's side,
/// on black: out of focus under a lens.
const SCENE: &str = "camera eye 0 0 10 at 0 0 0 up 0 1 0 angle 20 hither 1 resolution 48 48\n\
                     bclr 0 0 0\nlight punctual 0 0 10 1 1 1\n\
                     mat 1 1 1 1 1 1 1 0 10 0 1\ns 0 0 5 0.4\n";

/// Renders `scene` with `args`, returning the picture's pixels that are not black and
/// the standard error.
fn lit_pixels(scene: &Path, out: &Path, args: &[&str]) -> (usize, Vec<u8>, String) {
    let mut all = vec!["render", scene.to_str().unwrap(), "-o", out.to_str().unwrap()];
    all.extend(args);
    let run = nffrt(&all, b"");
    let stderr = String::from_utf8_lossy(&run.stderr).into_owned();
    assert_eq!(run.status.code(), Some(0), "{args:?}: {stderr}");
    let png = decode_png(std::fs::read(out).unwrap().as_slice()).unwrap();
    let lit = png.rgb.chunks(3).filter(|p| p.iter().any(|&c| c > 0)).count();
    (lit, png.rgb, stderr)
}

#[test]
fn a_lens_without_a_sample_count_blurs_and_says_so() {
    let dir = scratch_dir("effects", "lens");
    let scene = dir.join("s.p3f");
    std::fs::write(&scene, SCENE).unwrap();
    let out = dir.join("x.png");
    let (sharp, sharp_rgb, quiet) = lit_pixels(&scene, &out, &[]);
    assert!(!quiet.contains("note:"), "{quiet}");
    // docs/p3f.md's own example: a lens on a pinhole scene.
    let (blurred, blurred_rgb, said) = lit_pixels(&scene, &out, &["--aperture", "6", "--focal", "1"]);
    assert!(
        said.contains("note:") && said.contains("16 ") && said.contains("lens"),
        "{said}"
    );
    assert!(
        said.contains("stratified"),
        "the summary names the sampling: {said}"
    );
    // The blur spreads the disc: more pixels see some of it.
    assert!(
        blurred as f64 > 1.2 * sharp as f64,
        "{blurred} lit pixels blurred against {sharp} sharp"
    );
    assert_ne!(blurred_rgb, sharp_rgb);
    // --quiet keeps the note to itself.
    let (_, _, silent) = lit_pixels(&scene, &out, &["--aperture", "6", "-q"]);
    assert!(silent.is_empty(), "{silent}");
}

#[test]
fn an_explicit_single_sample_takes_one_jittered_lens_sample() {
    let dir = scratch_dir("effects", "one");
    let scene = dir.join("s.p3f");
    std::fs::write(
        &scene,
        SCENE.replace("resolution 48 48", "resolution 48 48 aperture 6 focal 1"),
    )
    .unwrap();
    let out = dir.join("x.png");
    let (sharp, _, _) = lit_pixels(&scene, &out, &["--aperture", "0"]);
    let (one, _, said) = lit_pixels(&scene, &out, &["--spp", "1"]);
    assert!(!said.contains("note:"), "{said}");
    // Each pixel's one lens sample lands anywhere on the lens: the disc's edge
    // frays outwards, noisy rather than sharp.
    assert!(
        one > sharp,
        "{one} lit pixels at --spp 1 against {sharp} with no lens"
    );
}

#[test]
fn the_course_dof_scene_without_spp_renders_its_blur() {
    let Some(path) = common::skip::shared("scenes/p3f/2019/dof.p3f") else {
        return;
    };
    let dir = scratch_dir("effects", "dof");
    let out = dir.join("dof.png");
    let run = nffrt(
        &[
            "render",
            path.to_str().unwrap(),
            "--width",
            "128",
            "-o",
            out.to_str().unwrap(),
        ],
        b"",
    );
    let stderr = String::from_utf8_lossy(&run.stderr);
    assert_eq!(run.status.code(), Some(0), "{stderr}");
    assert!(
        stderr.contains("note:") && stderr.contains("stratified-16"),
        "{stderr}"
    );
}

use nffrt::load::Assets;
use nffrt::nff::{parse_format, Format};
use nffrt::options::{RenderOptions, Sampling};
use nffrt::prepare::{prepare, RenderScene};
use nffrt::render::render;
use nffrt::scene::IntegratorKind;

/// A P3F scene from text, prepared.
fn p3f(text: &str) -> RenderScene {
    let scene = parse_format(text.as_bytes(), Format::P3f, &Default::default()).unwrap();
    prepare(scene, &Assets::default())
}

/// Glass absorbs by Beer-Lambert over the distance travelled inside: a ray through
/// the centre of a glass sphere of radius 0.8 with index 1 (no bending, no Fresnel
/// reflection at normal incidence) travels 1.6 inside, and brings back the white
/// background times exp(-(1 - C) 1.6) per channel.
#[test]
fn glass_absorbs_by_beer_lambert_over_the_path_inside() {
    let scene = p3f(
        "camera eye 0 0 10 at 0 0 0 up 0 1 0 angle 10 hither 1 resolution 9 9\n\
         bclr 1 1 1\nmat 1 0.5 0.25 0 1 1 1 0 10 1 1\ns 0 0 0 0.8\n",
    );
    let (image, _) = render(&scene, scene.view(), &RenderOptions::from_view(scene.view())).unwrap();
    let got = image.get(4, 4);
    let want = [1.0f32, 0.5, 0.25].map(|c| (-(1.0 - c) * 1.6).exp());
    for (g, w) in got.to_array().into_iter().zip(want) {
        assert!(
            (g - w).abs() < 1e-4,
            "centre pixel {got:?}, Beer-Lambert {want:?}"
        );
    }
    // A slab: a glass box 0.5 thick seen face on, the same law over 0.5.
    let slab = p3f(
        "camera eye 0 0 10 at 0 0 0 up 0 1 0 angle 10 hither 1 resolution 9 9\n\
         bclr 1 1 1\nmat 0.2 0.9 1 0 1 1 1 0 10 1 1\nbox -2 -2 -0.25 2 2 0.25\n",
    );
    let (image, _) = render(&slab, slab.view(), &RenderOptions::from_view(slab.view())).unwrap();
    let got = image.get(4, 4);
    let want = [0.2f32, 0.9, 1.0].map(|c| (-(1.0 - c) * 0.5).exp());
    for (g, w) in got.to_array().into_iter().zip(want) {
        assert!((g - w).abs() < 1e-4, "slab {got:?}, Beer-Lambert {want:?}");
    }
}

/// The fraction of the shutter, `[0, 1]`, during which the ray from `eye` along the
/// unit `dir` meets the sphere of radius `r` whose centre moves from `c0` to `c1`:
/// `|(c(t) - eye) x dir|^2 < r^2` is a quadratic inequality in `t`, solved exactly
/// in f64 (spheres in front of the eye only).
fn covered_time(eye: [f64; 3], dir: [f64; 3], c0: [f64; 3], c1: [f64; 3], r: f64) -> f64 {
    let sub = |a: [f64; 3], b: [f64; 3]| [a[0] - b[0], a[1] - b[1], a[2] - b[2]];
    let dot = |a: [f64; 3], b: [f64; 3]| a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
    let (w0, v) = (sub(c0, eye), sub(c1, c0));
    // |w|^2 - (w.d)^2 with w = w0 + t v: a t^2 + b t + c.
    let a = dot(v, v) - dot(v, dir).powi(2);
    let b = 2.0 * (dot(w0, v) - dot(w0, dir) * dot(v, dir));
    let c = dot(w0, w0) - dot(w0, dir).powi(2) - r * r;
    let disc = b * b - 4.0 * a * c;
    if disc <= 0.0 {
        return 0.0;
    }
    let (t0, t1) = ((-b - disc.sqrt()) / (2.0 * a), (-b + disc.sqrt()) / (2.0 * a));
    (t1.min(1.0) - t0.max(0.0)).max(0.0)
}

/// A black sphere of radius 0.6 crossing a white background from x = -3 to 3
/// while the shutter is open: each pixel of the middle row is white for the part of
/// the shutter (and of its own area) that the sphere does not cover. The analytic
/// coverage, worked out per pixel over a 16 x 16 grid of its points with the exact
/// covered time of each ray (the P3F camera of P3F-SPEC written out here in f64),
/// is a trapezoid; 1024 stratified samples per pixel match it within 0.02.
#[test]
fn a_moving_sphere_blurs_into_the_analytic_coverage_profile() {
    let (w, h, angle) = (64u32, 9u32, 10.0f64);
    let scene = p3f(&format!(
        "camera eye 0 0 10 at 0 0 0 up 0 1 0 angle {angle} hither 1 resolution {w} {h}\n\
         bclr 1 1 1\nmat 0 0 0 0 0 0 0 0 1 0 1\nsm -3 0 0 3 0 0 0.6 0 1\n"
    ));
    let opts = RenderOptions {
        sampling: Sampling::Stratified { spp: 1024 },
        ..RenderOptions::from_view(scene.view())
    };
    let (image, _) = render(&scene, scene.view(), &opts).unwrap();
    let pitch = 2.0 * (angle.to_radians() / 2.0).tan() / h as f64;
    let y = h / 2;
    let mut worst = 0.0f64;
    let mut profile = Vec::new();
    for x in 0..w {
        let n = 16;
        let mut covered = 0.0;
        for i in 0..n {
            for j in 0..n {
                let (px, py) = (
                    x as f64 + (i as f64 + 0.5) / n as f64,
                    y as f64 + (j as f64 + 0.5) / n as f64,
                );
                let d = [(px - w as f64 / 2.0) * pitch, (h as f64 / 2.0 - py) * pitch, -1.0];
                let len = (d[0] * d[0] + d[1] * d[1] + 1.0).sqrt();
                let dir = [d[0] / len, d[1] / len, d[2] / len];
                covered += covered_time([0.0, 0.0, 10.0], dir, [-3.0, 0.0, 0.0], [3.0, 0.0, 0.0], 0.6);
            }
        }
        let want = 1.0 - covered / (n * n) as f64;
        let got = image.get(x, y).x as f64;
        worst = worst.max((got - want).abs());
        profile.push((want * 100.0).round() / 100.0);
    }
    // The profile is a trapezoid: white outside, a plateau of about 1 - 1.2 / 6 = 0.8
    // where the sphere passes for its whole diameter, ramps between.
    let plateau = profile.iter().filter(|&&p| (p - 0.8).abs() < 0.02).count();
    assert!(plateau >= 10, "{profile:?}");
    assert!(
        worst < 0.02,
        "largest difference from the analytic coverage {worst}"
    );
}

/// Roughness 0 is the perfect mirror and smooth glass, byte for byte; roughness
/// above 0 spreads the mirror's reflection.
#[test]
fn roughness_zero_is_the_smooth_surface_and_roughness_spreads_reflections() {
    let text = |roughness: &str| {
        format!(
            "camera eye 0 -6 2 at 0 0 0.5 up 0 0 1 angle 40 hither 1 resolution 24 18\n\
             bclr 0.2 0.3 0.5\nlight punctual 3 -3 5 1 1 1\n\
             mat 0.9 0.3 0.3 0.8 1 1 1 0 10 0 1\np 4 -10 -10 0 10 -10 0 10 10 0 -10 10 0\n\
             mat 0.1 0.1 0.1 0.1 0.9 0.9 0.9 0.9 50 0 1{roughness}\ns -0.8 0 1 0.8\n\
             mat 1 1 1 0 1 1 1 0.1 50 1 1.5{roughness}\ns 1 0.8 1 0.7\nspp 4\n"
        )
    };
    let render_with = |t: &str, roughness: bool, integrator: IntegratorKind| {
        let scene = p3f(t);
        render(
            &scene,
            scene.view(),
            &RenderOptions {
                sampling: Sampling::Stratified { spp: 4 },
                roughness,
                integrator,
                ..RenderOptions::from_view(scene.view())
            },
        )
        .unwrap()
        .0
    };
    let render_text = |t: &str| render_with(t, true, IntegratorKind::Whitted);
    let smooth = render_text(&text(""));
    assert_eq!(render_text(&text(" roughness 0")), smooth);
    let rough = render_text(&text(" roughness 0.5"));
    assert_ne!(rough, smooth);
    // The viewer's roughness switch turned off renders the rough file as the smooth
    // one, in both integrators.
    for integrator in [IntegratorKind::Whitted, IntegratorKind::Path] {
        assert_eq!(
            render_with(&text(" roughness 0.5"), false, integrator),
            render_with(&text(""), true, integrator),
            "{integrator:?}"
        );
    }
}
