//! Leaf blocks of four spheres in structure-of-arrays form, intersected together.
//!
//! The sphere counterpart of [`Tri4`](super::tri4::Tri4): a BVH leaf made only of
//! (outside-visible) spheres is stored as one or more [`Sphere4`] blocks, 80 bytes for
//! four spheres where the primitives take 64 bytes each. Every lane performs exactly
//! the arithmetic of the scalar [`SphereShape::intersect`] (same operations in the same
//! order, no fused multiply-add), so hits and distances are bit-identical to the
//! scalar test's, and ties go to the lane whose primitive has the lowest rank, as they
//! go to that primitive in the scalar loop (`traverse::nearest`).

use wide::f32x4;

use super::tri4::{dot, Block, Ray4, LANES};
use crate::geometry::SphereShape;

/// Up to four spheres that are visible from outside (`inside` false): centres
/// `[axis][lane]`, squared radii, and the index of each lane's primitive. Unused lanes
/// have a squared radius of −1 (a negative discriminant, never hit) and primitive
/// index `u32::MAX`.
#[derive(Clone, Copy, Debug, PartialEq)]
#[repr(C, align(16))]
pub struct Sphere4 {
    center: [[f32; LANES]; 3],
    radius2: [f32; LANES],
    /// Primitive index of each lane in the BVH's primitive array.
    pub prim: [u32; LANES],
}

const _: () = assert!(std::mem::size_of::<Sphere4>() == 80);

/// `f32::min` per lane: a NaN operand gives the other one (`fast_min` alone gives
/// its second operand).
#[inline(always)]
pub(in crate::accel) fn min(a: f32x4, b: f32x4) -> f32x4 {
    b.is_nan().bitselect(a, a.fast_min(b))
}

/// `f32::max` per lane, NaN as in [`min`].
#[inline(always)]
pub(in crate::accel) fn max(a: f32x4, b: f32x4) -> f32x4 {
    b.is_nan().bitselect(a, a.fast_max(b))
}

impl Sphere4 {
    /// Packs up to four spheres with their primitive indices.
    ///
    /// # Panics
    /// With more than four spheres, or an inside-only one.
    pub fn new(spheres: &[(SphereShape, u32)]) -> Sphere4 {
        assert!(spheres.len() <= LANES, "a block holds at most {LANES} spheres");
        let mut block = Sphere4 {
            center: [[0.0; LANES]; 3],
            radius2: [-1.0; LANES],
            prim: [u32::MAX; LANES],
        };
        for (lane, (s, prim)) in spheres.iter().enumerate() {
            assert!(!s.inside, "inside-only spheres are tested alone");
            for (axis, c) in s.center.to_array().into_iter().enumerate() {
                block.center[axis][lane] = c;
            }
            block.radius2[lane] = s.radius2;
            block.prim[lane] = *prim;
        }
        block
    }
}

impl Block for Sphere4 {
    /// The scalar sphere test on the four lanes (no barycentrics: zero).
    #[inline(always)]
    fn test(&self, ray: &Ray4, t_max: f32) -> (f32x4, f32x4, f32x4, u32) {
        let d = &ray.dir;
        let center = self.center.map(f32x4::from);
        let radius2 = f32x4::from(self.radius2);
        let f = [0, 1, 2].map(|axis| ray.origin[axis] - center[axis]);
        let a = dot(d, d);
        let b = -dot(&f, d);
        let along = b / a;
        let l = [0, 1, 2].map(|axis| f[axis] + d[axis] * along);
        let disc = radius2 - dot(&l, &l);
        // `disc >= 0` is false for a NaN, which the scalar test rejects too. Most
        // blocks end here, before the square root and the divisions.
        let crossing = disc.simd_ge(f32x4::ZERO).to_bitmask();
        if crossing == 0 {
            return (disc, f32x4::ZERO, f32x4::ZERO, 0);
        }
        let c = dot(&f, &f) - radius2;
        // `copysign` of a non-negative (or NaN) root: its magnitude with b's sign bit.
        let root = (a * disc).sqrt();
        let q = b + (root.abs() | (b & f32x4::splat(-0.0)));
        let (r0, r1) = (c / q, q / a);
        let (t0, t1) = (min(r0, r1), max(r0, r1));
        let zero = f32x4::ZERO;
        let t_max = f32x4::splat(t_max);
        let near = t0.simd_gt(zero) & t0.simd_lt(t_max);
        let far = t1.simd_gt(zero) & t1.simd_lt(t_max);
        let t = near.bitselect(t0, t1);
        (t, zero, zero, crossing & (near | far).to_bitmask())
    }

