//! Nested transforms, keyframed motion, visibility, the camera's keyframes and
//! animated triangles on small scenes whose flattened frames are worked out by hand.

use super::scene;
use crate::math::Vec3;

fn close(a: Vec3, b: Vec3) -> bool {
    (a - b).length() < 1e-5
}

/// An outer block (scale 2, 90° about z, then (1, 0, 0)) holding an inner one
/// (translate (0, 1, 0)) with a triangle, and a keyframed one with a sphere whose
/// keys move it along x: 0 at t = 0, 3 at t = 1 (Catmull-Rom: 1.5 halfway); three
/// frames a time unit apart.
const NESTED: &str = "\
xs 2 2 2  0 0 1 90  1 0 0
{
  xs 1 1 1  0 0 1 0  0 1 0
  {
    p 3  1 0 0  0 1 0  0 0 1
  }
  x mover
  {
    s 1 0 0 0.5
  }
}
a 0 3 3
k mover
{
  transl 4
  -1 0 0 0  0 0 0
   0 0 0 0  0 0 0
   1 3 0 0  0 0 0
   2 3 0 0  0 0 0
}
";

#[test]
fn nested_transforms_compose_parent_last() {
    let s = scene(NESTED);
    assert_eq!(s.frames(), 3);
    let frame = s.flatten(s.time_of_frame(0)).unwrap();
    // (1, 0, 0): inner (1, 1, 0); scaled (2, 2, 0); turned (-2, 2, 0); moved (-1, 2, 0).
    // (0, 1, 0): (0, 2, 0), (0, 4, 0), (-4, 0, 0), (-3, 0, 0).
    // (0, 0, 1): (0, 1, 1), (0, 2, 2), (-2, 0, 2), (-1, 0, 2).
    let want = [
        Vec3::new(-1.0, 2.0, 0.0),
        Vec3::new(-3.0, 0.0, 0.0),
        Vec3::new(-1.0, 0.0, 2.0),
    ];
    assert_eq!(frame.polygon_vertices.len(), 3);
    for (got, want) in frame.polygon_vertices.iter().zip(want) {
        assert!(close(*got, want), "{got:?} != {want:?}");
    }
    // The sphere's centre (1 + x, 0, 0) under the keys' x, then the outer block:
    // (2 + 2x, 0, 0), turned (0, 2 + 2x, 0), moved (1, 2 + 2x, 0); radius 0.5 · 2.
    for (frame_number, x) in [(0, 0.0), (1, 3.0), (2, 3.0)] {
        let f = s.flatten(s.time_of_frame(frame_number)).unwrap();
        let sphere = f.spheres[0];
        assert!(
            close(sphere.center, Vec3::new(1.0, 2.0 + 2.0 * x, 0.0)),
            "frame {frame_number}: {sphere:?}"
        );
        assert!((sphere.radius - 1.0).abs() < 1e-6);
    }
    let halfway = s.flatten(0.5).unwrap().spheres[0].center;
    assert!(close(halfway, Vec3::new(1.0, 5.0, 0.0)), "{halfway:?}");
}

#[test]
fn normals_follow_the_inverse_transpose() {
    // A patch on the plane x + y = 1 (normals (1, 1, 0)) stretched by 2 along x lies
    // on x/2 + y = 1, whose normal is along (1, 2, 0).
    let s = scene("xs 2 1 1  0 0 1 0  0 0 0 { pp 3  1 0 0 1 1 0  0 1 0 1 1 0  1 0 1 1 1 0 }\n");
    let frame = s.flatten(0.0).unwrap();
    for n in &frame.patch_normals {
        assert!(
            close(n.normalize(), Vec3::new(1.0, 2.0, 0.0).normalize()),
            "{n:?}"
        );
    }
    assert!(close(frame.patch_vertices[0], Vec3::new(2.0, 0.0, 0.0)));
}

