//! `nffrt convert`: an AFF frame written as NFF holds the frame's triangles where the
//! keyframes put them (checked against rotations worked out by hand), the kitchen's
//! frame keeps every triangle, and outputs that are the scene's own files or named
//! like images are refused with nothing written.

mod common;

use common::{nffrt, scratch_dir, skip::shared};

/// A triangle under a transform turning it about z by 90 degrees from time 0 to 1
/// (keys at -1, 0, 1 and 2 with no tension, continuity or bias: the first and last
/// only shape the tangents, and the curve holds its end keys outside 0..1); 3 frames
/// over 0..2.
fn turning_triangle(test: &str) -> std::path::PathBuf {
    let dir = scratch_dir("convert_cli", test);
    let main = "v from 0 0 5 at 0 0 0 up 0 1 0 angle 40 hither 1 resolution 16 12\n\
                l 0 0 5\nf 1 1 1 1 0 0 0 1\na 0 2 3\nx turn { i 0 part.aff }\n\
                k turn { rot 4 -1 0 0 1 0 0 0 0 0 0 0 1 0 0 0 0 1 0 0 1 90 0 0 0 2 0 0 1 90 0 0 0 }\n";
    std::fs::write(dir.join("main.aff"), main).unwrap();
    std::fs::write(dir.join("part.aff"), "p 3 1 0 0 0 2 0 0 0 3\n").unwrap();
    dir
}

/// The vertices of the polygons (`p`) of an NFF text.
fn polygon_vertices(nff: &str) -> Vec<[f32; 3]> {
    let mut out = Vec::new();
    let mut lines = nff.lines();
    while let Some(line) = lines.next() {
        if let Some(n) = line.strip_prefix("p ") {
            for _ in 0..n.trim().parse::<usize>().unwrap() {
                let v: Vec<f32> = lines
                    .next()
                    .unwrap()
                    .split(' ')
                    .map(|x| x.parse().unwrap())
                    .collect();
                out.push([v[0], v[1], v[2]]);
            }
        }
    }
    out
}

