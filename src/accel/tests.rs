//! BVH tests: structural validation on edge cases, and closest-hit / occlusion
//! agreement with the brute-force scan on random scenes and rays.

use super::leaf::pack::leaf_kinds;
use super::{Bvh, NO_HINT};
use crate::geometry::build_geometry;
use crate::geometry::{ConeShape, Hit};
use crate::math::{Ray, Vec3};
use crate::scene::{Cone, Material, Polygon, Scene, Sphere};
use proptest::prelude::*;

fn scene_with(spheres: &[(Vec3, f32)], triangles: &[[Vec3; 3]]) -> Scene {
    let mut s = Scene {
        materials: vec![Material::DEFAULT],
        ..Scene::default()
    };
    for &(center, radius) in spheres {
        s.spheres.push(Sphere {
            center,
            radius,
            material: 0,
            line: 1,
        });
    }
    for t in triangles {
        let first = s.polygon_vertices.len() as u32;
        s.polygon_vertices.extend_from_slice(t);
        s.polygons.push(Polygon {
            first,
            count: 3,
            material: 0,
            line: 1,
        });
    }
    s
}

/// A fixed-seed xorshift generator of floats uniform in `[0, 1)`, for reproducible
/// random scenes and rays (`seed` must not be zero).
pub(super) fn uniform(seed: u64) -> impl FnMut() -> f32 {
    let mut state = seed;
    move || {
        state ^= state << 13;
        state ^= state >> 7;
        state ^= state << 17;
        (state >> 40) as f32 / (1u64 << 24) as f32
    }
}

fn bvh_of(scene: &Scene) -> Bvh {
    let bvh = Bvh::new(build_geometry(scene));
    bvh.validate().unwrap();
    bvh
}

#[test]
fn empty_scene_has_no_hits() {
    let bvh = bvh_of(&Scene::default());
    let r = Ray::new(Vec3::ZERO, Vec3::new(0.0, 0.0, 1.0));
    assert!(bvh.closest_hit(&r, f32::INFINITY).is_none());
    assert!(!bvh.occluded(&r, f32::INFINITY));
    assert_eq!(bvh.stats().nodes, 0);
}

#[test]
fn single_sphere_is_hit_at_the_analytic_distance() {
    let bvh = bvh_of(&scene_with(&[(Vec3::new(0.0, 0.0, 5.0), 1.0)], &[]));
    let r = Ray::new(Vec3::ZERO, Vec3::new(0.0, 0.0, 1.0));
    let (hit, _) = bvh.closest_hit(&r, f32::INFINITY).unwrap();
    assert!((hit.t - 4.0).abs() < 1e-5);
    assert!(bvh.occluded(&r, 10.0));
    assert!(!bvh.occluded(&r, 3.9));
}

#[test]
fn coincident_primitives_still_build_a_valid_shallow_tree() {
    let spheres: Vec<_> = (0..1000).map(|_| (Vec3::splat(1.0), 0.5)).collect();
    let bvh = bvh_of(&scene_with(&spheres, &[]));
    let st = bvh.stats();
    assert!(st.depth <= 12, "depth {}", st.depth);
    assert!(st.max_leaf as usize <= crate::accel::build::sah::MAX_LEAF);
}

