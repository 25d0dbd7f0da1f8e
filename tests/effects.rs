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
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("../shared/scenes/p3f/2019/dof.p3f");
    if !path.exists() {
        eprintln!(
            "note: {} is absent; the course scene check is skipped",
            path.display()
        );
        return;
    }
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
