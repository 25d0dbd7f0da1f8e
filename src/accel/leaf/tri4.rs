//! Leaf blocks of four triangles in structure-of-arrays form, intersected together.
//!
//! A BVH leaf made only of triangles is stored as one or more [`Tri4`] blocks; one
//! watertight test over four lanes replaces four scalar ones (and two blocks go
//! through one eight-lane test, `ray8::pair_hits`). Every lane performs exactly the
//! scalar [`Triangle::intersect`] arithmetic (the one generic function
//! [`watertight`], same operations in the same order, no fused multiply-add), so
//! hits, distances and barycentrics are bit-identical to the scalar test's, and ties
//! go to the lane whose primitive has the lowest rank, as they go to that primitive
//! in the scalar loop (`traverse::nearest`).

use std::ops::{Add, Mul, Sub};

use wide::f32x4;

use crate::geometry::watertight::{watertight, watertight_exact, Sheared};
use crate::geometry::{Hit, Triangle};
use crate::math::{lanes, Ray};

/// Lanes per block.
pub const LANES: usize = 4;

/// Up to four triangles: the vertices `v0`, `v1`, `v2` per lane, `[axis][lane]`, and
/// the index of each lane's primitive. Unused lanes have NaN vertices (a NaN
/// distance, never hit, and no edge function exactly zero to recompute) and
/// primitive index `u32::MAX`.
#[derive(Clone, Copy, Debug)]
#[repr(C, align(32))]
pub struct Tri4 {
    pub(in crate::accel) v0: [[f32; LANES]; 3],
    pub(in crate::accel) v1: [[f32; LANES]; 3],
    pub(in crate::accel) v2: [[f32; LANES]; 3],
    /// Primitive index of each lane in the BVH's primitive array.
    pub prim: [u32; LANES],
}

const _: () = assert!(std::mem::size_of::<Tri4>() == 160);

/// A ray broadcast to four lanes, and prepared for the triangle test.
#[derive(Clone, Copy)]
pub struct Ray4 {
    pub(in crate::accel) origin: [f32x4; 3],
    pub(in crate::accel) dir: [f32x4; 3],
    /// The ray in the triangle test's frame.
    pub(in crate::accel) sheared: Sheared,
}

impl Ray4 {
    /// Broadcasts `ray`.
    #[inline(always)]
    pub fn new(ray: &Ray) -> Self {
        Ray4::with_sheared(ray, Sheared::new(ray))
    }

    /// Broadcasts `ray`, whose frame `sheared` is already known.
    #[inline(always)]
    pub fn with_sheared(ray: &Ray, sheared: Sheared) -> Self {
        let (o, d) = (ray.origin, ray.dir);
        Ray4 {
            origin: [f32x4::splat(o.x), f32x4::splat(o.y), f32x4::splat(o.z)],
            dir: [f32x4::splat(d.x), f32x4::splat(d.y), f32x4::splat(d.z)],
            sheared,
        }
    }
}

#[inline(always)]
fn load(a: &[f32; LANES]) -> f32x4 {
    f32x4::from(*a)
}

/// `a × b` per lane, component order as in `Vec3::cross`.
#[inline(always)]
pub(in crate::accel) fn cross<T: Copy + Mul<Output = T> + Sub<Output = T>>(a: &[T; 3], b: &[T; 3]) -> [T; 3] {
    [
        a[1] * b[2] - a[2] * b[1],
        a[2] * b[0] - a[0] * b[2],
        a[0] * b[1] - a[1] * b[0],
    ]
}

/// `a · b` per lane, summed left to right as in `Vec3::dot`.
#[inline(always)]
pub(in crate::accel) fn dot<T: Copy + Mul<Output = T> + Add<Output = T>>(a: &[T; 3], b: &[T; 3]) -> T {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}

/// Of the lanes in `mask` (not empty), the one with the least `t`, of equals the one
/// of the lowest `rank` (the rule of `traverse::nearest`; ranks are looked up only
/// for an exact tie).
#[inline(always)]
pub(in crate::accel) fn nearest_lane(t: &[f32], mask: u32, rank: impl Fn(usize) -> u64) -> usize {
    let mut lane = mask.trailing_zeros() as usize;
    let others = mask & (mask - 1);
    for k in lanes(others) {
        if t[k] < t[lane] {
            lane = k;
        }
    }
    if others != 0 {
        // Other lanes at exactly that distance (rare): the lowest rank of them all.
        for k in lanes(mask) {
            if t[k] == t[lane] && k != lane && rank(k) < rank(lane) {
                lane = k;
            }
        }
    }
    lane
}