/// Four unit cubes 10 apart along x. By hand: root area 2(31 + 31 + 1) = 126, each
/// half (two cubes) 2(11 + 11 + 1) = 46. Four primitives tested one by one cost 4 as a
/// leaf and 1 + (46·2 + 46·2)/126 ≈ 2.46 split in halves, so they are split; four
/// that pack in one kind of block cost one block (1) as a leaf and 1 + (46 + 46)/126
/// ≈ 1.73 split, so they stay in one leaf; two triangles and two spheres cannot share
/// a block, so they are split like the first four.
#[test]
fn the_sah_counts_packable_primitives_a_block_at_a_time() {
    use crate::accel::build::sah::{build, leaf_cost, Pack, Packs};
    use crate::math::Aabb;
    let cubes: Vec<Aabb> = (0..4)
        .map(|i| {
            let min = Vec3::new(10.0 * i as f32, 0.0, 0.0);
            Aabb::new(min, min + Vec3::splat(1.0))
        })
        .collect();
    let one_by_one = build(&cubes, &[Pack::Alone; 4]);
    assert_eq!(one_by_one.nodes[0].count, 0, "split at the root");
    assert_eq!(one_by_one.nodes.len(), 7, "four leaves of one");
    for pack in [Pack::Triangle, Pack::Sphere, Pack::Cone] {
        let blocks = build(&cubes, &[pack; 4]);
        assert_eq!(blocks.nodes.len(), 1, "one leaf of {pack:?}");
        assert_eq!(blocks.nodes[0].count, 4);
    }
    let mixed = build(
        &cubes,
        &[Pack::Triangle, Pack::Sphere, Pack::Triangle, Pack::Sphere],
    );
    assert_eq!(mixed.nodes[0].count, 0, "mixed kinds split at the root");
    let packs = |kinds: &[Pack]| Packs::of(kinds.iter().copied());
    let (triangles, spheres, cones) = (
        packs(&[Pack::Triangle]),
        packs(&[Pack::Sphere]),
        packs(&[Pack::Cone]),
    );
    // Eight triangles to a test (two blocks of four), four spheres or four cones (one
    // block).
    assert_eq!(leaf_cost(8, triangles), 1.0);
    assert_eq!(leaf_cost(9, triangles), 2.0);
    assert_eq!(leaf_cost(4, spheres), 1.0);
    assert_eq!(leaf_cost(5, spheres), 2.0);
    assert_eq!(leaf_cost(4, cones), 1.0);
    assert_eq!(leaf_cost(6, cones), 2.0);
    assert_eq!(leaf_cost(4, packs(&[Pack::Triangle, Pack::Alone])), 4.0);
    assert_eq!(leaf_cost(4, packs(&[Pack::Triangle, Pack::Sphere])), 4.0);
    assert_eq!(leaf_cost(4, packs(&[Pack::Sphere, Pack::Cone])), 4.0);
    assert_eq!(leaf_cost(0, Packs::default()), 0.0);
}

#[test]
fn degenerate_flat_boxes_are_handled() {
    // Axis-aligned triangles have zero-thickness boxes.
    let tris: Vec<[Vec3; 3]> = (0..200)
        .map(|i| {
            let x = i as f32 * 0.1;
            [
                Vec3::new(x, 0.0, 0.0),
                Vec3::new(x + 0.1, 0.0, 0.0),
                Vec3::new(x, 1.0, 0.0),
            ]
        })
        .collect();
    let bvh = bvh_of(&scene_with(&[], &tris));
    let r = Ray::new(Vec3::new(5.02, 0.5, 1.0), Vec3::new(0.0, 0.0, -1.0));
    let (hit, _) = bvh.closest_hit(&r, f32::INFINITY).unwrap();
    assert!((hit.t - 1.0).abs() < 1e-6);
}

fn v3(range: f32) -> impl Strategy<Value = Vec3> {
    (-range..range, -range..range, -range..range).prop_map(|(x, y, z)| Vec3::new(x, y, z))
}

fn unit() -> impl Strategy<Value = Vec3> {
    v3(1.0)
        .prop_filter("non-zero", |v| v.length() > 0.1)
        .prop_map(Vec3::normalize)
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(64))]

    #[test]
    fn bvh_agrees_with_brute_force(
        spheres in prop::collection::vec((v3(10.0), 0.05f32..2.0), 0..60),
        tris in prop::collection::vec((v3(10.0), v3(2.0), v3(2.0)), 0..60),
        rays in prop::collection::vec((v3(15.0), unit()), 1..40),
    ) {
        let tris: Vec<[Vec3; 3]> = tris.iter().map(|&(a, d1, d2)| [a, a + d1, a + d2]).collect();
        let scene = scene_with(&spheres, &tris);
        let bvh = Bvh::new(build_geometry(&scene));
        prop_assert!(bvh.validate().is_ok());
        for (o, d) in rays {
            let r = Ray::new(o, d);
            let fast = bvh.closest_hit(&r, f32::INFINITY);
            let slow = bvh.closest_hit_linear(&r, f32::INFINITY);
            prop_assert_eq!(fast.is_some(), slow.is_some());
            if let (Some((a, _)), Some((b, _))) = (fast, slow) {
                prop_assert!((a.t - b.t).abs() <= 1e-6 * a.t.max(1.0), "{} vs {}", a.t, b.t);
                prop_assert!(a.t > 0.0 && a.t.is_finite());
            }
            for t_max in [1.0f32, 5.0, f32::INFINITY] {
                let any = bvh.closest_hit_linear(&r, t_max).is_some();
                prop_assert_eq!(bvh.occluded(&r, t_max), any);
                // The shadow cache never changes the answer, whatever the hint holds
                // (nothing, a primitive, a block of each kind, stale indices past the
                // ends); afterwards it names primitives of which one really lies on
                // the ray when one does, and nothing when none does.
                for start in [NO_HINT, 0, 7, 1000, 1 << 30, (1 << 30) | 1, 2 << 30, 3 << 30, (2 << 30) | 999] {
                    let hint = std::cell::Cell::new(start);
                    prop_assert_eq!(bvh.occluded_hinted(&r, t_max, &hint), any);
                    if any {
                        let blocker = bvh.hint_primitives(hint.get());
                        prop_assert!(blocker
                            .iter()
                            .any(|&p| bvh.primitive(p).intersect(&r, t_max, bvh.data()).is_some()));
                    } else {
                        prop_assert_eq!(hint.get(), NO_HINT);
                    }
                }
            }
        }
    }
}

