//! `nffrt render` on an animation's frames (`--frame`, `--time`, `--frames` with an
//! output pattern): a keyed sphere's centre in the pictures follows its
//! Kochanek-Bartels keys (positions computed by hand), frames are deterministic
//! whatever the thread count, BART's scenes move and are not flat, and bad requests
//! are refused with the usage exit code.

mod common;

use std::path::{Path, PathBuf};

use common::{nffrt, nffrt_ok, scratch_dir, skip::shared};
use nffrt::image::decode_ppm;

/// A white sphere of radius 0.2 (shown by the ambient light alone) on a black
/// background, its block `x ball` keyed along x: keys x = 0, 0, 2, 2 at times -1, 0,
/// 1, 2 (the curve runs from the second key to the third), four frames over t = 0..1.
/// The camera at z = 10 looks at the origin; its 101 x 101 pixel centres span
/// x, y = ±2.5 on the plane z = 0 (tan(angle / 2) = 0.25): 0.05 a pixel, column 50
/// at x = 0.
const BALL: &str = "v from 0 0 10 at 0 0 0 up 0 1 0 angle 28.072486935852957 hither 1 resolution 101 101\n\
    b 0 0 0\nam 1 1 1\nfm 1 1 1  0 0 0  0 0 0  1 0 1\na 0 1 4\n\
    x ball { s 0 0 0 0.2 }\n\
    k ball { transl 4  -1 0 0 0 0 0 0   0 0 0 0 0 0 0   1 2 0 0 0 0 0   2 2 0 0 0 0 0 }\n";

fn ball_dir(test: &str) -> PathBuf {
    let dir = scratch_dir("aff_frames", test);
    std::fs::write(dir.join("ball.aff"), BALL).unwrap();
    dir
}

/// The mean column and row of the pixels brighter than half grey in a PPM.
fn centroid(path: &Path) -> (f64, f64) {
    let (w, _, rgb) = decode_ppm(&std::fs::read(path).unwrap()).unwrap();
    let (mut sx, mut sy, mut n) = (0.0, 0.0, 0.0);
    for (i, px) in rgb.chunks(3).enumerate() {
        if px[0] > 128 {
            sx += (i as u32 % w) as f64;
            sy += (i as u32 / w) as f64;
            n += 1.0;
        }
    }
    assert!(n > 20.0, "{}: the ball covers {n} pixels", path.display());
    (sx / n, sy / n)
}

/// The centre's x at frame n (time n/4, u = n/4 on the segment from key 1 to key 2),
/// from the Kochanek-Bartels formulas with tension, continuity and bias 0:
/// D = 2; a1 = 2 (t2 - t1) / (t2 - t0) = 1, T1 = (D + (P1 - P0)) / 2 = 1;
/// a2 = 2 (t2 - t1) / (t3 - t1) = 1, T2 = ((P3 - P2) + D) / 2 = 1;
/// P(u) = T1 u + (3D - 2T1 - T2) u² + (T1 + T2 - 2D) u³ = u + 3u² - 2u³:
/// 0, 0.40625, 1, 1.59375 (a straight line would give 0.5 and 1.5 at u = 1/4, 3/4).
const CENTRE_X: [f64; 4] = [0.0, 0.40625, 1.0, 1.59375];

#[test]
fn a_keyed_spheres_centre_follows_its_keys() {
    let dir = ball_dir("follows");
    let scene = dir.join("ball.aff");
    let pattern = dir.join("f_%02d.ppm");
    nffrt_ok(&[
        "render",
        scene.to_str().unwrap(),
        "--frames",
        "0..3",
        "-o",
        pattern.to_str().unwrap(),
        "-q",
    ]);
    for (n, x) in CENTRE_X.iter().enumerate() {
        let (col, row) = centroid(&dir.join(format!("f_{n:02}.ppm")));
        let want = 50.0 + x / 0.05;
        assert!(
            (col - want).abs() < 0.5,
            "frame {n}: column {col}, expected {want}"
        );
        assert!((row - 50.0).abs() < 0.5, "frame {n}: row {row}");
    }
    // --frame and --time show the same pictures as --frames.
    let one = dir.join("one.ppm");
    nffrt_ok(&[
        "render",
        scene.to_str().unwrap(),
        "--frame",
        "1",
        "-o",
        one.to_str().unwrap(),
        "-q",
    ]);
    let at = dir.join("at.ppm");
    nffrt_ok(&[
        "render",
        scene.to_str().unwrap(),
        "--time",
        "0.25",
        "-o",
        at.to_str().unwrap(),
        "-q",
    ]);
    let frame1 = std::fs::read(dir.join("f_01.ppm")).unwrap();
    assert_eq!(std::fs::read(&one).unwrap(), frame1);
    assert_eq!(std::fs::read(&at).unwrap(), frame1);
}

