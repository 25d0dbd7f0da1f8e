//! `nffrt render --motion-blur K` on an AFF animation: a frame is the mean of K
//! sub-frames over its interval. A keyed sphere moving across the picture leaves a
//! streak whose every pixel is the share of sub-frames in which the sphere covers
//! it (computed here from the Kochanek-Bartels curve and the camera's rays); one
//! sub-frame is the plain picture at the middle of the interval; `--time`,
//! `--frame` and `--frames` agree; the same bytes on one and two threads; bad
//! requests refused with the usage exit code.

mod common;

use std::path::{Path, PathBuf};

use common::{nffrt, nffrt_ok, scratch_dir};
use nffrt::image::{decode_pfm, Image};

/// [`common::keyed_ball`] at 101 x 101 pixels: 0.05 a pixel, column 50 at x = 0.
fn ball_text() -> String {
    common::keyed_ball(101)
}

fn ball(test: &str) -> (PathBuf, PathBuf) {
    let dir = scratch_dir("aff_motion_blur", test);
    let scene = dir.join("ball.aff");
    std::fs::write(&scene, ball_text()).unwrap();
    (dir, scene)
}

fn s(p: &Path) -> &str {
    p.to_str().unwrap()
}

fn run(args: &[&str]) -> std::process::Output {
    nffrt(args, b"")
}

fn pfm(path: &Path) -> Image {
    decode_pfm(&std::fs::read(path).unwrap()).unwrap()
}

/// The ball's centre at time `t` in [0, 1].
fn centre_x(t: f64) -> f64 {
    t + 3.0 * t * t - 2.0 * t * t * t
}

/// How far the ray through pixel column `c` of the middle row passes from a centre
/// at (x, 0, 0): the ray runs from (0, 0, 10) through (xc, 0, 0), xc = 0.05 (c - 50),
/// so the distance is |(C - E) x d| / |d| = 10 |x - xc| / sqrt(xc² + 100).
fn ray_distance(c: u32, x: f64) -> f64 {
    let xc = 0.05 * (c as f64 - 50.0);
    10.0 * (x - xc).abs() / (xc * xc + 100.0).sqrt()
}

#[test]
fn a_moving_sphere_leaves_a_streak_of_partly_covered_pixels() {
    let (dir, scene) = ball("streak");
    let k = 8u32;
    let blurred = dir.join("blurred.pfm");
    let sharp = dir.join("sharp.pfm");
    let base = ["render", s(&scene), "--frame", "1", "-q"];
    nffrt_ok(&[&base[..], &["--motion-blur", "8", "-o", s(&blurred)]].concat());
    nffrt_ok(&[&base[..], &["-o", s(&sharp)]].concat());
    let (blurred, sharp) = (pfm(&blurred), pfm(&sharp));
    // Frame 1 spans t in [0.25, 0.5): sub-frame i at 0.25 + (i + 0.5) / 8 * 0.25.
    let centres: Vec<f64> = (0..k)
        .map(|i| centre_x(0.25 + (i as f64 + 0.5) / k as f64 * 0.25))
        .collect();
    let (mut partial, mut checked) = (0, 0);
    for c in 0..101 {
        let distances: Vec<f64> = centres.iter().map(|&x| ray_distance(c, x)).collect();
        // Rays that graze a sub-frame's sphere are left out: rounding decides them.
        if distances.iter().any(|d| (d - 0.2).abs() < 1e-4) {
            continue;
        }
        let covered = distances.iter().filter(|&&d| d < 0.2).count();
        let want = covered as f32 / k as f32;
        let got = blurred.get(c, 50);
        assert!(
            (got.x - want).abs() < 1e-6 && got.x == got.y && got.y == got.z,
            "column {c}: {got:?}, expected {want} ({covered} of {k} sub-frames)"
        );
        partial += usize::from(covered > 0 && covered < k as usize);
        checked += 1;
    }
    assert!(checked > 90, "{checked} columns checked");
    // The centre moves from 0.4 to 1.0 over the frame, 12 pixels: the streak's
    // ends (about 0.2 / 0.05 = 4 pixels each side of the sphere's middle) fade.
    assert!(partial >= 8, "{partial} partly covered pixels on the middle row");
    // The unblurred frame has no partly covered pixel on that row.
    assert!((0..101).all(|c| [0.0, 1.0].contains(&sharp.get(c, 50).x)));
}