/// Thousands of primitives make trees several wide levels deep, so traversal goes
/// through its stack (the proptest scenes above are mostly one or two levels).
#[test]
fn deep_trees_agree_with_brute_force() {
    let mut uniform = uniform(0x2545_f491_4f6c_dd1d);
    let mut next = move || uniform() * 2.0 - 1.0;
    let mut point = |scale: f32| Vec3::new(next() * scale, next() * scale, next() * scale);
    let mut spheres: Vec<(Vec3, f32)> = (0..500).map(|_| (point(20.0), 0.2)).collect();
    // Clusters of eight (leaves of several spheres, tested in blocks) and a few
    // inside-only spheres (tested alone).
    for _ in 0..25 {
        let c = point(20.0);
        for _ in 0..8 {
            spheres.push((c + point(0.5), 0.1));
        }
    }
    for _ in 0..20 {
        spheres.push((point(20.0), -0.5));
    }
    let tris: Vec<[Vec3; 3]> = (0..3000)
        .map(|_| {
            let a = point(20.0);
            [a, a + point(0.8), a + point(0.8)]
        })
        .collect();
    let mut scene = scene_with(&spheres, &tris);
    // Cones and cylinders: scattered, in clusters of six (leaves of several cones,
    // tested in blocks), and a few inside-only ones (tested alone).
    let mut cone = |base: Vec3, r: f32, apex: Vec3, ra: f32| {
        scene.cones.push(Cone {
            base,
            base_radius: r,
            apex,
            apex_radius: ra,
            material: 0,
            line: 1,
        })
    };
    for i in 0..300 {
        let base = point(20.0);
        cone(base, 0.2, base + point(1.5), if i % 2 == 0 { 0.2 } else { 0.05 });
    }
    for _ in 0..25 {
        let c = point(20.0);
        for _ in 0..6 {
            let base = c + point(0.5);
            cone(base, 0.1, base + point(0.4), 0.1);
        }
    }
    for _ in 0..10 {
        let base = point(20.0);
        cone(base, -0.5, base + point(1.0), -0.3);
    }
    // Thin ones, most of them filed in pieces (`accel::build::split`).
    for _ in 0..100 {
        let base = point(20.0);
        cone(base, 0.04, base + point(1.5), 0.04);
    }
    let bvh = bvh_of(&scene);
    assert!(bvh.stats().depth >= 8, "depth {}", bvh.stats().depth);
    let (split, whole) = (bvh.stats().references, bvh.stats().primitives);
    assert!(
        split >= whole + 50,
        "only {} cones split in pieces",
        split - whole
    );
    let shared = bvh.sphere4.iter().filter(|b| b.prim[1] != u32::MAX).count();
    assert!(
        shared >= 20,
        "only {shared} sphere blocks hold more than one sphere"
    );
    let shared = bvh.cone4.iter().filter(|b| b.prim[1] != u32::MAX).count();
    assert!(shared >= 20, "only {shared} cone blocks hold more than one cone");
    assert_eq!(bvh.kinds, leaf_kinds::ALL);
    assert_agrees_with_brute_force(&bvh, &mut point);
}

