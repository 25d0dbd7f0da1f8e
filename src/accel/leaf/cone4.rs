//! Leaf blocks of four cones (or cylinders) in structure-of-arrays form, intersected
//! together.
//!
//! The cone counterpart of [`Sphere4`](super::sphere4::Sphere4): a BVH leaf made only
//! of cones visible from outside is stored as one or more [`Cone4`] blocks. Every lane
//! performs exactly the arithmetic of the scalar [`ConeShape::intersect`] (same
//! operations in the same order, no fused multiply-add; the two per-cone constants it
//! recomputes for every ray, the larger radius and the axis midpoint, are computed
//! once here by the same expressions), so hits and distances are bit-identical to
//! the scalar test's. A block whose lanes all fail the scalar test's quick rejection
//! stops there, before the divisions, the square root and the roots.

use wide::f32x4;

use super::sphere4::{max, min};
use super::tri4::{cross, dot, Block, Ray4, LANES};
use crate::geometry::ConeShape;

/// Up to four open cones visible from outside, `[axis][lane]` for vectors: the base
/// centre, the unit axis, the axis midpoint `base + axis · (length / 2)`, the length,
/// the base radius, the slope, the larger of the two radii, and each lane's primitive
/// index. Unused lanes hold NaNs (a NaN length fails the quick rejection: never hit)
/// and primitive index `u32::MAX`.
#[derive(Clone, Copy, Debug)]
#[repr(C, align(16))]
pub struct Cone4 {
    base: [[f32; LANES]; 3],
    axis: [[f32; LANES]; 3],
    mid: [[f32; LANES]; 3],
    length: [f32; LANES],
    base_radius: [f32; LANES],
    slope: [f32; LANES],
    max_radius: [f32; LANES],
    /// Primitive index of each lane in the BVH's primitive array.
    pub prim: [u32; LANES],
}

const _: () = assert!(std::mem::size_of::<Cone4>() == 224);

impl Cone4 {
    /// Packs up to four cones with their primitive indices.
    ///
    /// # Panics
    /// With more than four cones, an inside-only one or a degenerate one (base and
    /// apex in one point).
    pub fn new(cones: &[(ConeShape, u32)]) -> Cone4 {
        assert!(cones.len() <= LANES, "a block holds at most {LANES} cones");
        let mut block = Cone4 {
            base: [[f32::NAN; LANES]; 3],
            axis: [[f32::NAN; LANES]; 3],
            mid: [[f32::NAN; LANES]; 3],
            length: [f32::NAN; LANES],
            base_radius: [f32::NAN; LANES],
            slope: [f32::NAN; LANES],
            max_radius: [f32::NAN; LANES],
            prim: [u32::MAX; LANES],
        };
        for (lane, (c, prim)) in cones.iter().enumerate() {
            assert!(!c.inside, "inside-only cones are tested alone");
            assert!(c.length > 0.0, "degenerate cones are tested alone");
            // As `ConeShape::intersect` computes them.
            let mid = c.base + c.axis * (0.5 * c.length);
            for axis in 0..3 {
                block.base[axis][lane] = c.base.to_array()[axis];
                block.axis[axis][lane] = c.axis.to_array()[axis];
                block.mid[axis][lane] = mid.to_array()[axis];
            }
            block.length[lane] = c.length;
            block.base_radius[lane] = c.base_radius;
            block.slope[lane] = c.slope;
            block.max_radius[lane] = c.base_radius.max(c.apex_radius());
            block.prim[lane] = *prim;
        }
        block
    }
}

