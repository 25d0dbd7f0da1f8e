//! BVH tests: structural validation on edge cases and the builder's (here),
//! closest-hit / occlusion agreement with the brute-force scan on random scenes and
//! rays (`brute`), and the traversal's corner cases: packets, ties, rays in faces
//! and through shared edges (`edges`).

use super::build::collapse::MAX_MERGED_LEAF;
use super::leaf::pack::leaf_kinds;
use super::{Bvh, NO_HINT};
use crate::geometry::build_geometry;
use crate::geometry::{ConeShape, Hit};
use crate::math::{Ray, Vec3};
use crate::scene::{Cone, Material, Polygon, Scene, Sphere};
use proptest::prelude::*;

mod brute;
mod edges;
mod graft;
mod instance;
mod packets8;
mod structures;
mod watertight;

/// Points in the cube `[-range, range)^3`.
fn v3(range: f32) -> impl Strategy<Value = Vec3> {
    (-range..range, -range..range, -range..range).prop_map(|(x, y, z)| Vec3::new(x, y, z))
}

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
pub(crate) fn uniform(seed: u64) -> impl FnMut() -> f32 {
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
    assert!(st.max_leaf <= MAX_MERGED_LEAF);
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
    let one_by_one = build(|i| cubes[i], &[Pack::Alone; 4]);
    assert_eq!(one_by_one.nodes[0].count, 0, "split at the root");
    assert_eq!(one_by_one.nodes.len(), 7, "four leaves of one");
    for pack in [Pack::Triangle, Pack::Sphere, Pack::Cone] {
        let blocks = build(|i| cubes[i], &[pack; 4]);
        assert_eq!(blocks.nodes.len(), 1, "one leaf of {pack:?}");
        assert_eq!(blocks.nodes[0].count, 4);
    }
    let mixed = build(
        |i| cubes[i],
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
fn bins_without_kinds_build_the_tree_bins_with_kinds_build() {
    // A build whose primitives are all of one kind leaves the bins' kinds untracked;
    // tracking them must not change the tree.
    use crate::accel::build::sah::{build_with, build_with_kinds, Pack, Packs};
    let bits =
        |n: &crate::accel::BvhNode| (n.min.map(f32::to_bits), n.max.map(f32::to_bits), n.first, n.count);
    for (kind, pack) in [
        (0, Pack::Triangle),
        (1, Pack::Sphere),
        (2, Pack::Alone),
        (3, Pack::Cone),
    ] {
        for (seed, n) in [(6, 9), (7, 300), (8, 20_000)] {
            let boxes = random_boxes(n, seed, kind);
            let packs = vec![pack; n];
            let untracked = build_with(&boxes, &packs, usize::MAX);
            let tracked = build_with_kinds(|i| boxes[i], &packs, usize::MAX, None);
            let what = format!("{pack:?}, kind {kind}, {n} boxes");
            assert_eq!(untracked.order, tracked.order, "{what}");
            assert!(
                untracked
                    .nodes
                    .iter()
                    .map(bits)
                    .eq(tracked.nodes.iter().map(bits)),
                "{what}"
            );
            assert_eq!(Packs::of(packs.iter().copied()).uniform(), Some(Packs::one(pack)));
        }
    }
}

#[test]
fn parallel_build_equals_sequential_build_exactly() {
    use crate::accel::build::sah::{build_with, Pack, MAX_LEAF};
    let pool = rayon::ThreadPoolBuilder::new().num_threads(4).build().unwrap();
    let bits =
        |n: &crate::accel::BvhNode| (n.min.map(f32::to_bits), n.max.map(f32::to_bits), n.first, n.count);
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

/// Everything the queries read of `bvh`, as bits: the wide nodes, and each leaf-order
/// entry's box (which tells the primitive order).
fn tree_bits(bvh: &Bvh) -> (Vec<u32>, Vec<u32>) {
    let wide = bvh
        .wide
        .iter()
        .flat_map(|n| {
            let bounds = n.bounds.iter().flatten().flatten().map(|x| x.to_bits());
            bounds.chain(n.child).chain(n.count).collect::<Vec<_>>()
        })
        .collect();
    let entries = bvh.primitives[..bvh.bounded]
        .iter()
        .flat_map(|p| {
            let b = p.bounds(&bvh.data).expect("bounded");
            [b.min, b.max].map(|v| v.to_array().map(f32::to_bits))
        })
        .flatten()
        .collect();
    (wide, entries)
}

/// A scene of every packable kind, big enough for the builder's parallel passes:
/// scattered and clustered spheres, triangles, cones (thin ones split in pieces).
fn soup(n: usize) -> Scene {
    let mut uniform = uniform(0x9e37_79b9_7f4a_7c15);
    let mut next = move || uniform() * 2.0 - 1.0;
    let mut point = |scale: f32| Vec3::new(next() * scale, next() * scale, next() * scale);
    let spheres: Vec<(Vec3, f32)> = (0..n)
        .map(|i| (point(50.0), 0.05 + (i % 7) as f32 * 0.03))
        .collect();
    let tris: Vec<[Vec3; 3]> = (0..n)
        .map(|_| {
            let a = point(50.0);
            [a, a + point(0.8), a + point(0.8)]
        })
        .collect();
    let mut scene = scene_with(&spheres, &tris);
    for i in 0..n / 4 {
        let base = point(50.0);
        let (r, apex) = if i % 3 == 0 {
            (0.04, point(1.5))
        } else {
            (0.2, point(0.6))
        };
        scene.cones.push(Cone {
            base,
            base_radius: r,
            apex: base + apex,
            apex_radius: r * 0.5,
            material: 0,
            line: 1,
        });
    }
    scene
}

/// The tree (binary and wide nodes, leaf order) is the same bits on one, two and
/// four threads: the parallel passes of the biggest nodes and the subtrees handed to
/// `rayon::join` give what the serial build gives.
#[test]
fn the_tree_is_the_same_on_any_number_of_threads() {
    use crate::gen::{generate, SpdScene};
    let scenes = [generate(SpdScene::Mount, 8).expect("mount 8"), soup(40_000)];
    for scene in &scenes {
        let trees: Vec<_> = [1, 2, 4]
            .map(|threads| {
                let pool = rayon::ThreadPoolBuilder::new()
                    .num_threads(threads)
                    .build()
                    .unwrap();
                pool.install(|| tree_bits(&bvh_of(scene)))
            })
            .into();
        assert!(trees[0].1.len() > 90_000, "{} entries", trees[0].1.len() / 6);
        assert!(trees[1] == trees[0], "two threads against one");
        assert!(trees[2] == trees[0], "four threads against one");
    }
}

/// `info --bvh`'s figures agree with the wide tree's shape: every node but the root
/// fills one lane of its parent, every entry is in one leaf lane, a leaf holds at
/// most the collapse's largest merged leaf, and the root (which every ray entering
/// the tree visits) counts 1 toward the expected visits, which the SAH cost
/// includes; no tree, no figures.
#[test]
fn the_tree_statistics_count_its_nodes_and_lanes() {
    assert_eq!(
        bvh_of(&Scene::default()).stats(),
        crate::accel::BvhStats::default()
    );
    let spheres: Vec<_> = (0..512)
        .map(|i| (Vec3::new(i as f32 * 3.0, (i % 7) as f32, 0.0), 0.5))
        .collect();
    let st = bvh_of(&scene_with(&spheres, &[])).stats();
    assert!(st.nodes > 1 && st.depth > 1, "{st:?}");
    let lanes = (st.mean_lanes * st.nodes as f64).round() as usize;
    assert_eq!(lanes, st.nodes - 1 + st.leaves, "{st:?}");
    assert_eq!((st.mean_leaf * st.leaves as f64).round() as usize, 512, "{st:?}");
    assert!(st.min_leaf >= 1 && st.max_leaf <= MAX_MERGED_LEAF, "{st:?}");
    assert!(
        st.expected_visits >= 1.0 && st.expected_visits <= st.nodes as f64,
        "{st:?}"
    );
    assert!(st.sah_cost > st.expected_visits, "{st:?}");
}