/// Thin cylinders lying across the axes, as in the SPD's rings, are filed in pieces
/// (`accel::build::split`); rays aimed at their sides right at the seams between pieces (and
/// a little to either side) find the hit the scan finds, single and in packets.
#[test]
fn rays_at_the_seams_of_split_cones_find_the_scans_hit() {
    let mut uniform = uniform(0x6a09_e667_f3bc_c908);
    let mut next = move || uniform() * 2.0 - 1.0;
    let mut scene = scene_with(&[], &[]);
    let mut cones = Vec::new();
    for i in 0..400 {
        let base = Vec3::new(next() * 20.0, next() * 20.0, next() * 20.0);
        let dir = Vec3::new(next(), next(), next() * 0.3).normalize();
        let apex = base + dir * (1.0 + next().abs());
        let r = 0.05 + 0.03 * next().abs();
        scene.cones.push(Cone {
            base,
            base_radius: r,
            apex,
            apex_radius: if i % 3 == 0 { r * 0.5 } else { r },
            material: 0,
            line: 1,
        });
        cones.push(ConeShape::new(
            base,
            r,
            apex,
            if i % 3 == 0 { r * 0.5 } else { r },
        ));
    }
    let bvh = bvh_of(&scene);
    let (split, whole) = (bvh.stats().references, bvh.stats().primitives);
    assert!(split >= whole + 300, "only {} of 400 cones split", split - whole);
    let eye = Vec3::new(3.0, -4.0, 60.0);
    let mut rays = Vec::new();
    for c in &cones {
        for s in [0.5, 0.4999, 0.5001, 0.499, 0.501] {
            let along = c.length * s;
            let r = c.base_radius + c.slope * along;
            let centre = c.base + c.axis * along;
            // The point of the side facing the eye, then a ray from the eye to it.
            let towards = eye - centre;
            let side = (towards - c.axis * towards.dot(c.axis)).normalize();
            let target = centre + side * r;
            rays.push(Ray::new(eye, (target - eye).normalize()));
        }
    }
    let mut hits = 0;
    for r in &rays {
        let fast = bvh.closest_hit(r, f32::INFINITY);
        assert_eq!(fast, bvh.closest_hit_linear(r, f32::INFINITY));
        assert_eq!(bvh.occluded(r, f32::INFINITY), fast.is_some());
        hits += usize::from(fast.is_some());
    }
    assert!(hits >= rays.len() * 9 / 10, "{hits} of {} rays hit", rays.len());
    for packet in rays.chunks(super::PACKET) {
        let mut out = vec![None; packet.len()];
        bvh.closest_hit_packet(packet, f32::INFINITY, &mut out);
        for (r, got) in packet.iter().zip(&out) {
            assert_eq!(*got, bvh.closest_hit(r, f32::INFINITY));
        }
    }
}

/// Scenes of triangles only, and of spheres and triangles apart, deep enough to use
/// the stack: the queries run their copies for those kinds of leaf (see
/// `Bvh::kinds`), which agree with the scan and with the general copy.
#[test]
fn deep_trees_of_fewer_kinds_agree_with_brute_force() {
    let mut uniform = uniform(0x9e37_79b9_7f4a_7c15);
    let mut next = move || uniform() * 2.0 - 1.0;
    let mut point = |scale: f32| Vec3::new(next() * scale, next() * scale, next() * scale);
    // Triangles at x > 0, spheres (in the second scene) at x < 0.
    let tris: Vec<[Vec3; 3]> = (0..4000)
        .map(|_| {
            let a = point(10.0) + Vec3::new(11.0, 0.0, 0.0);
            [a, a + point(0.8), a + point(0.8)]
        })
        .collect();
    let spheres: Vec<(Vec3, f32)> = (0..1500)
        .map(|_| (point(10.0) - Vec3::new(11.0, 0.0, 0.0), 0.2))
        .collect();
    for (spheres, kinds) in [
        (&[][..], leaf_kinds::TRIANGLES),
        (&spheres[..], leaf_kinds::SPHERES_AND_TRIANGLES),
    ] {
        let bvh = bvh_of(&scene_with(spheres, &tris));
        assert!(bvh.stats().depth >= 8, "depth {}", bvh.stats().depth);
        assert_eq!(bvh.kinds, kinds);
        assert_agrees_with_brute_force(&bvh, &mut point);
    }
}