impl Block for Cone4 {
    /// The scalar cone test on the four lanes (no barycentrics: zero).
    #[inline(always)]
    fn test(&self, ray: &Ray4, t_max: f32) -> (f32x4, f32x4, f32x4, u32) {
        let load3 = |a: &[[f32; LANES]; 3]| a.map(f32x4::from);
        let (o, d) = (&ray.origin, &ray.dir);
        let (base, w) = (load3(&self.base), load3(&self.axis));
        let length = f32x4::from(self.length);
        let zero = f32x4::ZERO;
        // Quick rejection: the ray's line passes farther from the axis line than the
        // larger radius (plus the scalar test's margin).
        let to_base = [0, 1, 2].map(|a| base[a] - o[a]);
        let n = cross(d, &w);
        let g = dot(&to_base, &n);
        let far = to_base[0]
            .abs()
            .fast_max(to_base[1].abs())
            .fast_max(to_base[2].abs());
        let reach = f32x4::from(self.max_radius) + f32x4::splat(1e-4) * (far + length.abs());
        // `!(g² > …)`: a NaN goes on, as in the scalar test; unused lanes (a NaN
        // length) stop here.
        let near_axis = !(g * g).simd_gt(reach * reach * dot(&n, &n)) & length.simd_gt(zero);
        if near_axis.to_bitmask() == 0 {
            return (zero, zero, zero, 0);
        }
        let mid = load3(&self.mid);
        let t_c = dot(&[0, 1, 2].map(|a| mid[a] - o[a]), d) / dot(d, d);
        let f = [0, 1, 2].map(|a| (o[a] + d[a] * t_c) - base[a]);
        let (f_w, d_w) = (dot(&f, &w), dot(d, &w));
        let f_p = [0, 1, 2].map(|a| f[a] - w[a] * f_w);
        let d_p = [0, 1, 2].map(|a| d[a] - w[a] * d_w);
        let s = f32x4::from(self.slope);
        let r0 = f32x4::from(self.base_radius) + s * f_w;
        let a = dot(&d_p, &d_p) - s * s * d_w * d_w;
        let b = dot(&f_p, &d_p) - s * d_w * r0;
        let c = dot(&f_p, &f_p) - r0 * r0;
        let disc = b * b - a * c;
        // `disc >= 0` is false for a NaN, which the scalar test rejects too.
        let solvable = near_axis & t_c.is_finite() & disc.simd_ge(zero);
        if solvable.to_bitmask() == 0 {
            return (zero, zero, zero, 0);
        }
        // `copysign` of a non-negative (or −0) root: its magnitude with b's sign bit.
        let q = -(b + (disc.sqrt().abs() | (b & f32x4::splat(-0.0))));
        let (x0, x1) = (c / q, q / a);
        let t_max = f32x4::splat(t_max);
        let accept = |tau: f32x4| {
            let t = t_c + tau;
            let h = f_w + tau * d_w;
            let ok = t.simd_gt(zero) & t.simd_lt(t_max) & h.simd_ge(zero) & h.simd_le(length);
            (t, ok)
        };
        let (t0, ok0) = accept(min(x0, x1));
        let (t1, ok1) = accept(max(x0, x1));
        let t = ok0.bitselect(t0, t1);
        (t, zero, zero, (solvable & (ok0 | ok1)).to_bitmask())
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

    /// Cones and rays reaching every branch of the scalar test: quick rejections,
    /// lines near the axis that miss the finite cone, near and far walls, hits from
    /// inside, rays along the axis, grazing a generator, a zero direction (NaN), tiny
    /// far cylinders, rays across a rim (h exactly 0 or `length`) and `t_max` cutting
    /// between the two walls.
    fn cases() -> (Vec<ConeShape>, Vec<(Ray, f32)>) {
        let cones = vec![
            ConeShape::new(Vec3::new(0.0, 0.0, 4.0), 1.0, Vec3::new(0.0, 0.0, 6.0), 1.0),
            ConeShape::new(Vec3::new(-1.0, 0.0, 5.0), 0.5, Vec3::new(1.0, 0.0, 5.0), 0.0),
            ConeShape::new(Vec3::new(0.2, -0.3, 8.0), 2.0, Vec3::new(0.5, 1.0, 9.5), 0.7),
            ConeShape::new(
                Vec3::new(90.0, 50.0, 3000.0),
                0.001,
                Vec3::new(110.0, 50.0, 3000.0),
                0.001,
            ),
            ConeShape::new(Vec3::new(0.0, 0.0, -3.0), 1.0, Vec3::new(0.0, 0.0, -1.0), 2.0),
            ConeShape::new(Vec3::new(0.0, -2.0, 0.0), 1.5, Vec3::new(0.0, 2.0, 0.0), 1.5),
            ConeShape::new(Vec3::new(3.0, 3.0, 3.0), 0.2, Vec3::new(4.0, 4.0, 4.0), 0.2),
        ];
        let mut rays = Vec::new();
        for (o, d) in [
            (Vec3::ZERO, Vec3::new(0.0, 0.0, 1.0)),
            (Vec3::ZERO, Vec3::new(0.15, 0.0, 1.0)),
            (Vec3::ZERO, Vec3::new(0.02, -0.01, 1.0)),
            (Vec3::ZERO, Vec3::new(100.0, 50.0, 3000.0)),
            (Vec3::new(0.0, 0.0, 5.0), Vec3::new(0.3, 0.8, 0.1)),
            (Vec3::new(0.0, 0.0, 5.0), Vec3::new(0.0, 0.0, 1.0)),
            (Vec3::new(-4.0, 0.25, 5.0), Vec3::new(1.0, 0.0, 0.0)),
            (Vec3::new(0.0, 0.0, 1.0), Vec3::ZERO),
            (Vec3::new(0.0, 0.0, -10.0), Vec3::new(0.0, 0.1, 1.0)),
            (Vec3::new(0.0, 5.0, 0.5), Vec3::new(0.0, -1.0, 0.0)),
            (Vec3::new(5.0, 0.0, 0.0), Vec3::new(-1.0, 0.0, 0.0)),
            (Vec3::new(1.0, 3.0, 3.0), Vec3::new(1.0, 0.0, 0.3)),
            // Across the first cylinder's rims, exactly at h = length and h = 0.
            (Vec3::new(-5.0, 0.0, 6.0), Vec3::new(1.0, 0.0, 0.0)),
            (Vec3::new(-5.0, 0.5, 4.0), Vec3::new(1.0, 0.0, 0.0)),
        ] {
            for t_max in [f32::INFINITY, 5.5, 4.5, 0.5] {
                rays.push((Ray::new(o, d), t_max));
            }
        }
        (cones, rays)
    }

    #[test]
    fn each_lane_matches_the_scalar_test_bit_for_bit() {
        let (cones, rays) = cases();
        assert_blocks_match_scalar(&cones, &rays, Cone4::new, |c, ray, t_max| c.intersect(ray, t_max));
    }

    /// Many rays from a fixed pseudo-random sequence, aimed near the cones (so that
    /// most pass the quick rejection), against every block of the cases' cones: the
    /// distances agree bit for bit with the scalar test's.
    #[test]
    fn random_rays_match_the_scalar_test_bit_for_bit() {
        let (cones, _) = cases();
        let mut uniform = crate::accel::tests::uniform(0x2545_f491_4f6c_dd1d);
        let mut next = move || uniform() * 2.0 - 1.0;
        let mut hits = 0;
        for chunk in cones.chunks(LANES) {
            let lanes: Vec<(ConeShape, u32)> = chunk.iter().map(|c| (*c, 0)).collect();
            let block = Cone4::new(&lanes);
            for c in chunk {
                for _ in 0..500 {
                    let target = c.base + c.axis * (c.length * (0.5 + 0.7 * next()));
                    let origin = target + Vec3::new(next(), next(), next()) * 8.0;
                    let aim = target + Vec3::new(next(), next(), next()) * c.base_radius * 1.5;
                    let ray = Ray::new(origin, (aim - origin).normalize());
                    let ray4 = Ray4::new(&ray);
                    let (t, _, _, mask) = block.test(&ray4, f32::INFINITY);
                    for (lane, (cone, _)) in lanes.iter().enumerate() {
                        let expected = cone.intersect(&ray, f32::INFINITY).map(|h| h.t.to_bits());
                        let got = (mask & (1 << lane) != 0).then(|| t.to_array()[lane].to_bits());
                        assert_eq!(got, expected, "cone {lane}, ray {ray:?}");
                        hits += usize::from(expected.is_some());
                    }
                }
            }
        }
        assert!(hits > 1000, "only {hits} hits: too few to compare");
    }

    #[test]
    fn the_rays_reach_both_walls_and_misses() {
        // Guards the cases above against losing their point: hits on the near wall,
        // on the far wall (from inside, or past a cut-off near one), quick
        // rejections and misses after solving all occur.
        let (cones, rays) = cases();
        let (mut near, mut far, mut missed) = (0, 0, 0);
        for c in &cones {
            for (ray, t_max) in &rays {
                match c.intersect(ray, *t_max) {
                    None => missed += 1,
                    Some(h) => {
                        let p = ray.at(h.t) - c.base;
                        let out = p - c.axis * p.dot(c.axis);
                        if out.dot(ray.dir) < 0.0 {
                            near += 1
                        } else {
                            far += 1
                        }
                    }
                }
            }
        }
        assert!(near > 5 && far > 5 && missed > 5, "{near} {far} {missed}");
    }

    #[test]
    fn empty_lanes_are_never_hit() {
        let block = Cone4::new(&[]);
        let ray = Ray4::new(&Ray::new(Vec3::ZERO, Vec3::new(0.0, 0.0, 1.0)));
        assert_eq!(block.closest_hit(&ray, f32::INFINITY, &[]), None);
        assert!(!block.any_hit(&ray, f32::INFINITY));
    }

    #[test]
    #[should_panic(expected = "inside-only")]
    fn inside_only_cones_are_refused() {
        Cone4::new(&[(
            ConeShape::new(Vec3::ZERO, -1.0, Vec3::new(0.0, 0.0, 1.0), -1.0),
            0,
        )]);
    }
}