    #[inline(always)]
    fn prims(&self) -> &[u32; LANES] {
        &self.prim
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::accel::leaf::tri4::assert_blocks_match_scalar;
    use crate::math::{Ray, Vec3};

    /// Spheres and rays chosen to reach every branch of the scalar test: misses, the
    /// near root, the far root from inside, tiny spheres far away, a sphere behind the
    /// origin, a tangent, a zero direction (NaN) and `t_max` cutting between roots.
    fn cases() -> (Vec<SphereShape>, Vec<(Ray, f32)>) {
        let spheres = vec![
            SphereShape::new(Vec3::new(0.0, 0.0, 5.0), 1.0),
            SphereShape::new(Vec3::new(0.3, -0.2, 9.0), 2.5),
            SphereShape::new(Vec3::new(100.0, 50.0, 3000.0), 0.0006),
            SphereShape::new(Vec3::new(0.0, 0.0, -4.0), 1.0),
            SphereShape::new(Vec3::new(1.0, 0.0, 3.0), 1.0),
            SphereShape::new(Vec3::new(0.0, 0.1, 0.0), 0.5),
        ];
        let mut rays = Vec::new();
        for (o, d) in [
            (Vec3::ZERO, Vec3::new(0.0, 0.0, 1.0)),
            (Vec3::ZERO, Vec3::new(0.1, -0.05, 1.0)),
            (Vec3::ZERO, Vec3::new(100.0, 50.0, 3000.0)),
            (Vec3::new(0.0, 0.0, 5.0), Vec3::new(0.2, 0.7, -0.1)),
            (Vec3::ZERO, Vec3::new(0.0, 0.0, -1.0)),
            (Vec3::new(0.0, 1.0, 3.0), Vec3::new(1.0, 0.0, 0.0)),
            (Vec3::new(0.0, 0.0, 1.0), Vec3::ZERO),
            (Vec3::new(-3.0, 0.2, 9.0), Vec3::new(1.0, 0.0, 0.0)),
        ] {
            for t_max in [f32::INFINITY, 5.0, 4.0, 0.5] {
                rays.push((Ray::new(o, d), t_max));
            }
        }
        (spheres, rays)
    }

    #[test]
    fn each_lane_matches_the_scalar_test_bit_for_bit() {
        let (spheres, rays) = cases();
        assert_blocks_match_scalar(&spheres, &rays, Sphere4::new, |s, ray, t_max| {
            s.intersect(ray, t_max)
        });
    }

    #[test]
    fn the_rays_reach_both_roots_and_misses() {
        // Guards the cases above against losing their point: near roots, far roots
        // (from inside) and misses all occur.
        let (spheres, rays) = cases();
        let (mut near, mut far, mut miss) = (0, 0, 0);
        for s in &spheres {
            for (ray, t_max) in &rays {
                match s.intersect(ray, *t_max) {
                    None => miss += 1,
                    Some(h) if (ray.at(h.t) - s.center).dot(ray.dir) < 0.0 => near += 1,
                    Some(_) => far += 1,
                }
            }
        }
        assert!(near > 0 && far > 0 && miss > 0, "{near} {far} {miss}");
    }

    #[test]
    fn empty_lanes_are_never_hit() {
        let block = Sphere4::new(&[]);
        let ray = Ray4::new(&Ray::new(Vec3::ZERO, Vec3::new(0.0, 0.0, 1.0)));
        assert_eq!(block.closest_hit(&ray, f32::INFINITY, &[]), None);
        assert!(!block.any_hit(&ray, f32::INFINITY));
    }

    #[test]
    #[should_panic(expected = "inside-only")]
    fn inside_only_spheres_are_refused() {
        Sphere4::new(&[(SphereShape::new(Vec3::ZERO, -1.0), 0)]);
    }
}
