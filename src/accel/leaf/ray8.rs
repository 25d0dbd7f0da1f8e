//! Eight rays in structure-of-arrays form, tested together against one triangle of a
//! [`Tri4`] block: the leaf test of a packet; and the eight triangles of two blocks
//! tested together against one ray ([`pair_hits`]).
//!
//! Each (ray, triangle) pair goes through exactly the arithmetic of the 4-lane
//! [`Tri4`] test (the generic [`watertight`], same operations in the same order, no
//! fused multiply-add), so hits, distances and barycentrics are bit-identical to
//! what the ray gets alone. Each ray sees the triangle in its own frame
//! ([`Sheared`]): the vertices' coordinates are permuted by the ray's axes, lane by
//! lane when the rays do not all share them (rare in a coherent packet).

use wide::f32x8;

use super::tri4::{Ray4, Tri4, LANES};
use crate::geometry::watertight::{watertight, Sheared};
use crate::math::Ray;

/// Rays per [`Ray8`].
pub const RAYS: usize = 8;

/// Up to eight rays, `[axis][ray]` (missing rays repeat the last one).
#[derive(Clone, Copy, Debug)]
pub struct Ray8 {
    /// Origins.
    pub origin: [[f32; RAYS]; 3],
    /// Directions.
    pub dir: [[f32; RAYS]; 3],
    /// Inverse directions (`Ray::inv_dir`).
    pub inv: [[f32; RAYS]; 3],
    /// Each ray's [`Sheared::origin`], `[axis][ray]`.
    pub sheared_origin: [[f32; RAYS]; 3],
    /// Each ray's [`Sheared::shear`], `[axis][ray]`.
    pub shear: [[f32; RAYS]; 3],
    /// Each ray's [`Sheared::axes`].
    pub axes: [[u8; 3]; RAYS],
    /// The axes, when all eight rays have the same.
    pub shared_axes: Option<[u8; 3]>,
}

impl Ray8 {
    /// Packs one to eight rays.
    #[inline(always)]
    pub fn new(rays: &[Ray]) -> Ray8 {
        let n = rays.len();
        assert!((1..=RAYS).contains(&n), "one to {RAYS} rays");
        let mut r = Ray8 {
            origin: [[0.0; RAYS]; 3],
            dir: [[0.0; RAYS]; 3],
            inv: [[0.0; RAYS]; 3],
            sheared_origin: [[0.0; RAYS]; 3],
            shear: [[0.0; RAYS]; 3],
            axes: [[0; 3]; RAYS],
            shared_axes: None,
        };
        let mut shared = true;
        for k in 0..RAYS {
            let ray = &rays[k.min(n - 1)];
            let sheared = Sheared::new(ray);
            for axis in 0..3 {
                r.origin[axis][k] = ray.origin[axis];
                r.dir[axis][k] = ray.dir[axis];
                r.inv[axis][k] = ray.inv_dir[axis];
                r.sheared_origin[axis][k] = sheared.origin[axis];
                r.shear[axis][k] = sheared.shear[axis];
            }
            r.axes[k] = sheared.axes;
            shared &= sheared.axes == r.axes[0];
        }
        r.shared_axes = shared.then_some(r.axes[0]);
        r
    }

    /// Lane `lane`'s vertices of `block`, each permuted by each ray's axes,
    /// `[vertex][axis][ray]` (for rays that do not share their axes).
    #[inline(always)]
    pub fn gather(&self, block: &Tri4, lane: usize) -> [[[f32; RAYS]; 3]; 3] {
        let mut out = [[[0.0; RAYS]; 3]; 3];
        for (vertex, v) in [&block.v0, &block.v1, &block.v2].into_iter().enumerate() {
            for k in 0..RAYS {
                for (j, &axis) in self.axes[k].iter().enumerate() {
                    out[vertex][j][k] = v[axis as usize][lane];
                }
            }
        }
        out
    }
}

/// What a triangle test of eight rays returns: per ray the distance and barycentrics,
/// and the rays that hit with `0 < t < limit` as bits.
pub type Hits8 = ([f32; RAYS], [f32; RAYS], [f32; RAYS], u32);

/// The watertight test on eight lanes, as arrays.
#[inline(always)]
fn test8(origin: &[f32x8; 3], shear: &[f32x8; 3], v: [[f32x8; 3]; 3], limit: f32x8) -> Hits8 {
    let (t, u, v, hit) = watertight(origin, shear, &v[0], &v[1], &v[2], limit);
    (t.to_array(), u.to_array(), v.to_array(), hit)
}