impl Tri4 {
    /// Packs up to four triangles with their primitive indices.
    pub fn new(triangles: &[(Triangle, u32)]) -> Tri4 {
        assert!(
            triangles.len() <= LANES,
            "a block holds at most {LANES} triangles"
        );
        let mut block = Tri4 {
            v0: [[f32::NAN; LANES]; 3],
            v1: [[f32::NAN; LANES]; 3],
            v2: [[f32::NAN; LANES]; 3],
            prim: [u32::MAX; LANES],
        };
        for (lane, (t, prim)) in triangles.iter().enumerate() {
            for axis in 0..3 {
                block.v0[axis][lane] = t.v0[axis];
                block.v1[axis][lane] = t.v1[axis];
                block.v2[axis][lane] = t.v2[axis];
            }
            block.prim[lane] = *prim;
        }
        block
    }
}

impl Tri4 {
    /// The ray's [`Sheared::origin`] and [`Sheared::shear`] broadcast, and the
    /// vertices permuted by its axes.
    #[inline(always)]
    #[allow(clippy::type_complexity)]
    fn inputs(&self, ray: &Ray4) -> ([f32x4; 3], [f32x4; 3], [[f32x4; 3]; 3]) {
        let s = &ray.sheared;
        let [kx, ky, kz] = [s.axes[0] as usize, s.axes[1] as usize, s.axes[2] as usize];
        let vertex = |v: &[[f32; LANES]; 3]| [load(&v[kx]), load(&v[ky]), load(&v[kz])];
        let splat = |a: &[f32; 3]| [f32x4::splat(a[0]), f32x4::splat(a[1]), f32x4::splat(a[2])];
        (
            splat(&s.origin),
            splat(&s.shear),
            [vertex(&self.v0), vertex(&self.v1), vertex(&self.v2)],
        )
    }

    /// `Block::test` when an edge function came out zero (see [`watertight_exact`]).
    #[cold]
    #[inline(never)]
    fn test_exact(&self, ray: &Ray4, t_max: f32) -> (f32x4, f32x4, f32x4, u32) {
        let (origin, shear, [v0, v1, v2]) = self.inputs(ray);
        watertight_exact(&origin, &shear, &v0, &v1, &v2, f32x4::splat(t_max))
    }
}

impl Block for Tri4 {
    /// The watertight test on the four lanes (see [`watertight`]).
    #[inline(always)]
    fn test(&self, ray: &Ray4, t_max: f32) -> (f32x4, f32x4, f32x4, u32) {
        let (origin, shear, [v0, v1, v2]) = self.inputs(ray);
        match watertight(&origin, &shear, &v0, &v1, &v2, f32x4::splat(t_max)) {
            Some(found) => found,
            None => self.test_exact(ray, t_max),
        }
    }

    #[inline(always)]
    fn prims(&self) -> &[u32; LANES] {
        &self.prim
    }
}

/// A block of up to [`LANES`] primitives of one kind (in index order), tested
/// together against one ray.
pub(in crate::accel) trait Block {
    /// Per lane the distance and the barycentrics (zero for shapes without), and the
    /// lanes hit with `0 < t < t_max` as bits.
    fn test(&self, ray: &Ray4, t_max: f32) -> (f32x4, f32x4, f32x4, u32);

    /// The primitive index of each lane (`u32::MAX` for an empty one).
    fn prims(&self) -> &[u32; LANES];

    /// The nearest hit with `0 < t < t_max` (of equals, the one whose primitive has
    /// the lowest rank in `ranks`), and its primitive index.
    #[inline(always)]
    fn closest_hit(&self, ray: &Ray4, t_max: f32, ranks: &[u64]) -> Option<(Hit, u32)> {
        let (t, u, v, mask) = self.test(ray, t_max);
        if mask == 0 {
            return None;
        }
        let (t, u, v) = (t.to_array(), u.to_array(), v.to_array());
        let lane = nearest_lane(&t, mask, |k| ranks[self.prims()[k] as usize]);
        let hit = Hit {
            t: t[lane],
            u: u[lane],
            v: v[lane],
            part: 0,
        };
        Some((hit, self.prims()[lane]))
    }

    /// True when some lane is hit with `0 < t < t_max`.
    #[inline(always)]
    fn any_hit(&self, ray: &Ray4, t_max: f32) -> bool {
        self.test(ray, t_max).3 != 0
    }
}