/// 3000 rays between random points of `point(scale)`: closest hits (hit and
/// primitive) equal the linear scan's, occlusion agrees with it at three distances,
/// and every copy of the queries that serves the tree (see `Bvh::kinds`) with the
/// portable kernels gives the answers of the copy and kernels this CPU chose.
fn assert_agrees_with_brute_force(bvh: &Bvh, point: &mut impl FnMut(f32) -> Vec3) {
    let mut hits = 0;
    for _ in 0..3000 {
        let origin = point(25.0);
        let r = Ray::new(origin, (point(15.0) - origin).normalize());
        let fast = bvh.closest_hit(&r, f32::INFINITY);
        let slow = bvh.closest_hit_linear(&r, f32::INFINITY);
        // The same hit and primitive: ties go to the lowest index, as in the scan.
        assert_eq!(fast, slow);
        hits += usize::from(fast.is_some());
        let occluded: Vec<bool> = [2.0, 10.0, f32::INFINITY]
            .iter()
            .map(|&t_max| {
                let any = bvh.closest_hit_linear(&r, t_max).is_some();
                assert_eq!(bvh.occluded(&r, t_max), any);
                any
            })
            .collect();
        // The portable kernels (what the queries run on a CPU without AVX2) give the
        // very same answers as the ones this CPU may have chosen, in every copy.
        assert_portable_copy::<{ leaf_kinds::ALL }>(bvh, &r, fast, &occluded);
        if bvh.kinds & !leaf_kinds::SPHERES_AND_TRIANGLES == 0 {
            assert_portable_copy::<{ leaf_kinds::SPHERES_AND_TRIANGLES }>(bvh, &r, fast, &occluded);
        }
        if bvh.kinds == leaf_kinds::TRIANGLES {
            assert_portable_copy::<{ leaf_kinds::TRIANGLES }>(bvh, &r, fast, &occluded);
        }
    }
    assert!(
        hits > 500,
        "only {hits} of 3000 rays hit: the test would be too weak"
    );
}

/// The portable copy of the queries for leaf kinds `KINDS` gives `closest` as the
/// closest hit of `r` and `occluded` as its occlusion at t_max 2, 10 and infinity.
fn assert_portable_copy<const KINDS: u32>(
    bvh: &Bvh,
    r: &Ray,
    closest: Option<(Hit, u32)>,
    occluded: &[bool],
) {
    use crate::accel::traverse::wide::Portable;
    assert_eq!(
        bvh.closest_hit_with::<_, KINDS>(Portable, r, f32::INFINITY),
        closest
    );
    for (&t_max, &any) in [2.0, 10.0, f32::INFINITY].iter().zip(occluded) {
        assert_eq!(bvh.occluder_with::<_, KINDS>(Portable, r, t_max).is_some(), any);
    }
}

/// Boxes for the builder tests: `n` random ones from a fixed-seed generator, shaped
/// by `kind`.
pub(super) fn random_boxes(n: usize, seed: u64, kind: u32) -> Vec<crate::math::Aabb> {
    let mut next = uniform(seed.wrapping_mul(0x9e37_79b9_7f4a_7c15) | 1);
    let special = [
        0.0,
        -0.0,
        f32::INFINITY,
        f32::NEG_INFINITY,
        f32::NAN,
        3e38,
        -3e38,
        1e-40,
    ];
    (0..n)
        .map(|i| {
            let mut v = || Vec3::new(next(), next(), next());
            let (lo, size) = match kind {
                // General position, mixed sizes.
                0 => (v() * 100.0, v() * 2.0),
                // All the same box.
                1 => (Vec3::splat(1.0), Vec3::splat(0.5)),
                // Points, on a coarse grid so many coincide.
                2 => {
                    let p = v() * 8.0;
                    (Vec3::new(p.x.floor(), p.y.floor(), p.z.floor()), Vec3::ZERO)
                }
                // Huge coordinates, overflowing sums and extents.
                3 => (v() * 3e38 * 2.0 - Vec3::splat(3e38), v() * 1e38),
                // Special values (signed zeros, infinities, NaN) among ordinary boxes.
                _ => {
                    let s = |k: usize| special[(k * 7 + i) % special.len()];
                    if i % 3 == 0 {
                        (Vec3::new(s(0), s(1), s(2)), Vec3::new(s(3), 0.0, s(5)).abs())
                    } else {
                        (v() * 10.0, v())
                    }
                }
            };
            crate::math::Aabb::new(lo, lo + size)
        })
        .collect()
}