fn convert(args: &[&str]) -> String {
    let out = nffrt(&[&["convert"], args].concat(), b"");
    assert_eq!(
        out.status.code(),
        Some(0),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    String::from_utf8(out.stdout).unwrap()
}

#[test]
fn a_frame_holds_its_triangles_where_the_keys_put_them() {
    let dir = turning_triangle("frames");
    let main = dir.join("main.aff");
    let main = main.to_str().unwrap();
    let close = |got: Vec<[f32; 3]>, want: [[f32; 3]; 3]| {
        assert_eq!(got.len(), 3, "{got:?}");
        for (g, w) in got.iter().zip(want) {
            assert!(
                g.iter().zip(w).all(|(a, b)| (a - b).abs() < 1e-5),
                "{got:?} != {want:?}"
            );
        }
    };
    // Frame 0 (time 0) and time -1 (before the curve, which holds its first key):
    // the triangle as in the file.
    let still = [[1.0, 0.0, 0.0], [0.0, 2.0, 0.0], [0.0, 0.0, 3.0]];
    close(polygon_vertices(&convert(&[main])), still);
    close(polygon_vertices(&convert(&[main, "--time", "-1"])), still);
    // Time 1 (the curve's last key) and frame 2 (time 4/3, past it): a quarter turn
    // about z, taking (x, y, z) to (-y, x, z).
    let turned = [[0.0, 1.0, 0.0], [-2.0, 0.0, 0.0], [0.0, 0.0, 3.0]];
    close(polygon_vertices(&convert(&[main, "--time", "1"])), turned);
    close(polygon_vertices(&convert(&[main, "--frame", "2"])), turned);
    // To a file: the same text.
    let file = dir.join("frame2.nff");
    convert(&[main, "--frame", "2", "-o", file.to_str().unwrap()]);
    close(polygon_vertices(&std::fs::read_to_string(&file).unwrap()), turned);
}

#[test]
fn own_files_images_and_frames_past_the_end_are_refused() {
    let dir = turning_triangle("refused");
    let main = dir.join("main.aff");
    let part = dir.join("part.aff");
    let before = std::fs::read(&part).unwrap();
    let png = dir.join("frame.png");
    for (args, says) in [
        (
            vec!["-o", main.to_str().unwrap()],
            "would overwrite the scene file",
        ),
        (
            vec!["-o", part.to_str().unwrap()],
            "would overwrite a file the scene includes",
        ),
        (vec!["-o", png.to_str().unwrap()], "not an image"),
        (vec!["--frame", "3"], "has 3 frames (0 to 2)"),
    ] {
        let out = nffrt(&[&["convert", main.to_str().unwrap()], &args[..]].concat(), b"");
        let stderr = String::from_utf8_lossy(&out.stderr);
        assert_eq!(out.status.code(), Some(2), "{args:?}: {stderr}");
        assert!(stderr.contains(says), "{args:?}: {stderr}");
        assert!(out.stdout.is_empty());
    }
    assert_eq!(std::fs::read(&part).unwrap(), before);
    assert!(!png.exists());
    let nff = dir.join("still.nff");
    std::fs::write(
        &nff,
        "v from 0 0 5 at 0 0 0 up 0 1 0 angle 40 hither 1 resolution 8 8\ns 0 0 0 1\n",
    )
    .unwrap();
    let out = nffrt(&["convert", nff.to_str().unwrap(), "--frame", "0"], b"");
    assert_eq!(out.status.code(), Some(2), "--frame on an NFF scene");
}

#[test]
fn the_kitchen_frame_keeps_every_triangle() {
    let Some(kitchen) = shared("scenes/bart/kitchen/aff/kitchen.aff") else {
        return;
    };
    let dir = scratch_dir("convert_cli", "kitchen");
    let nff = dir.join("kitchen400.nff");
    let out = nffrt(
        &[
            "convert",
            kitchen.to_str().unwrap(),
            "--frame",
            "400",
            "-o",
            nff.to_str().unwrap(),
        ],
        b"",
    );
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(0), "{stderr}");
    assert!(stderr.contains("NFF has no textures"), "{stderr}");
    // The frame as `render --frame 400` flattens it, and the NFF file read back: the
    // same triangles (a mesh's written as polygons) and patches, vertices and normals
    // to the bit.
    let loaded = nffrt::load::load(nffrt::load::Source::File(&kitchen), &Default::default()).unwrap();
    let aff = loaded.aff.as_deref().unwrap();
    let frame = aff.flatten(aff.time_of_frame(400)).unwrap();
    let back = nffrt::nff::parse(&std::fs::read_to_string(&nff).unwrap()).unwrap();
    let (frame, back) = (shapes(&frame), shapes(&back));
    assert!(frame.len() > 100_000, "{}", frame.len());
    assert_eq!(frame.len(), back.len());
    assert!(frame == back, "the triangles differ");
}

/// Every polygon, mesh triangle and patch of `scene` as the bits of its vertices
/// (then normals), sorted.
fn shapes(scene: &nffrt::Scene) -> Vec<Vec<u32>> {
    let bits = |v: &mut dyn Iterator<Item = &nffrt::math::Vec3>| {
        v.flat_map(|p| p.to_array().map(f32::to_bits)).collect::<Vec<_>>()
    };
    let mut out: Vec<Vec<u32>> = scene
        .polygons
        .iter()
        .map(|p| bits(&mut scene.polygon_points(p).iter()))
        .collect();
    for m in &scene.meshes {
        for t in scene.mesh_triangles_of(m) {
            out.push(bits(
                &mut t.vertices.iter().map(|&k| &scene.mesh_vertices[k as usize]),
            ));
        }
    }
    for p in &scene.patches {
        let (v, n) = scene.patch_points(p);
        out.push(bits(&mut v.iter().chain(n)));
    }
    out.sort_unstable();
    out
}