#[test]
fn frames_are_the_same_bytes_on_one_and_two_threads() {
    let dir = ball_dir("threads");
    let scene = dir.join("ball.aff");
    for threads in ["1", "2"] {
        let pattern = dir.join(format!("t{threads}_%d.png"));
        let args = [
            "render",
            scene.to_str().unwrap(),
            "--frames",
            "1..2",
            "--threads",
            threads,
        ];
        nffrt_ok(&[&args[..], &["-o", pattern.to_str().unwrap(), "-q"]].concat());
    }
    for n in 1..=2 {
        let a = std::fs::read(dir.join(format!("t1_{n}.png"))).unwrap();
        assert_eq!(
            a,
            std::fs::read(dir.join(format!("t2_{n}.png"))).unwrap(),
            "frame {n}"
        );
    }
}

/// Runs `nffrt` expecting the usage exit code and a message containing `says`.
fn refused(args: &[&str], says: &str) {
    let out = nffrt(args, b"");
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(2), "{args:?}: {stderr}");
    assert!(stderr.contains(says), "{args:?}: {stderr}");
}

#[test]
fn bad_frame_requests_are_refused() {
    let dir = ball_dir("refused");
    let scene = dir.join("ball.aff");
    let scene = scene.to_str().unwrap();
    let nff = dir.join("still.nff");
    std::fs::write(
        &nff,
        "v from 0 0 5 at 0 0 0 up 0 1 0 angle 40 hither 1 resolution 4 4\ns 0 0 0 1\n",
    )
    .unwrap();
    refused(
        &["render", nff.to_str().unwrap(), "--frame", "1"],
        "are for AFF scenes",
    );
    refused(&["render", scene, "--frame", "4"], "has 4 frames (0 to 3)");
    refused(
        &[
            "render",
            scene,
            "--frames",
            "0..2",
            "-o",
            dir.join("x.png").to_str().unwrap(),
        ],
        "frame number field",
    );
    refused(&["render", scene, "--frames", "2..1"], "A <= B");
    refused(
        &["render", scene, "--frame", "1", "--time", "0.5"],
        "cannot be used with",
    );
    refused(&["render", scene, "--time", "inf"], "finite");
    refused(
        &[
            "render",
            scene,
            "--frames",
            "0..1",
            "-o",
            dir.join("a%s.png").to_str().unwrap(),
        ],
        "%d",
    );
    // A picture that would replace a texture the scene reads (frame 1's name).
    let textured = format!("{BALL}tt tex_1.ppm 0 0 -5 0 0  1 0 -5 1 0  0 1 -5 0 1\n");
    std::fs::write(dir.join("tex.aff"), textured).unwrap();
    let texture = b"P6\n1 1\n255\n\x10\x20\x30";
    std::fs::write(dir.join("tex_1.ppm"), texture).unwrap();
    let pattern = dir.join("tex_%d.ppm");
    let tex = dir.join("tex.aff");
    refused(
        &[
            "render",
            tex.to_str().unwrap(),
            "--frames",
            "0..2",
            "-o",
            pattern.to_str().unwrap(),
        ],
        "would overwrite a texture",
    );
    assert_eq!(std::fs::read(dir.join("tex_1.ppm")).unwrap(), texture);
    assert!(
        !dir.join("tex_0.ppm").exists(),
        "nothing is written before the refusal"
    );
}