#[test]
fn visibility_keys_hide_a_subtree() {
    let s = scene(
        "x blink { xs 1 1 1 0 0 1 0 0 0 0 { s 0 0 0 1 } }\n\
         k blink { visibility 2  0.5 0  1.5 1 }\n",
    );
    let spheres = |t: f64| s.flatten(t).unwrap().spheres.len();
    assert_eq!(
        (
            spheres(0.0),
            spheres(0.5),
            spheres(1.0),
            spheres(1.5),
            spheres(9.0)
        ),
        (1, 0, 0, 1, 1)
    );
}

#[test]
fn camera_keys_place_the_eye_and_turn_the_view() {
    // The camera looks down its own -z with +y up: turned 90° about y, -z becomes
    // -x (the third column of the rotation is (sin 90°, 0, cos 90°) = (1, 0, 0)).
    let s = scene(
        "k camera {\n\
           transl 4  -1 5 0 0 0 0 0  0 5 0 0 0 0 0  1 5 0 0 0 0 0  2 5 0 0 0 0 0\n\
           rot 4  -1 0 1 0 90 0 0 0  0 0 1 0 90 0 0 0  1 0 1 0 90 0 0 0  2 0 1 0 90 0 0 0\n\
         }\n",
    );
    let v = s.camera_at(0.5);
    assert!(close(v.from, Vec3::new(5.0, 0.0, 0.0)), "{v:?}");
    assert!(
        close((v.at - v.from).normalize(), Vec3::new(-1.0, 0.0, 0.0)),
        "{v:?}"
    );
    assert!(close(v.up, Vec3::new(0.0, 1.0, 0.0)), "{v:?}");
    // The angle and the image size stay the 'v' block's.
    assert_eq!((v.angle, v.width), (40.0, 8));
}

#[test]
fn animated_triangles_move_linearly_and_stay_outside_their_times() {
    // At t = 0 the triangle is at x = 0..1, at t = 2 shifted by 2 along x.
    let s = scene(
        "tpa 2\n\
         0  0 0 0 0 0 1  1 0 0 0 0 1  0 1 0 0 0 1\n\
         2  2 0 0 0 0 1  3 0 0 0 0 1  2 1 0 0 0 1\n",
    );
    let first_x = |t: f64| s.flatten(t).unwrap().patch_vertices[0].x;
    assert_eq!(
        (
            first_x(-1.0),
            first_x(0.0),
            first_x(0.5),
            first_x(1.0),
            first_x(2.0),
            first_x(5.0)
        ),
        (0.0, 0.0, 0.5, 1.0, 2.0, 2.0)
    );
}

#[test]
fn meshes_are_placed_by_their_node() {
    // Two `m` keywords are two geometries (one text read twice, by an include, is
    // one: tests/aff_files.rs).
    let mesh = "m vertices 3 0 0 0 1 0 0 0 1 0 triangles 1 0 1 2\n";
    let s = scene(&format!("{mesh}xs 1 1 1 0 0 1 0 5 0 0 {{ {mesh} }}\n"));
    assert_eq!((s.objects.len(), s.meshes.geometries.len()), (2, 2));
    let frame = s.flatten(0.0).unwrap();
    assert_eq!(frame.mesh_triangles.len(), 2);
    assert!(close(frame.mesh_vertices[3], Vec3::new(5.0, 0.0, 0.0)));
    let summary = s.summary();
    assert_eq!((summary.instanced_triangles, summary.flattened_triangles), (2, 2));
}

#[test]
fn the_span_maps_frames_to_times_as_the_original_renderer() {
    // a -1 5 300: step (5 - -1) / 300 = 0.02; frame 299 at 4.98, frame 300 (the
    // original's last picture) at 5.
    let s = scene("a -1 5 300\n");
    assert_eq!(s.time_of_frame(0), -1.0);
    assert!((s.time_of_frame(1) - -0.98).abs() < 1e-12);
    assert!((s.time_of_frame(299) - 4.98).abs() < 1e-12);
    assert!((s.time_of_frame(300) - 5.0).abs() < 1e-12);
    let still = scene("");
    assert_eq!((still.frames(), still.time_of_frame(0)), (1, 0.0));
}
