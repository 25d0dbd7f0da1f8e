//! Generated scenes without the SPD's files: primitive counts as a function of size
//! (formulas worked out from the SPD's descriptions), the geometry each description
//! promises, and exact round trips through the NFF writer and parser.

use nffrt::gen::{generate, SpdScene};
use nffrt::limits::DEFAULT_MAX_PRIMITIVES;
use nffrt::math::Vec3;
use nffrt::Scene;

fn gen(which: SpdScene, size: u32) -> Scene {
    generate(which, size).unwrap()
}

fn close(a: f32, b: f32, tol: f32) -> bool {
    (a - b).abs() <= tol
}

#[test]
fn counts_follow_the_spd_formulas() {
    for n in 1..=4u32 {
        let s = gen(SpdScene::Balls, n);
        // 1 + 9 + 81 + ... + 9^n spheres and the floor.
        assert_eq!(s.spheres.len(), (0..=n).map(|k| 9usize.pow(k)).sum::<usize>());
        assert_eq!(s.polygons.len(), 1);

        let s = gen(SpdScene::Gears, n);
        // n^3 gears, each 2 faces of 144 vertices and 144 side rectangles; the floor.
        let gears = (n * n * n) as usize;
        assert_eq!(s.polygons.len(), 1 + gears * (2 + 144));
        assert_eq!(s.polygons.iter().filter(|p| p.count == 144).count(), 2 * gears);

        let s = gen(SpdScene::Mount, n);
        // Two triangles per cell of a 2^n x 2^n grid; four spheres.
        assert_eq!(s.polygons.len(), 2 * 4usize.pow(n));
        assert_eq!(s.spheres.len(), 4);

        let s = gen(SpdScene::Rings, n);
        // Layer d holds d^2 objects of 30 cylinders and 30 spheres.
        let objects: usize = (1..=n as usize).map(|d| d * d).sum();
        assert_eq!(
            (s.spheres.len(), s.cones.len(), s.polygons.len()),
            (30 * objects, 30 * objects, 1)
        );

        let s = gen(SpdScene::Teapot, n);
        // 32 patches of n x n quads, two triangles each, less the n triangles with two
        // corners on the cusp in each of the 4 lid-top and 4 bottom patches; n^2 squares.
        let n = n as usize;
        assert_eq!(s.patches.len(), 32 * 2 * n * n - 8 * n);
        assert_eq!(s.polygons.len(), n * n);

        let s = gen(SpdScene::Tetra, n as u32);
        assert_eq!(s.polygons.len(), 4usize.pow(n as u32));

        let s = gen(SpdScene::Tree, n as u32);
        // A binary tree of n levels below the trunk: 2^(n+1) - 1 branches.
        assert_eq!((s.cones.len(), s.spheres.len()), ((2 << n) - 1, (2 << n) - 1));
    }
}

#[test]
fn primitive_count_predicts_every_generated_scene() {
    for which in SpdScene::ALL {
        for size in 1..=3 {
            assert_eq!(
                gen(which, size).primitive_count() as u64,
                which.primitive_count(size),
                "{which} {size}"
            );
        }
        assert!(which.primitive_count(which.max_size()) <= DEFAULT_MAX_PRIMITIVES as u64);
        assert!(which.primitive_count(which.max_size() + 1) > DEFAULT_MAX_PRIMITIVES as u64);
    }
}

#[test]
fn writing_and_parsing_gives_back_the_same_scene() {
    for which in SpdScene::ALL {
        // Teapot size 1 has degenerate triangles (as in the SPD) that the parser skips.
        for size in [2, 3] {
            let scene = gen(which, size);
            let mut text = Vec::new();
            nffrt::nff::write_nff(&scene, &mut text).unwrap();
            let back = nffrt::nff::parse_bytes(&text).unwrap();
            assert!(
                back == scene,
                "{which} at size {size} does not survive a round trip"
            );
        }
    }
}

#[test]
fn sphereflake_children_touch_a_parent_three_times_their_size() {
    let s = gen(SpdScene::Balls, 3);
    assert_eq!((s.spheres[0].center, s.spheres[0].radius), (Vec3::ZERO, 0.5));
    for c in &s.spheres[1..] {
        let touching = s.spheres.iter().any(|p| {
            close(p.radius, 3.0 * c.radius, 1e-6)
                && close((p.center - c.center).length(), p.radius + c.radius, 1e-5)
        });
        assert!(touching, "sphere at {:?} has no parent", c.center);
    }
}

#[test]
fn tetra_triangles_are_equilateral_inside_the_cube() {
    for n in 1..=4u32 {
        // Level-n tetrahedra sit in cubes of half-side 2^(1-n); edges are face diagonals.
        let edge = 2f32.powi(2 - n as i32) * 2f32.sqrt();
        let s = gen(SpdScene::Tetra, n);
        for p in &s.polygons {
            let v = s.polygon_points(p);
            for k in 0..3 {
                assert!(close((v[k] - v[(k + 1) % 3]).length(), edge, 1e-5));
                assert!(v[k].abs().max_elem() <= 1.0);
            }
        }
    }
}