/// The standard deviation of a PNG's 8-bit values.
fn spread(png: &[u8]) -> f64 {
    let image = nffrt::image::decode_png(png).unwrap();
    let values: Vec<f64> = image.rgb.iter().map(|&v| v as f64).collect();
    let mean = values.iter().sum::<f64>() / values.len() as f64;
    (values.iter().map(|v| (v - mean).powi(2)).sum::<f64>() / values.len() as f64).sqrt()
}

#[test]
fn barts_scenes_render_frames_that_move_and_are_not_flat() {
    for (scene, later) in [
        ("kitchen/aff/kitchen.aff", "400"),
        ("robot/aff/Robot.aff", "400"),
        ("museum/aff/museum5.aff", "150"),
    ] {
        let Some(path) = shared(&format!("scenes/bart/{scene}")) else {
            return;
        };
        let dir = scratch_dir("aff_frames", &scene.replace('/', "_"));
        let mut pictures = Vec::new();
        for frame in ["0", later] {
            let out = dir.join(format!("f{frame}.png"));
            let args = [
                "render",
                path.to_str().unwrap(),
                "--frame",
                frame,
                "--width",
                "96",
                "-q",
            ];
            nffrt_ok(&[&args[..], &["-o", out.to_str().unwrap()]].concat());
            let png = std::fs::read(&out).unwrap();
            let s = spread(&png);
            assert!(
                s > 10.0,
                "{scene} frame {frame}: standard deviation {s:.1} of 255"
            );
            pictures.push(png);
        }
        assert_ne!(
            pictures[0], pictures[1],
            "{scene}: frames 0 and {later} are the same picture"
        );
    }
}

/// `--frames` builds the objects under no keyframed transform once and each frame
/// only what moves, grafted under one root (`prepare::prepare_frame`): its pictures
/// are the bytes of `--rebuild-whole`, which flattens and builds every frame whole,
/// on every structure (the grid and the scan query the grafted primitives), for a
/// keyed ball beside fixed objects and for BART's scenes (moving transforms,
/// textures, animated triangles).
#[test]
fn frames_built_on_the_fixed_part_are_the_whole_rebuilds_bytes() {
    let dir = ball_dir("fixed_part");
    let with_fixed = format!(
        "{BALL}xs 1 1 1  0 0 1 30  0 1 0 {{ s -1 0 0 0.3 p 3 1 -1 0 2 -1 0 1.5 -0.5 0 }}\n\
         x ball {{ xs 1 1 1 0 1 0 0  0 -1 0 {{ p 3 0 0 0 0.5 0 0 0 0.5 0 }} }}\n"
    );
    std::fs::write(dir.join("mixed.aff"), with_fixed).unwrap();
    let mut scenes = vec![(dir.join("mixed.aff"), "0..3".to_string())];
    for (scene, frames) in [
        ("kitchen/aff/kitchen.aff", "398..400"),
        ("robot/aff/Robot.aff", "398..400"),
        ("museum/aff/museum5.aff", "149..150"),
    ] {
        match shared(&format!("scenes/bart/{scene}")) {
            Some(path) => scenes.push((path, frames.to_string())),
            None => return,
        }
    }
    for (i, (scene, frames)) in scenes.iter().enumerate() {
        let (first, last) = frames.split_once("..").unwrap();
        let (first, last): (u32, u32) = (first.parse().unwrap(), last.parse().unwrap());
        for accel in ["bvh", "grid"] {
            let render = |how: &str, extra: &[&str]| {
                let pattern = dir.join(format!("s{i}_{accel}_{how}_%d.ppm"));
                let args = [
                    "render",
                    scene.to_str().unwrap(),
                    "--frames",
                    frames,
                    "--width",
                    "64",
                    "--accel",
                    accel,
                    "-q",
                    "-o",
                    pattern.to_str().unwrap(),
                ];
                nffrt_ok(&[&args[..], extra].concat());
            };
            render("fixed", &[]);
            render("whole", &["--rebuild-whole"]);
            for n in first..=last {
                let read =
                    |how: &str| std::fs::read(dir.join(format!("s{i}_{accel}_{how}_{n}.ppm"))).unwrap();
                assert!(
                    read("fixed") == read("whole"),
                    "{} frame {n} ({accel}): the grafted frame differs from the whole rebuild",
                    scene.display()
                );
            }
        }
    }
}