#[test]
fn parallel_build_equals_sequential_build_exactly() {
    use crate::accel::build::sah::{build_with, Pack, MAX_LEAF};
    let pool = rayon::ThreadPoolBuilder::new().num_threads(4).build().unwrap();
    let bits = |n: &super::BvhNode| (n.min.map(f32::to_bits), n.max.map(f32::to_bits), n.first, n.count);
    for kind in 0..5 {
        for (seed, n) in [(1, 1), (2, 7), (3, 100), (4, 5000), (5, 30_000)] {
            let boxes = random_boxes(n, seed, kind);
            // Packable and not, mixed (each box's flag from its index).
            let kinds = [
                Pack::Alone,
                Pack::Triangle,
                Pack::Triangle,
                Pack::Sphere,
                Pack::Triangle,
            ];
            let packable: Vec<Pack> = (0..n).map(|i| kinds[i % 5]).collect();
            let seq = build_with(&boxes, &packable, usize::MAX);
            for threshold in [0, 64, 4096] {
                let par = pool.install(|| build_with(&boxes, &packable, threshold));
                let what = format!("kind {kind}, {n} boxes, threshold {threshold}");
                assert_eq!(par.order, seq.order, "{what}");
                assert_eq!(par.depth, seq.depth, "{what}");
                assert_eq!(par.nodes.len(), seq.nodes.len(), "{what}");
                assert!(
                    par.nodes.iter().map(bits).eq(seq.nodes.iter().map(bits)),
                    "{what}"
                );
            }
            let mut sorted = seq.order.clone();
            sorted.sort_unstable();
            assert!(
                sorted.iter().copied().eq(0..n as u32),
                "kind {kind}: order is a permutation"
            );
            // Interior nodes point at later siblings; leaves cover the primitives once.
            let mut covered = 0;
            for (i, node) in seq.nodes.iter().enumerate() {
                if node.count == 0 {
                    assert!(node.first as usize > i && node.first as usize + 1 < seq.nodes.len());
                } else {
                    covered += node.count as usize;
                    assert!(node.count as usize <= MAX_LEAF || kind != 0);
                }
            }
            assert_eq!(covered, n);
        }
    }
}

/// Packets give every ray exactly its single-ray answer (hit, distance bits and
/// primitive), for coherent rays from one point (the interval test) and for rays
/// whose directions differ in sign (ray-by-ray tests), packets of 1 to 8 rays; the
/// scene has many exact ties (triangles sharing edges, a grid of coincident spheres).
#[test]
fn packets_give_each_ray_its_single_ray_answer() {
    use super::PACKET;
    let mut tris = Vec::new();
    for i in 0..40 {
        for j in 0..40 {
            let (x, y) = (i as f32 * 0.5 - 10.0, j as f32 * 0.5 - 10.0);
            let z = ((i * 7 + j * 3) % 5) as f32 * 0.1;
            let (a, b, c, d) = (
                Vec3::new(x, y, z),
                Vec3::new(x + 0.5, y, z),
                Vec3::new(x, y + 0.5, z),
                Vec3::new(x + 0.5, y + 0.5, z),
            );
            tris.push([a, b, c]);
            tris.push([b, d, c]);
        }
    }
    let spheres: Vec<(Vec3, f32)> = (0..200)
        .map(|i| (Vec3::new((i % 20) as f32 - 10.0, (i / 20) as f32 - 5.0, 2.0), 0.5))
        .chain((0..50).map(|_| (Vec3::new(3.0, 3.0, 4.0), 0.7)))
        .collect();
    let bvh = bvh_of(&scene_with(&spheres, &tris));
    let eye = Vec3::new(0.3, -2.0, 25.0);
    let mut rays = Vec::new();
    for j in 0..64 {
        for i in 0..64 {
            let target = Vec3::new(i as f32 * 0.33 - 10.5, j as f32 * 0.33 - 10.5, 0.0);
            rays.push(Ray::new(eye, (target - eye).normalize()));
        }
    }
    // Directions of mixed signs: from the scene's middle outwards and across it.
    for i in 0..512 {
        let a = i as f32 * 0.61;
        let d = Vec3::new(a.cos(), a.sin(), (a * 0.37).sin() * 0.5);
        rays.push(Ray::new(Vec3::new(0.1, 0.2, 1.0), d.normalize()));
    }
    let mut hits = 0;
    for size in [1, 3, PACKET] {
        for packet in rays.chunks(size) {
            let mut out = vec![None; packet.len()];
            bvh.closest_hit_packet(packet, f32::INFINITY, &mut out);
            for (r, got) in packet.iter().zip(&out) {
                let single = bvh.closest_hit(r, f32::INFINITY);
                assert_eq!(
                    got.map(|(h, p)| (h.t.to_bits(), h.u.to_bits(), h.v.to_bits(), p)),
                    single.map(|(h, p)| (h.t.to_bits(), h.u.to_bits(), h.v.to_bits(), p))
                );
                hits += usize::from(got.is_some());
            }
        }
    }
    assert!(hits > 3 * 3000, "{hits} hits: the rays should mostly hit");
}