impl Tri4 {
    /// Lane `lane`'s triangle against the eight rays of `rays`, each below its own
    /// `limits[k]`, with the arithmetic of the 4-lane test (`Tri4::test`).
    #[inline(always)]
    pub fn hits8(&self, lane: usize, rays: &Ray8, limits: &[f32; RAYS]) -> Hits8 {
        debug_assert!(lane < LANES);
        let v = match rays.shared_axes {
            Some(axes) => {
                [&self.v0, &self.v1, &self.v2].map(|v| axes.map(|axis| f32x8::splat(v[axis as usize][lane])))
            }
            None => rays.gather(self, lane).map(|v| v.map(f32x8::from)),
        };
        test8(
            &rays.sheared_origin.map(f32x8::from),
            &rays.shear.map(f32x8::from),
            v,
            f32x8::from(*limits),
        )
    }
}

/// The eight triangles of two blocks (`first`'s four lanes, then `second`'s) against
/// one ray (`ray`, prepared) below `t_max`, with the arithmetic of the 4-lane test
/// (`Tri4::test`): one eight-lane test where a leaf holds five to eight triangles.
#[inline(always)]
pub fn pair_hits(first: &Tri4, second: &Tri4, ray: &Ray4, t_max: f32) -> Hits8 {
    let axes = ray.sheared.axes;
    let both = |a: &[[f32; LANES]; 3], b: &[[f32; LANES]; 3]| {
        axes.map(|axis| {
            let mut lanes = [0.0; RAYS];
            lanes[..LANES].copy_from_slice(&a[axis as usize]);
            lanes[LANES..].copy_from_slice(&b[axis as usize]);
            f32x8::from(lanes)
        })
    };
    test8(
        &ray.sheared.origin.map(f32x8::splat),
        &ray.sheared.shear.map(f32x8::splat),
        [
            both(&first.v0, &second.v0),
            both(&first.v1, &second.v1),
            both(&first.v2, &second.v2),
        ],
        f32x8::splat(t_max),
    )
}

#[cfg(test)]
pub(crate) mod tests {
    use super::*;
    use crate::geometry::Triangle;
    use crate::math::Vec3;

    /// Packets of rays, each with its rays' limits.
    pub(crate) type Packets = Vec<(Vec<Ray>, [f32; RAYS])>;

    /// Rays from around the origin towards +z against four triangles at various
    /// depths and sizes (one edge-on to some rays), several packets and limits.
    pub(crate) fn cases() -> (Tri4, [Triangle; 4], Packets) {
        let tris = [
            Triangle::new(
                Vec3::new(-1.0, -1.0, 3.0),
                Vec3::new(1.0, -1.0, 3.0),
                Vec3::new(0.0, 1.0, 3.0),
                Triangle::FLAT,
            ),
            Triangle::new(
                Vec3::new(-0.5, -0.5, 2.0),
                Vec3::new(0.5, -0.5, 2.5),
                Vec3::new(0.0, 0.5, 2.0),
                Triangle::FLAT,
            ),
            Triangle::new(
                Vec3::new(-4.0, -4.0, 5.0),
                Vec3::new(4.0, -4.0, 5.0),
                Vec3::new(0.0, 4.0, 5.0),
                Triangle::FLAT,
            ),
            Triangle::new(
                Vec3::new(0.0, -1.0, 1.0),
                Vec3::new(0.0, 1.0, 1.0),
                Vec3::new(0.0, 0.0, 4.0),
                Triangle::FLAT,
            ),
        ];
        let block = Tri4::new(&[(tris[0], 0), (tris[1], 1), (tris[2], 2), (tris[3], 3)]);
        let mut packets = Vec::new();
        for p in 0..60 {
            let rays: Vec<Ray> = (0..RAYS)
                .map(|k| {
                    let (x, y) = (
                        (k as f32 - 3.5) * 0.13 + p as f32 * 0.011,
                        (p % 9) as f32 * 0.2 - 0.8,
                    );
                    let o = Vec3::new(0.0, 0.0, -1.0 + (p % 3) as f32);
                    Ray::new(o, Vec3::new(x, y, 1.0).normalize())
                })
                .collect();
            let limits = std::array::from_fn(|k| [f32::INFINITY, 4.0, 2.2][(k + p) % 3]);
            packets.push((rays, limits));
        }
        // Packets whose rays differ in their largest direction component (x for
        // some, z for the others, both equal for one), so in their test frames.
        for p in 0..30 {
            let rays: Vec<Ray> = (0..RAYS)
                .map(|k| {
                    let x = match k {
                        7 => 1.0,
                        _ => (k as f32 - 3.5) * 0.3 + (p % 5) as f32 * 0.013,
                    };
                    let y = (p % 7) as f32 * 0.1 - 0.3;
                    let o = Vec3::new(0.01 * p as f32, 0.0, 1.8);
                    let d = Vec3::new(x, y, 1.0);
                    Ray::new(o, if p % 2 == 0 { d } else { d.normalize() })
                })
                .collect();
            let limits = std::array::from_fn(|k| [f32::INFINITY, 4.0, 2.2][(k + p) % 3]);
            packets.push((rays, limits));
        }
        (block, tris, packets)
    }

