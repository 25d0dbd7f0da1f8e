//! Instancing (docs/aff.md, "How frames are built"): a mesh placed more than once,
//! or moved by keyframes, is built once in its own space and placed per frame. Its
//! pictures are those of the meshes copied into world space (`--flatten-meshes`,
//! the path checked against hand computations elsewhere) within f32 rounding: on a
//! hand-written scene with a mesh placed three times (once mirrored, once keyed)
//! and on BART's kitchen and robots. `nffrt info` says what is instanced.

mod common;

use std::path::Path;

use common::{nffrt, nffrt_ok, scratch_dir, skip::shared};
use nffrt::image::decode_ppm;

/// A bumpy sheet of 8 x 4 quads (64 triangles: the least the policy instances)
/// with vertex normals, z = 0.2 sin(2x) cos(2y) over |x| <= 1, |y| <= 0.5.
fn sheet() -> String {
    let (nx, ny) = (9, 5);
    let mut vertices = Vec::new();
    let mut normals = Vec::new();
    for j in 0..ny {
        for i in 0..nx {
            let (x, y) = (-1.0 + 2.0 * i as f64 / 8.0, -0.5 + j as f64 / 4.0);
            let z = 0.2 * (2.0 * x).sin() * (2.0 * y).cos();
            let (dx, dy) = (
                0.4 * (2.0 * x).cos() * (2.0 * y).cos(),
                -0.4 * (2.0 * x).sin() * (2.0 * y).sin(),
            );
            vertices.push(format!("{x} {y} {z}"));
            normals.push(format!("{} {} 1", -dx, -dy));
        }
    }
    let mut triangles = Vec::new();
    for j in 0..ny - 1 {
        for i in 0..nx - 1 {
            let v = j * nx + i;
            for t in [[v, v + 1, v + nx + 1], [v, v + nx + 1, v + nx]] {
                let [a, b, c] = t;
                triangles.push(format!("{a} {b} {c}  {a} {b} {c}"));
            }
        }
    }
    format!(
        "m vertices {} {}\nnormals {} {}\ntriangles {} {}\n",
        vertices.len(),
        vertices.join("  "),
        normals.len(),
        normals.join("  "),
        triangles.len(),
        triangles.join("   ")
    )
}

/// The sheet placed plainly, mirrored (x scaled by -1), and under a keyed turn
/// about y; a light, a grey floor polygon, three frames.
const MAIN: &str = "v from 0 1.5 6 at 0 0 0 up 0 1 0 angle 45 hither 1 resolution 120 90\n\
    b 0.1 0.1 0.2\nl 3 5 5\nl -4 3 2\na 0 1 3\n\
    f 0.9 0.6 0.3 0.7 0.3 20 0 1\n\
    xs 0.8 0.8 0.8  1 0 0 -30  -1.6 0.5 0 { i 0 sheet.aff }\n\
    xs -0.8 0.8 0.8  1 0 0 -30  1.6 0.5 0 { i 0 sheet.aff }\n\
    x turn { i 0 sheet.aff }\n\
    k turn { rot 4  -1 0 1 0 0 0 0 0  0 0 1 0 0 0 0 0  1 0 1 0 70 0 0 0  2 0 1 0 70 0 0 0 }\n\
    f 0.5 0.5 0.5 1 0 1 0 1\np 4 -3 -1 -3  3 -1 -3  3 -1 3  -3 -1 3\n";

/// Pixels of `a` and `b` (8-bit RGB of one size): the share that differ at all,
/// and the share that differ by more than 16 levels in a channel.
fn differences(a: &[u8], b: &[u8]) -> (f64, f64) {
    assert_eq!(a.len(), b.len());
    let pixels = a.len() / 3;
    let (mut any, mut large) = (0, 0);
    for (p, q) in a.chunks(3).zip(b.chunks(3)) {
        let d = p.iter().zip(q).map(|(x, y)| x.abs_diff(*y)).max().unwrap();
        any += usize::from(d > 0);
        large += usize::from(d > 16);
    }
    (any as f64 / pixels as f64, large as f64 / pixels as f64)
}

/// Renders `scene` at `frames` (with `extra`) to `dir`, returning each frame's
/// raster.
fn frames(scene: &Path, frames: &str, dir: &Path, tag: &str, extra: &[&str]) -> Vec<Vec<u8>> {
    let pattern = dir.join(format!("{tag}_%d.ppm"));
    let args = [
        "render",
        scene.to_str().unwrap(),
        "--frames",
        frames,
        "-q",
        "-o",
        pattern.to_str().unwrap(),
    ];
    nffrt_ok(&[&args[..], extra].concat());
    let (first, last) = frames.split_once("..").unwrap();
    (first.parse::<u32>().unwrap()..=last.parse().unwrap())
        .map(|n| {
            let bytes = std::fs::read(dir.join(format!("{tag}_{n}.ppm"))).unwrap();
            decode_ppm(&bytes).unwrap().2
        })
        .collect()
}

#[test]
fn a_mesh_placed_three_times_is_one_prototype_and_renders_as_its_copies() {
    let dir = scratch_dir("aff_instances", "sheet");
    std::fs::write(dir.join("sheet.aff"), sheet()).unwrap();
    std::fs::write(dir.join("main.aff"), MAIN).unwrap();
    let scene = dir.join("main.aff");
    let info = nffrt(&["info", scene.to_str().unwrap()], b"");
    let text = String::from_utf8_lossy(&info.stdout);
    assert!(
        text.contains("instances 3 of 1 prototype built once (64 triangles), placing 192 triangles"),
        "{text}"
    );
    let instanced = frames(&scene, "0..2", &dir, "i", &[]);
    let copied = frames(&scene, "0..2", &dir, "c", &["--flatten-meshes"]);
    for (n, (i, c)) in instanced.iter().zip(&copied).enumerate() {
        let (any, large) = differences(i, c);
        assert!(
            any <= 0.02 && large <= 0.002,
            "frame {n}: {any} of the pixels differ, {large} by more than 16 levels"
        );
    }
    // The keyed sheet turns: the frames differ; and the sheets are seen.
    assert!(differences(&instanced[0], &instanced[2]).1 > 0.01);
    let lit = instanced[0]
        .chunks(3)
        .filter(|p| p[0] > 100 && p[2] < 100)
        .count();
    assert!(lit > instanced[0].len() / 3 / 50, "{lit} orange pixels");
}

#[test]
fn barts_instanced_frames_render_as_their_meshes_copied() {
    for (scene, frame) in [("kitchen/aff/kitchen.aff", 400), ("robot/aff/Robot.aff", 0)] {
        let Some(path) = shared(&format!("scenes/bart/{scene}")) else {
            return;
        };
        let dir = scratch_dir("aff_instances", "bart");
        let range = format!("{frame}..{frame}");
        let extra = ["--width", "200"];
        let i = &frames(&path, &range, &dir, "i", &extra)[0];
        let c = &frames(
            &path,
            &range,
            &dir,
            "c",
            &[&extra[..], &["--flatten-meshes"]].concat(),
        )[0];
        let (any, large) = differences(i, c);
        // Curved mirrors (the kitchen's chrome rings) magnify the rounding.
        assert!(
            any <= 0.05 && large <= 0.005,
            "{scene} frame {frame}: {any} of the pixels differ, {large} by more than 16 levels"
        );
        let out = nffrt(&["info", path.to_str().unwrap()], b"");
        assert!(
            String::from_utf8_lossy(&out.stdout).contains("  instances "),
            "{scene}"
        );
    }
}