/// Rays straight down onto the shared edges and corners of a flat grid of triangles:
/// several triangles are hit at exactly the same distance, in different leaves. The
/// lowest primitive index must win, whatever order the traversal meets them in.
#[test]
fn ties_go_to_the_lowest_primitive_index() {
    let mut tris = Vec::new();
    for i in 0..24 {
        for j in 0..24 {
            let (x, y) = (i as f32, j as f32);
            let (a, b, c, d) = (
                Vec3::new(x, y, 0.0),
                Vec3::new(x + 1.0, y, 0.0),
                Vec3::new(x, y + 1.0, 0.0),
                Vec3::new(x + 1.0, y + 1.0, 0.0),
            );
            tris.push([a, b, c]);
            tris.push([b, d, c]);
        }
    }
    let bvh = bvh_of(&scene_with(&[], &tris));
    let mut rays = Vec::new();
    for i in 1..48 {
        for j in 1..48 {
            let o = Vec3::new(i as f32 * 0.5, j as f32 * 0.5, 5.0);
            rays.push(Ray::new(o, Vec3::new(0.0, 0.0, -1.0)));
        }
    }
    let mut out = [None; super::PACKET];
    for packet in rays.chunks(super::PACKET) {
        let out = &mut out[..packet.len()];
        bvh.closest_hit_packet(packet, f32::INFINITY, out);
        for (r, got) in packet.iter().zip(out.iter()) {
            let scan = bvh.closest_hit_linear(r, f32::INFINITY);
            assert!(scan.is_some());
            assert_eq!(bvh.closest_hit(r, f32::INFINITY), scan, "ray at {:?}", r.origin);
            assert_eq!(*got, scan, "packet ray at {:?}", r.origin);
        }
    }
}

/// A ray with a zero direction component lying exactly in its box's face: the
/// triangle's top edge (y = 2) is hit (Möller–Trumbore includes edges), so the slab
/// test must not close the box at t = 0 (see `RayBoxes::exit_origin`).
#[test]
fn a_ray_in_a_box_face_still_finds_its_primitive() {
    let tri = [
        Vec3::new(0.0, 0.0, 0.0),
        Vec3::new(1.0, 2.0, 0.0),
        Vec3::new(0.0, 2.0, 0.0),
    ];
    let bvh = bvh_of(&scene_with(&[], &[tri]));
    for (o, d) in [
        (Vec3::new(0.5, 2.0, 5.0), Vec3::new(0.0, 0.0, -1.0)),
        (Vec3::new(0.0, 1.0, -5.0), Vec3::new(-0.0, 0.0, 1.0)),
    ] {
        let r = Ray::new(o, d);
        let hit = bvh.closest_hit(&r, f32::INFINITY);
        assert_eq!(hit.map(|h| h.0.t), Some(5.0), "from {o:?}");
        assert!(bvh.occluded(&r, 6.0));
        let mut out = [None];
        bvh.closest_hit_packet(&[r], f32::INFINITY, &mut out);
        assert_eq!(out[0], hit);
    }
}