#[test]
fn one_subframe_is_the_plain_picture_at_the_middle_of_the_interval() {
    let (dir, scene) = ball("one");
    let (one, middle) = (dir.join("one.pfm"), dir.join("middle.pfm"));
    // Frame 1 starts at 0.25; the middle of its interval is 0.25 + 0.5 * 0.25.
    nffrt_ok(&[
        "render",
        s(&scene),
        "--frame",
        "1",
        "--motion-blur",
        "1",
        "-q",
        "-o",
        s(&one),
    ]);
    nffrt_ok(&["render", s(&scene), "--time", "0.375", "-q", "-o", s(&middle)]);
    assert!(std::fs::read(&one).unwrap() == std::fs::read(&middle).unwrap());
}

#[test]
fn time_frame_and_frames_blur_alike_on_any_thread_count() {
    let (dir, scene) = ball("agree");
    let blur = ["--motion-blur", "5", "-q"];
    let at = dir.join("at.png");
    nffrt_ok(&[&["render", s(&scene), "--time", "0.5", "-o", s(&at)][..], &blur].concat());
    let frame = dir.join("frame.png");
    nffrt_ok(&[&["render", s(&scene), "--frame", "2", "-o", s(&frame)][..], &blur].concat());
    for threads in ["1", "2"] {
        let pattern = dir.join(format!("t{threads}_%d.png"));
        let args = [
            "render",
            s(&scene),
            "--frames",
            "1..2",
            "--threads",
            threads,
            "-o",
            s(&pattern),
        ];
        nffrt_ok(&[&args[..], &blur].concat());
    }
    let bytes = |name: &str| std::fs::read(dir.join(name)).unwrap();
    assert!(bytes("at.png") == bytes("frame.png"), "--time 0.5 and --frame 2");
    assert!(
        bytes("t1_2.png") == bytes("frame.png"),
        "--frames' frame 2 and --frame 2"
    );
    assert!(bytes("t1_1.png") == bytes("t2_1.png") && bytes("t1_2.png") == bytes("t2_2.png"));
}

#[test]
fn bad_blur_requests_are_refused() {
    let (dir, scene) = ball("refused");
    let still = dir.join("still.aff");
    std::fs::write(&still, ball_text().replace("a 0 1 4\n", "")).unwrap();
    let nff = dir.join("still.nff");
    std::fs::write(
        &nff,
        "v from 0 0 5 at 0 0 0 up 0 1 0 angle 40 hither 1 resolution 4 4\ns 0 0 0 1\n",
    )
    .unwrap();
    let out = dir.join("x.png");
    for (args, says) in [
        (vec![s(&still), "--motion-blur", "4"], "no animation"),
        (vec![s(&nff), "--motion-blur", "4"], "are for AFF scenes"),
        (vec![s(&scene), "--motion-blur", "0"], "1 to 1024"),
        (
            vec![s(&scene), "--motion-blur", "2", "--spp", "4", "--denoise"],
            "cannot be used with",
        ),
        (
            vec![s(&scene), "--motion-blur", "2", "--aov", "depth"],
            "cannot be used with",
        ),
    ] {
        let all = [&["render"][..], &args, &["-o", s(&out)]].concat();
        let run = run(&all);
        let stderr = String::from_utf8_lossy(&run.stderr);
        assert_eq!(run.status.code(), Some(2), "{args:?}: {stderr}");
        assert!(stderr.contains(says), "{args:?}: {stderr}");
    }
    assert!(!out.exists(), "nothing written");
}
