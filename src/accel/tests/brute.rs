//! Closest hit and occlusion agree with the brute-force scan: random scenes
//! (proptest), deep trees, split cones, trees of fewer leaf kinds, moving spheres at
//! random ray times.

use super::*;
use crate::accel::Coherence;

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
    assert!(bvh.stats().depth >= 3, "wide depth {}", bvh.stats().depth);
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
    for packet in rays.chunks(crate::accel::PACKET) {
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
        assert!(bvh.stats().depth >= 3, "wide depth {}", bvh.stats().depth);
        assert_eq!(bvh.kinds, kinds);
        assert_agrees_with_brute_force(&bvh, &mut point);
    }
}

/// Moving spheres (tested alone, at each ray's time) among still spheres and
/// triangles, their own times inside a shutter of [0.2, 0.9]: rays at random times,
/// inside the shutter and outside it (where the spheres stand at its ends), single,
/// in packets of mixed times and for occlusion (single and in packets), find what
/// the scan finds.
#[test]
fn moving_spheres_agree_with_brute_force_at_any_time() {
    use crate::accel::leaf::ray8::{Ray8, RAYS};
    use crate::geometry::SourceKind;
    use crate::scene::MovingSphere;
    let mut time = uniform(0x3c6e_f372_fe94_f82b);
    let mut uniform = uniform(0xbb67_ae85_84ca_a73b);
    let mut next = move || uniform() * 2.0 - 1.0;
    let mut point = |scale: f32| Vec3::new(next() * scale, next() * scale, next() * scale);
    let spheres: Vec<(Vec3, f32)> = (0..300).map(|_| (point(20.0), 0.3)).collect();
    let tris: Vec<[Vec3; 3]> = (0..1000)
        .map(|_| {
            let a = point(20.0);
            [a, a + point(0.8), a + point(0.8)]
        })
        .collect();
    let mut scene = scene_with(&spheres, &tris);
    scene.shutter = Some([0.2, 0.9]);
    for i in 0..600 {
        let center0 = point(20.0);
        // Short and long paths; every fifth sphere inside-only.
        let path = point(if i % 3 == 0 { 6.0 } else { 1.0 });
        scene.moving_spheres.push(MovingSphere {
            center0,
            center1: center0 + path,
            radius: if i % 5 == 0 { -0.4 } else { 0.4 },
            time0: 0.4,
            time1: 0.6,
            material: 0,
            line: 1,
        });
    }
    let bvh = bvh_of(&scene);
    assert_eq!(bvh.kinds, leaf_kinds::ALL);
    // No moving sphere in a block of still ones.
    let blocked = bvh.sphere4.iter().flat_map(|b| b.prim).filter(|&p| p != u32::MAX);
    assert!(blocked
        .map(|p| bvh.primitive(p).kind)
        .all(|k| k == SourceKind::Sphere));
    let (mut moving_hits, mut rays) = (0, Vec::new());
    for _ in 0..4000 {
        let origin = point(25.0);
        let r = Ray::with_time(origin, (point(15.0) - origin).normalize(), time() * 2.0 - 0.5);
        let fast = bvh.closest_hit(&r, f32::INFINITY);
        assert_eq!(fast, bvh.closest_hit_linear(&r, f32::INFINITY), "time {}", r.time);
        let moving = fast.is_some_and(|(_, p)| bvh.primitive(p).kind == SourceKind::MovingSphere);
        moving_hits += usize::from(moving);
        let occluded: Vec<bool> = [2.0, 10.0, f32::INFINITY]
            .iter()
            .map(|&t_max| {
                let any = bvh.closest_hit_linear(&r, t_max).is_some();
                assert_eq!(bvh.occluded(&r, t_max), any);
                any
            })
            .collect();
        assert_portable_copy::<{ leaf_kinds::ALL }>(&bvh, &r, fast, &occluded);
        rays.push(r);
    }
    assert!(
        moving_hits > 300,
        "only {moving_hits} of 4000 rays hit a moving sphere: the test would be too weak"
    );
    // Packets of eight rays from one eye with mixed times: each ray's own hit.
    let eye = Vec3::new(0.0, 0.0, 40.0);
    let fan: Vec<Ray> = rays
        .iter()
        .map(|r| Ray::with_time(eye, (r.origin * 0.6 - eye).normalize(), r.time))
        .collect();
    for packet in fan.chunks(crate::accel::PACKET) {
        let mut out = vec![None; packet.len()];
        bvh.closest_hit_packet(packet, f32::INFINITY, &mut out);
        for (r, got) in packet.iter().zip(&out) {
            assert_eq!(*got, bvh.closest_hit_linear(r, f32::INFINITY), "time {}", r.time);
        }
    }
    // Shadow packets of eight rays from one point with mixed times, per-ray limits
    // and lanes left out: each active ray blocked exactly when the scan finds
    // something before its limit.
    let (mut blocked, mut moving_blockers) = (0, 0);
    for (p, packet) in fan.chunks(RAYS).enumerate() {
        let limits: [f32; RAYS] = std::array::from_fn(|k| [8.0, 30.0, 45.0, f32::INFINITY][(k + p) % 4]);
        let active = if p % 3 == 0 { 0b1011_0111 } else { 0xff } & ((1 << packet.len()) - 1);
        let got = bvh.occluded8(&Ray8::new(packet), &limits, active, Coherence::Coherent);
        for (k, r) in packet.iter().enumerate() {
            let first = bvh.closest_hit_linear(r, limits[k]);
            let want = active >> k & 1 != 0 && first.is_some();
            assert_eq!(got >> k & 1 != 0, want, "packet {p}, ray {k}, time {}", r.time);
            blocked += usize::from(want);
            let moving = first.is_some_and(|(_, i)| bvh.primitive(i).kind == SourceKind::MovingSphere);
            moving_blockers += usize::from(want && moving);
        }
    }
    assert!(
        blocked > 300 && moving_blockers > 150,
        "{blocked} shadow rays blocked, {moving_blockers} first by a moving sphere: the test would be too weak"
    );
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
        // The same hit and primitive: ties go to the lowest rank, as in the scan.
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
        bvh.closest_hit_with::<_, KINDS, _>(Portable, r, f32::INFINITY, &mut ()),
        closest
    );
    for (&t_max, &any) in [2.0, 10.0, f32::INFINITY].iter().zip(occluded) {
        assert_eq!(bvh.occluder_with::<_, KINDS>(Portable, r, t_max).is_some(), any);
    }
}
