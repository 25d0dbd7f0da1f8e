//! The traversal's corner cases: packets, ties in distance, rays lying in box faces
//! or passing through the shared edges of a mesh, empty lanes.

use super::*;

/// Packets give every ray exactly its single-ray answer (hit, distance bits and
/// primitive), for coherent rays from one point (the frustum test) and for rays
/// whose directions differ in sign (one walk per octant), packets of 1 to 8 rays, with
/// the kernels this CPU chose and with the portable ones, and so does the stream of
/// all of them (`closest_hits`); the scene has many exact ties (triangles sharing
/// edges, a grid of coincident spheres).
#[test]
fn packets_give_each_ray_its_single_ray_answer() {
    use crate::accel::traverse::wide::Portable;
    use crate::accel::PACKET;
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
    let bits = |h: &Option<(Hit, u32)>| h.map(|(h, p)| (h.t.to_bits(), h.u.to_bits(), h.v.to_bits(), p));
    let mut hits = 0;
    for size in [1, 3, PACKET] {
        for packet in rays.chunks(size) {
            let mut out = vec![None; packet.len()];
            let mut portable = vec![None; packet.len()];
            bvh.closest_hit_packet(packet, f32::INFINITY, &mut out);
            bvh.closest_hit_packet_with(Portable, packet, f32::INFINITY, &mut portable);
            for ((r, got), port) in packet.iter().zip(&out).zip(&portable) {
                let single = bvh.closest_hit(r, f32::INFINITY);
                assert_eq!(bits(got), bits(&single));
                assert_eq!(bits(port), bits(&single), "portable kernels");
                hits += usize::from(got.is_some());
            }
        }
    }
    assert!(hits > 3 * 3000, "{hits} hits: the rays should mostly hit");
    // A stream whose length is no multiple of the packet's.
    let stream = &rays[..rays.len() - 3];
    let mut out = vec![None; stream.len()];
    bvh.closest_hits(stream, f32::INFINITY, &mut out);
    for (r, got) in stream.iter().zip(&out) {
        assert_eq!(bits(got), bits(&bvh.closest_hit(r, f32::INFINITY)));
    }
}

/// Rays straight down onto the shared edges and corners of a flat grid of triangles:
/// several triangles are hit at exactly the same distance, in different leaves. The
/// lowest rank (here, the scene's order) must win, as in the reference scan, whatever
/// order the traversal meets them in.
#[test]
fn ties_go_to_the_lowest_rank_whatever_the_traversal_order() {
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
    let mut out = [None; crate::accel::PACKET];
    for packet in rays.chunks(crate::accel::PACKET) {
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
/// triangle's top edge (y = 2) is hit (the triangle test includes edges), so the slab
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
    let mut out = [None; crate::accel::PACKET];
    for packet in rows.chunks(crate::accel::PACKET) {
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