/// Rays aimed exactly at the vertices and edge midpoints of a bumpy, tilted mesh of
/// 4 608 triangles, from scattered origins (single rays) and from one eye along the
/// rows (packets): where neighbouring triangles meet, the hit lies on the boundary of
/// the leaf boxes, whose computed entry and exit may cross by a rounding (a miss
/// through the mesh unless exits are stretched, `wide::FAR_SCALE`) or land a few
/// units in the last place beyond the triangle test's distance (the lower index of a
/// tie skipped unless the search looks a little further, `nearest::TIE_SLACK`). The
/// answer must be the scan's, ties included, and occlusion must see every hit.
#[test]
fn rays_through_shared_edges_and_vertices_find_the_scans_hit() {
    let mut rnd = uniform(0x9e37_79b9_7f4a_7c15);
    let n = 48;
    let heights: Vec<f32> = (0..(n + 1) * (n + 1)).map(|_| rnd() * 0.7).collect();
    let vertex = |i: usize, j: usize| {
        let (x, y, z) = (i as f32 * 0.37, j as f32 * 0.41, heights[i * (n + 1) + j]);
        Vec3::new(
            x * 0.8 + z * 0.6,
            y * 0.9 - z * 0.3 + x * 0.1,
            z * 0.7 - x * 0.35 + y * 0.2,
        )
    };
    let mut tris = Vec::new();
    for i in 0..n {
        for j in 0..n {
            let (a, b, c, d) = (
                vertex(i, j),
                vertex(i + 1, j),
                vertex(i, j + 1),
                vertex(i + 1, j + 1),
            );
            tris.push([a, b, c]);
            tris.push([b, d, c]);
        }
    }
    let bvh = bvh_of(&scene_with(&[], &tris));
    let target = |rnd: &mut dyn FnMut() -> f32, i: usize, j: usize| {
        if rnd() < 0.5 {
            vertex(i, j)
        } else {
            let (a, b) = (vertex(i, j), vertex(i + 1, j));
            a + (b - a) * 0.5
        }
    };
    let mut rays = Vec::new();
    for _ in 0..20_000 {
        let (i, j) = ((rnd() * n as f32) as usize, (rnd() * n as f32) as usize);
        let o = Vec3::new(rnd() * 30.0 - 5.0, rnd() * 30.0 - 5.0, 25.0 + rnd() * 10.0);
        rays.push(Ray::new(o, (target(&mut rnd, i, j) - o).normalize()));
    }
    let eye = Vec3::new(7.0, 9.0, 30.0);
    let rows: Vec<Ray> = (0..n * n)
        .map(|k| Ray::new(eye, (target(&mut rnd, k / n, k % n) - eye).normalize()))
        .collect();
    let mut ties = 0;
    let mut check = |r: &Ray, got: Option<(Hit, u32)>| {
        let scan = bvh.closest_hit_linear(r, f32::INFINITY);
        assert_eq!(got, scan, "ray from {:?} along {:?}", r.origin, r.dir);
        assert_eq!(bvh.occluded(r, f32::INFINITY), scan.is_some());
        if let Some((hit, p)) = scan {
            let data = bvh.data();
            let tie = |q: u32| {
                q != p
                    && bvh
                        .primitive(q)
                        .intersect(r, f32::INFINITY, data)
                        .is_some_and(|h| h.t == hit.t)
            };
            ties += usize::from((0..tris.len() as u32).any(tie));
        }
    };
    for r in &rays {
        check(r, bvh.closest_hit(r, f32::INFINITY));
    }
    let mut out = [None; super::PACKET];
    for packet in rows.chunks(super::PACKET) {
        let out = &mut out[..packet.len()];
        bvh.closest_hit_packet(packet, f32::INFINITY, out);
        for (r, &got) in packet.iter().zip(out.iter()) {
            check(r, got);
        }
    }
    // About one ray in ten meets two triangles at the same distance.
    assert!(
        ties > 1_000,
        "{ties} ties: the rays should test the rule for ties"
    );
}

/// An empty lane (`wide::EMPTY`'s inside-out box) is missed by every ray, whatever
/// its `t_max`, including rays along the axes (infinite inverse directions) and rays
/// starting at the origin; a lane in use beside it is still entered.
#[test]
fn empty_lanes_are_never_entered() {
    use crate::accel::traverse::wide::{Kernels, Portable, RayBoxes, EMPTY, MAX, MIN};
    let mut node = EMPTY;
    for axis in 0..3 {
        node.bounds[MIN][axis][0] = -1.0;
        node.bounds[MAX][axis][0] = 1.0;
    }
    let mut rnd = uniform(0x5eed);
    let mut dirs: Vec<Vec3> = (0..500)
        .map(|_| Vec3::new(rnd() - 0.5, rnd() - 0.5, rnd() - 0.5).normalize())
        .collect();
    for axis in 0..3 {
        for sign in [1.0, -1.0] {
            let mut d = [0.0f32; 3];
            d[axis] = sign;
            dirs.push(Vec3::from_array(d));
        }
    }
    for (i, d) in dirs.iter().enumerate() {
        for origin in [Vec3::ZERO, Vec3::new(0.3, -0.2, 0.1), *d * -5.0] {
            let r = RayBoxes::new(&Ray::new(origin, *d));
            for t_max in [f32::INFINITY, f32::MAX, 100.0, 0.5] {
                let (_, mask) = Portable.entries(&node, &r, t_max);
                let entered = Portable.entered(&node, &r, t_max);
                assert_eq!(mask & !1, 0, "ray {i} from {origin:?}, t_max {t_max}");
                assert_eq!(entered & !1, 0, "ray {i} from {origin:?}, t_max {t_max}");
                if t_max > 10.0 {
                    assert_eq!((mask, entered), (1, 1), "ray {i} from {origin:?}");
                }
            }
        }
    }
}