    #[test]
    fn each_ray_gets_the_scalar_test_bit_for_bit() {
        let (block, tris, packets) = cases();
        let (mut hits, mut mixed) = (0, 0);
        for (rays, limits) in &packets {
            let rays8 = Ray8::new(rays);
            mixed += usize::from(rays8.shared_axes.is_none());
            for (lane, tri) in tris.iter().enumerate() {
                let (t, u, v, mask) = block.hits8(lane, &rays8, limits);
                for (k, r) in rays.iter().enumerate() {
                    let want = tri.intersect(r, limits[k]);
                    assert_eq!(mask & (1 << k) != 0, want.is_some(), "lane {lane} ray {k}");
                    if let Some(h) = want {
                        assert_eq!(
                            (t[k].to_bits(), u[k].to_bits(), v[k].to_bits()),
                            (h.t.to_bits(), h.u.to_bits(), h.v.to_bits())
                        );
                        hits += 1;
                    }
                }
            }
        }
        assert!(hits > 100, "{hits} hits: too few to test the lanes");
        assert!(mixed >= 20, "{mixed} packets of rays with different axes");
    }

    /// One triangle against eight rays and two blocks against one ray, where an edge
    /// function rounds to zero: the `f64` recomputation in the lanes that need it
    /// (see `tri4`'s test of the same).
    #[test]
    fn eight_lanes_recompute_edge_functions_rounded_to_zero() {
        let (ray, hit, missed) = crate::geometry::triangle::tests::split_by_a_near_edge();
        let block = Tri4::new(&[(missed, 0), (hit, 1)]);
        let other = Ray::new(Vec3::new(0.1, -0.3, 0.0), Vec3::new(0.0, 0.0, 1.0));
        let rays = [ray, other, ray, ray, other, ray, ray, other];
        let rays8 = Ray8::new(&rays);
        let limits = [f32::INFINITY; RAYS];
        assert_eq!(block.hits8(0, &rays8, &limits).3, 0b1001_0010);
        assert_eq!(block.hits8(1, &rays8, &limits).3, 0b0110_1101);
        let (t, _, _, mask) = pair_hits(&block, &block, &Ray4::new(&ray), f32::INFINITY);
        assert_eq!(mask, 0b0010_0010);
        assert_eq!(t[1], hit.intersect(&ray, f32::INFINITY).unwrap().t);
    }

    /// The second block of [`pair_hits`]: the first one's triangles in reverse order,
    /// three of them (one empty lane).
    pub(crate) fn second_block(tris: &[Triangle; 4]) -> Tri4 {
        Tri4::new(&[(tris[3], 4), (tris[2], 5), (tris[1], 6)])
    }

    #[test]
    fn pair_lanes_get_the_scalar_test_bit_for_bit() {
        let (first, tris, packets) = cases();
        let second = second_block(&tris);
        let lanes = [tris[0], tris[1], tris[2], tris[3], tris[3], tris[2], tris[1]];
        let mut hits = 0;
        for (rays, limits) in &packets {
            for (r, &t_max) in rays.iter().zip(limits) {
                let (t, u, v, mask) = pair_hits(&first, &second, &Ray4::new(r), t_max);
                assert_eq!(mask & 0x80, 0, "the empty lane is never hit");
                for (lane, tri) in lanes.iter().enumerate() {
                    let want = tri.intersect(r, t_max);
                    assert_eq!(mask & (1 << lane) != 0, want.is_some(), "lane {lane}");
                    if let Some(h) = want {
                        assert_eq!(
                            (t[lane].to_bits(), u[lane].to_bits(), v[lane].to_bits()),
                            (h.t.to_bits(), h.u.to_bits(), h.v.to_bits())
                        );
                        hits += 1;
                    }
                }
            }
        }
        assert!(hits > 100, "{hits} hits: too few to test the lanes");
    }
}