#[test]
fn mountain_sits_on_its_grid_and_its_spheres_touch() {
    let n = 4;
    let s = gen(SpdScene::Mount, n);
    let step = 2.0 / 2f32.powi(n as i32);
    for v in &s.polygon_vertices {
        for c in [v.x, v.y] {
            let k = (c + 1.0) / step;
            assert!(
                (-1.0..=1.0).contains(&c) && close(k, k.round(), 1e-4),
                "{c} is off the grid"
            );
        }
    }
    // The corners of the square stay at height zero.
    for corner in [Vec3::new(-1.0, -1.0, 0.0), Vec3::new(1.0, 1.0, 0.0)] {
        assert!(s.polygon_vertices.contains(&corner));
    }
    // Four spheres of radius 0.17 on a tetrahedron of edge 0.34: each pair touches.
    for (i, a) in s.spheres.iter().enumerate() {
        for b in &s.spheres[i + 1..] {
            assert!(close((a.center - b.center).length(), 0.34, 1e-5));
        }
    }
}

#[test]
fn teapot_normals_are_unit_and_the_pot_stands_on_the_board() {
    let s = gen(SpdScene::Teapot, 4);
    assert!(s.patch_normals.iter().all(|n| close(n.length(), 1.0, 1e-5)));
    let (lo, hi) = s
        .patch_vertices
        .iter()
        .fold((Vec3::splat(f32::MAX), Vec3::splat(f32::MIN)), |(lo, hi), v| {
            (lo.min(*v), hi.max(*v))
        });
    // Bottom at z = 0, lid knob at 3.15; handle out to -3, spout tip short of 3.525.
    assert!(close(lo.z, 0.0, 1e-6) && close(hi.z, 3.15, 1e-6), "{lo:?} {hi:?}");
    assert!(
        close(lo.x, -3.0, 1e-2) && hi.x < 3.525 && hi.x > 3.3,
        "{lo:?} {hi:?}"
    );
    // The board: n^2 squares tiling [-4, 4]^2 at z = 0.
    let area: f32 = s
        .polygons
        .iter()
        .map(|p| {
            let v = s.polygon_points(p);
            (v[2].x - v[0].x) * (v[2].y - v[0].y)
        })
        .sum();
    assert!(close(area, 64.0, 1e-3));
}

#[test]
fn tree_branches_start_where_a_joint_sphere_sits() {
    let s = gen(SpdScene::Tree, 5);
    let trunk = s.cones[0];
    assert_eq!(
        (trunk.base, trunk.base_radius, trunk.apex),
        (Vec3::ZERO, 0.15, Vec3::new(0.0, 0.0, 1.0))
    );
    for (c, sphere) in s.cones.iter().zip(&s.spheres) {
        // Every cone ends in its own sphere, narrowing by 0.67.
        assert_eq!((c.apex, c.apex_radius), (sphere.center, sphere.radius));
        assert!(close(c.apex_radius, 0.67 * c.base_radius, 1e-6));
    }
    for c in &s.cones[1..] {
        // Every other branch grows from a joint of the width of its base.
        assert!(s
            .spheres
            .iter()
            .any(|p| p.center == c.base && close(p.radius, c.base_radius, 1e-7)));
    }
}

#[test]
fn ring_tubes_are_pentagon_sides_ending_in_spheres() {
    let s = gen(SpdScene::Rings, 2);
    let side = (s.cones[0].apex - s.cones[0].base).length();
    // Pentagon of circumradius 1/(1 + 0.07412): side 2 R sin 36 degrees.
    assert!(close(side, 2.0 * 36f32.to_radians().sin() / 1.07412, 1e-5));
    for (c, sphere) in s.cones.iter().zip(&s.spheres) {
        assert!(close((c.apex - c.base).length(), side, 1e-5));
        assert_eq!(c.base, sphere.center);
    }
    // Six colours, one per ring, in the SPD's order.
    let red = s.materials[s.cones[0].material as usize].color;
    let yellow = s.materials[s.cones[29].material as usize].color;
    assert_eq!(
        (red, yellow),
        (Vec3::new(1.0, 0.0, 0.0), Vec3::new(1.0, 1.0, 0.0))
    );
}

#[test]
fn gear_faces_are_flat_and_a_fifth_of_the_gears_are_glass() {
    let s = gen(SpdScene::Gears, 3);
    for p in s.polygons.iter().filter(|p| p.count == 144) {
        let v = s.polygon_points(p);
        assert!(v.iter().all(|q| q.z == v[0].z));
    }
    let glass = s
        .polygons
        .iter()
        .filter(|p| p.count == 144 && s.materials[p.material as usize].t > 0.0)
        .count();
    // Gears with (4 ix + 2 iy + iz) divisible by 5, two faces each.
    let expected = (0..27)
        .filter(|i| (4 * (i % 3) + 2 * (i / 3 % 3) + i / 9) % 5 == 0)
        .count();
    assert_eq!(glass, 2 * expected);
}

#[test]
fn larger_mountains_refine_smaller_ones() {
    // The displacement of a point depends on its position only, so every vertex of
    // a coarser mountain is a vertex of a finer one, up to the SPD's size 7 and past it.
    let key = |v: &Vec3| [v.x.to_bits(), v.y.to_bits(), v.z.to_bits()];
    let fine = gen(SpdScene::Mount, 9);
    let fine: std::collections::HashSet<_> = fine.polygon_vertices.iter().map(key).collect();
    for size in [4, 6, 8] {
        let coarse = gen(SpdScene::Mount, size);
        let missing = coarse
            .polygon_vertices
            .iter()
            .filter(|v| !fine.contains(&key(v)))
            .count();
        assert_eq!(
            missing, 0,
            "size {size}: {missing} vertices are not on the size 9 mountain"
        );
    }
}