/// Test helper for the blocks: for every run of up to [`LANES`] consecutive shapes of
/// `shapes` packed by `make` (lane `k` with primitive index `10 + k`), and every ray
/// and `t_max` of `rays`, the block's nearest hit is the scalar test's (`scalar`)
/// nearest over those shapes, distance bit for bit and the lowest lane among equals
/// (ranked in index order), and its any-hit query answers exactly when there is one.
#[cfg(test)]
pub(in crate::accel) fn assert_blocks_match_scalar<S: Copy, B: Block>(
    shapes: &[S],
    rays: &[(Ray, f32)],
    make: impl Fn(&[(S, u32)]) -> B,
    scalar: impl Fn(&S, &Ray, f32) -> Option<Hit>,
) {
    for first in 0..shapes.len().saturating_sub(1) {
        let chunk: Vec<(S, u32)> = shapes[first..]
            .iter()
            .take(LANES)
            .enumerate()
            .map(|(k, s)| (*s, 10 + k as u32))
            .collect();
        let block = make(&chunk);
        for (i, (ray, t_max)) in rays.iter().enumerate() {
            let expected = chunk
                .iter()
                .filter_map(|(s, prim)| scalar(s, ray, *t_max).map(|h| (h, *prim)))
                .fold(None::<(Hit, u32)>, |best, h| match best {
                    Some(b) if b.0.t <= h.0.t => Some(b),
                    _ => Some(h),
                });
            let ray4 = Ray4::new(ray);
            // Ranks in index order: of equals, the lowest lane.
            let ranks: Vec<u64> = (0..10 + LANES as u64).collect();
            let got = block.closest_hit(&ray4, *t_max, &ranks);
            assert_eq!(
                got.map(|(h, p)| (h.t.to_bits(), p)),
                expected.map(|(h, p)| (h.t.to_bits(), p)),
                "block {first}, ray {i}"
            );
            assert_eq!(block.any_hit(&ray4, *t_max), expected.is_some());
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::math::Vec3;

    fn tri(z: f32, scale: f32) -> Triangle {
        Triangle::new(
            Vec3::new(-scale, -scale, z),
            Vec3::new(scale, -scale, z),
            Vec3::new(0.0, scale, z),
            Triangle::FLAT,
        )
    }

    #[test]
    fn each_lane_matches_the_scalar_test_bit_for_bit() {
        let tris = [tri(3.0, 1.0), tri(2.0, 0.5), tri(5.0, 4.0), tri(-1.0, 1.0)];
        let block = Tri4::new(&[(tris[0], 10), (tris[1], 11), (tris[2], 12), (tris[3], 13)]);
        for (i, dir) in [
            (0.1, 0.2, 1.0),
            (0.0, 0.0, 1.0),
            (0.7, 0.1, 1.0),
            (0.0, 0.0, -1.0),
        ]
        .into_iter()
        .enumerate()
        {
            let ray = Ray::new(
                Vec3::new(0.05 * i as f32, 0.0, 0.0),
                Vec3::new(dir.0, dir.1, dir.2),
            );
            let expected = tris
                .iter()
                .enumerate()
                .filter_map(|(k, t)| t.intersect(&ray, 100.0).map(|h| (h, 10 + k as u32)))
                .fold(None::<(Hit, u32)>, |best, h| match best {
                    Some(b) if b.0.t <= h.0.t => Some(b),
                    _ => Some(h),
                });
            assert_eq!(
                block.closest_hit(&Ray4::new(&ray), 100.0, &[0, 1, 2, 3]),
                expected,
                "ray {i}"
            );
            assert_eq!(block.any_hit(&Ray4::new(&ray), 100.0), expected.is_some());
        }
    }

    #[test]
    fn the_nearest_lane_wins_and_t_max_is_exclusive() {
        let block = Tri4::new(&[(tri(3.0, 1.0), 0), (tri(2.0, 1.0), 1), (tri(2.0, 1.0), 2)]);
        let ray = Ray4::new(&Ray::new(Vec3::ZERO, Vec3::new(0.0, 0.0, 1.0)));
        // Lanes 1 and 2 tie at t = 2: the primitive of the lower rank wins, whichever
        // lane it is in.
        for (ranks, winner) in [([0, 1, 2], 1), ([0, 2, 1], 2), ([2, 1, 0], 2)] {
            assert_eq!(
                block.closest_hit(&ray, 10.0, &ranks).map(|h| (h.0.t, h.1)),
                Some((2.0, winner)),
                "ranks {ranks:?}"
            );
        }
        assert_eq!(block.closest_hit(&ray, 2.0, &[0, 1, 2]), None);
        assert!(!block.any_hit(&ray, 2.0));
        assert!(block.any_hit(&ray, 2.5));
    }

    /// A lane whose edge function rounds to zero goes through the scalar `f64`
    /// recomputation, and only that lane: the triangle on the ray's side of the edge
    /// is hit, its neighbour across it is not, as in the scalar test.
    #[test]
    fn an_edge_function_rounded_to_zero_is_recomputed_as_in_the_scalar_test() {
        let (ray, hit, missed) = crate::geometry::triangle::tests::split_by_a_near_edge();
        let block = Tri4::new(&[(missed, 0), (tri(3.0, 1.0), 1), (hit, 2), (missed, 3)]);
        let ray4 = Ray4::new(&ray);
        let (t, _, _, mask) = block.test(&ray4, f32::INFINITY);
        assert_eq!(mask, 0b0110);
        assert_eq!(
            block.closest_hit(&ray4, f32::INFINITY, &[0, 1, 2, 3]),
            Some((hit.intersect(&ray, f32::INFINITY).unwrap(), 2))
        );
        assert_eq!(t.to_array()[1], 3.0);
    }

    /// Rays straight down and slanted through the vertices and along the edges of a
    /// grid of triangles, where edge functions come out exactly zero (and stay zero
    /// in `f64`): every lane agrees with the scalar test, distance and barycentrics
    /// bit for bit.
    #[test]
    fn lanes_match_the_scalar_test_on_edges_and_vertices() {
        let mut tris = Vec::new();
        for i in 0..3 {
            for j in 0..2 {
                let (x, y) = (i as f32, j as f32);
                let z = |x: f32, y: f32| 0.25 * x - 0.5 * y;
                let p = |x: f32, y: f32| Vec3::new(x, y, z(x, y));
                tris.push(Triangle::new(
                    p(x, y),
                    p(x + 1.0, y),
                    p(x, y + 1.0),
                    Triangle::FLAT,
                ));
                tris.push(Triangle::new(
                    p(x + 1.0, y),
                    p(x + 1.0, y + 1.0),
                    p(x, y + 1.0),
                    Triangle::FLAT,
                ));
            }
        }
        let mut hits = 0;
        for block_tris in tris.chunks(LANES) {
            let block = Tri4::new(
                &block_tris
                    .iter()
                    .enumerate()
                    .map(|(k, t)| (*t, k as u32))
                    .collect::<Vec<_>>(),
            );
            for i in 0..=6 {
                for j in 0..=4 {
                    let (x, y) = (i as f32 * 0.5, j as f32 * 0.5);
                    for d in [
                        Vec3::new(0.0, 0.0, -1.0),
                        Vec3::new(0.5, -0.25, -1.0),
                        Vec3::new(-2.0, 1.0, -1.0),
                    ] {
                        let ray = Ray::new(Vec3::new(x, y, 0.25 * x - 0.5 * y) - d * 3.0, d);
                        let (t, u, v, mask) = block.test(&Ray4::new(&ray), f32::INFINITY);
                        for (k, tri) in block_tris.iter().enumerate() {
                            let want = tri.intersect(&ray, f32::INFINITY);
                            assert_eq!(mask & 1 << k != 0, want.is_some(), "lane {k}, ray {ray:?}");
                            if let Some(h) = want {
                                let got = (t.to_array()[k], u.to_array()[k], v.to_array()[k]);
                                assert_eq!(got.0.to_bits(), h.t.to_bits());
                                assert_eq!(
                                    (got.1.to_bits(), got.2.to_bits()),
                                    (h.u.to_bits(), h.v.to_bits())
                                );
                                hits += 1;
                            }
                        }
                    }
                }
            }
        }
        assert!(hits > 100, "{hits} hits");
    }

    #[test]
    fn empty_lanes_are_never_hit() {
        let block = Tri4::new(&[]);
        let ray = Ray4::new(&Ray::new(Vec3::new(0.0, 0.0, -1.0), Vec3::new(0.0, 0.0, 1.0)));
        assert_eq!(block.closest_hit(&ray, f32::INFINITY, &[]), None);
        assert!(!block.any_hit(&ray, f32::INFINITY));
    }
}
