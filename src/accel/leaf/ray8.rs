//! Eight rays in structure-of-arrays form, tested together against one triangle of a
//! [`Tri4`] block: the leaf test of a packet; and the eight triangles of two blocks
//! tested together against one ray ([`pair_hits`]). Rays made eight at a time (the
//! camera's, an area light's points seen from one hit) are set lane by lane
//! ([`RayLanes`]) and become a packet without passing through single rays.
//!
//! Each (ray, triangle) pair goes through exactly the arithmetic of the 4-lane
//! [`Tri4`] test (the generic [`watertight`], same operations in the same order, no
//! fused multiply-add), so hits, distances and barycentrics are bit-identical to
//! what the ray gets alone. Each ray sees the triangle in its own frame
//! ([`Sheared`]): the vertices' coordinates are permuted by the ray's axes, lane by
//! lane when the rays do not all share them (rare in a coherent packet).

use wide::f32x8;

use super::tri4::{Ray4, Tri4, LANES};
use crate::geometry::watertight::{watertight, watertight_exact, Axis, Sheared};
use crate::math::{safe_recip, Ray, Vec3};

/// Rays per [`Ray8`].
pub const RAYS: usize = 8;

/// Rays made lane by lane, one array per coordinate, before they become a [`Ray8`]:
/// rays made eight at a time (a camera's, the shadow rays of a packet's hits) need
/// not be made one by one and then transposed.
#[derive(Clone, Copy, Debug, Default)]
pub struct RayLanes {
    origin: [[f32; RAYS]; 3],
    dir: [[f32; RAYS]; 3],
    inv: [[f32; RAYS]; 3],
    time: [f32; RAYS],
}

impl RayLanes {
    /// Sets ray `k` from `origin` along `dir` at `time`, its inverse direction as
    /// [`Ray::with_time`] works it out.
    #[inline(always)]
    pub fn set(&mut self, k: usize, origin: Vec3, dir: Vec3, time: f32) {
        let (o, d) = (origin.to_array(), dir.to_array());
        for axis in 0..3 {
            self.origin[axis][k] = o[axis];
            self.dir[axis][k] = d[axis];
            self.inv[axis][k] = safe_recip(d[axis]);
        }
        self.time[k] = time;
    }

    /// Sets ray `k` to `ray`, field for field.
    #[inline(always)]
    pub fn set_ray(&mut self, k: usize, ray: &Ray) {
        let (o, d, inv) = (ray.origin.to_array(), ray.dir.to_array(), ray.inv_dir.to_array());
        for axis in 0..3 {
            self.origin[axis][k] = o[axis];
            self.dir[axis][k] = d[axis];
            self.inv[axis][k] = inv[axis];
        }
        self.time[k] = ray.time;
    }

    /// Ray `k` as it was set.
    #[inline(always)]
    pub fn ray(&self, k: usize) -> Ray {
        lane_ray(&self.origin, &self.dir, &self.inv, &self.time, k)
    }

    /// The packet of the first `n` rays (one to eight; the rays past `n` repeat ray
    /// `n - 1`).
    #[inline(always)]
    pub fn packet(mut self, n: usize) -> Ray8 {
        assert!((1..=RAYS).contains(&n), "one to {RAYS} rays");
        for k in n..RAYS {
            for axis in 0..3 {
                self.origin[axis][k] = self.origin[axis][n - 1];
                self.dir[axis][k] = self.dir[axis][n - 1];
                self.inv[axis][k] = self.inv[axis][n - 1];
            }
            self.time[k] = self.time[n - 1];
        }
        let mut r = Ray8 {
            origin: self.origin,
            dir: self.dir,
            inv: self.inv,
            sheared_origin: [[0.0; RAYS]; 3],
            shear: [[0.0; RAYS]; 3],
            axes: [[Axis::X; 3]; RAYS],
            picks: [[[0.0; RAYS]; 2]; 3],
            shared_axes: None,
            time: self.time,
        };
        r.shear_all();
        r
    }
}

/// Ray `k` of lanes `[axis][ray]`.
#[inline(always)]
fn lane_ray(
    origin: &[[f32; RAYS]; 3],
    dir: &[[f32; RAYS]; 3],
    inv: &[[f32; RAYS]; 3],
    time: &[f32; RAYS],
    k: usize,
) -> Ray {
    let lane = |a: &[[f32; RAYS]; 3]| Vec3::new(a[0][k], a[1][k], a[2][k]);
    Ray {
        origin: lane(origin),
        dir: lane(dir),
        inv_dir: lane(inv),
        time: time[k],
    }
}

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
    pub axes: [[Axis; 3]; RAYS],
    /// The same axes as lane masks, per frame axis `[j]` the rays whose axis `j` is
    /// world `x` (`[j][0]`, all ones) or `y` (`[j][1]`); the others' is `z`. They
    /// permute a vertex for every ray at once ([`Ray8::gather`]).
    pub picks: [[[f32; RAYS]; 2]; 3],
    /// The axes, when all eight rays have the same.
    pub shared_axes: Option<[Axis; 3]>,
    /// Times (`Ray::time`).
    pub time: [f32; RAYS],
}

impl Ray8 {
    /// Packs one to eight rays.
    #[inline(always)]
    pub fn new(rays: &[Ray]) -> Ray8 {
        let mut lanes = RayLanes::default();
        for (k, ray) in rays.iter().take(RAYS).enumerate() {
            lanes.set_ray(k, ray);
        }
        lanes.packet(rays.len())
    }

    /// Each ray's frame, as [`Sheared::new`] makes it (the same selections and
    /// products), eight rays at a time: `sheared_origin`, `shear`, `axes` and
    /// `shared_axes` from `origin`, `dir` and `inv`.
    #[inline(always)]
    fn shear_all(&mut self) {
        let rows = |a: &[[f32; RAYS]; 3]| [f32x8::from(a[0]), f32x8::from(a[1]), f32x8::from(a[2])];
        let (o, d, inv) = (rows(&self.origin), rows(&self.dir), rows(&self.inv));
        let a = d.map(f32x8::abs);
        let zero = f32x8::ZERO;
        // `kz` as `Vec3::dominant_axis` picks it, and the sign along it.
        let z_is_x = a[0].simd_ge(a[1]) & a[0].simd_ge(a[2]);
        let z_is_y = !z_is_x & a[1].simd_ge(a[2]);
        let z_is_z = !(z_is_x | z_is_y);
        let negative =
            (z_is_x & d[0].simd_lt(zero)) | (z_is_y & d[1].simd_lt(zero)) | (z_is_z & d[2].simd_lt(zero));
        let positive = !negative;
        // `kx` and `ky` from `Sheared::AXES`.
        let x_is_x = (z_is_y & negative) | (z_is_z & positive);
        let x_is_y = (z_is_x & positive) | (z_is_z & negative);
        let y_is_x = (z_is_y & positive) | (z_is_z & negative);
        let y_is_y = (z_is_x & negative) | (z_is_z & positive);
        let pick =
            |v: &[f32x8; 3], is_x: f32x8, is_y: f32x8| is_x.bitselect(v[0], is_y.bitselect(v[1], v[2]));
        let sz = pick(&inv, z_is_x, z_is_y);
        self.sheared_origin = [
            pick(&o, x_is_x, x_is_y).to_array(),
            pick(&o, y_is_x, y_is_y).to_array(),
            pick(&o, z_is_x, z_is_y).to_array(),
        ];
        self.shear = [
            (pick(&d, x_is_x, x_is_y) * sz).to_array(),
            (pick(&d, y_is_x, y_is_y) * sz).to_array(),
            sz.to_array(),
        ];
        self.picks = [
            [x_is_x.to_array(), x_is_y.to_array()],
            [y_is_x.to_array(), y_is_y.to_array()],
            [z_is_x.to_array(), z_is_y.to_array()],
        ];
        let (is_x, is_y, neg) = (z_is_x.to_bitmask(), z_is_y.to_bitmask(), negative.to_bitmask());
        for (k, axes) in self.axes.iter_mut().enumerate() {
            let kz = if is_x >> k & 1 != 0 {
                0
            } else {
                2 - (is_y >> k & 1) as usize
            };
            *axes = Sheared::AXES[2 * kz + (neg >> k & 1) as usize];
        }
        let uniform = |bits: u32| bits == 0 || bits == (1 << RAYS) - 1;
        self.shared_axes = (uniform(is_x) && uniform(is_y) && uniform(neg)).then_some(self.axes[0]);
    }

    /// Ray `k` as it was packed (the very same fields).
    #[inline(always)]
    pub fn ray(&self, k: usize) -> Ray {
        lane_ray(&self.origin, &self.dir, &self.inv, &self.time, k)
    }

    /// Ray `k`'s frame.
    #[inline(always)]
    pub fn sheared(&self, k: usize) -> Sheared {
        let lane = |a: &[[f32; RAYS]; 3]| [a[0][k], a[1][k], a[2][k]];
        Sheared {
            axes: self.axes[k],
            origin: lane(&self.sheared_origin),
            shear: lane(&self.shear),
        }
    }

    /// Lane `lane`'s vertices of `block`, each permuted by each ray's axes,
    /// `[vertex][axis]` eight rays wide (for rays that do not share their axes): per
    /// frame axis the vertex's world coordinate that [`Ray8::picks`] selects.
    #[inline(always)]
    pub fn gather(&self, block: &Tri4, lane: usize) -> [[f32x8; 3]; 3] {
        let masks = self
            .picks
            .map(|[is_x, is_y]| (f32x8::from(is_x), f32x8::from(is_y)));
        [&block.v0, &block.v1, &block.v2].map(|v| {
            let [x, y, z] = [0, 1, 2].map(|axis| f32x8::splat(v[axis][lane]));
            masks.map(|(is_x, is_y)| is_x.bitselect(x, is_y.bitselect(y, z)))
        })
    }
}

/// What a triangle test of eight rays returns: per ray the distance and barycentrics,
/// and the rays that hit with `0 < t < limit` as bits.
pub type Hits8 = ([f32; RAYS], [f32; RAYS], [f32; RAYS], u32);

/// A result of the eight-lane test as arrays.
#[inline(always)]
fn arrays((t, u, v, hit): (f32x8, f32x8, f32x8, u32)) -> Hits8 {
    (t.to_array(), u.to_array(), v.to_array(), hit)
}

/// The inputs of the eight-lane test: the rays' origins and shears in their
/// frames, the vertices, the limits.
type Inputs8 = ([f32x8; 3], [f32x8; 3], [[f32x8; 3]; 3], f32x8);

impl Tri4 {
    /// Lane `lane`'s triangle against the eight rays of `rays`, each below its own
    /// `limits[k]`, with the arithmetic of the 4-lane test (`Tri4::test`).
    #[inline(always)]
    pub fn hits8(&self, lane: usize, rays: &Ray8, limits: &[f32; RAYS]) -> Hits8 {
        debug_assert!(lane < LANES);
        let Some([kx, ky, kz]) = rays.shared_axes else {
            return self.hits8_gathered(lane, rays, limits, false);
        };
        let [kx, ky, kz] = [kx as usize, ky as usize, kz as usize];
        let vertex = |v: &[[f32; LANES]; 3]| {
            [
                f32x8::splat(v[kx][lane]),
                f32x8::splat(v[ky][lane]),
                f32x8::splat(v[kz][lane]),
            ]
        };
        let (origin, shear) = (rows(&rays.sheared_origin), rows(&rays.shear));
        let [v0, v1, v2] = [vertex(&self.v0), vertex(&self.v1), vertex(&self.v2)];
        match watertight(&origin, &shear, &v0, &v1, &v2, f32x8::from(*limits)) {
            Some(found) => arrays(found),
            None => self.hits8_gathered(lane, rays, limits, true),
        }
    }

    /// [`Tri4::hits8`] for rays that do not share their axes (the vertices gathered
    /// lane by lane, [`Ray8::gather`]), or with `exact` when an edge function came
    /// out zero (see `watertight_exact`).
    #[cold]
    #[inline(never)]
    fn hits8_gathered(&self, lane: usize, rays: &Ray8, limits: &[f32; RAYS], exact: bool) -> Hits8 {
        let (origin, shear) = (rows(&rays.sheared_origin), rows(&rays.shear));
        let [v0, v1, v2] = rays.gather(self, lane);
        let limit = f32x8::from(*limits);
        if !exact {
            if let Some(found) = watertight(&origin, &shear, &v0, &v1, &v2, limit) {
                return arrays(found);
            }
        }
        arrays(watertight_exact(&origin, &shear, &v0, &v1, &v2, limit))
    }
}

/// Rows of eight lanes as vectors.
#[inline(always)]
fn rows(a: &[[f32; RAYS]; 3]) -> [f32x8; 3] {
    [f32x8::from(a[0]), f32x8::from(a[1]), f32x8::from(a[2])]
}

/// The eight triangles of two blocks (`first`'s four lanes, then `second`'s) against
/// one ray (`ray`, prepared) below `t_max`, with the arithmetic of the 4-lane test
/// (`Tri4::test`): one eight-lane test where a leaf holds five to eight triangles.
#[inline(always)]
pub fn pair_hits(first: &Tri4, second: &Tri4, ray: &Ray4, t_max: f32) -> Hits8 {
    let (origin, shear, [v0, v1, v2], limit) = pair_inputs(first, second, ray, t_max);
    match watertight(&origin, &shear, &v0, &v1, &v2, limit) {
        Some(found) => arrays(found),
        None => pair_hits_exact(first, second, ray, t_max),
    }
}

/// [`pair_hits`] when an edge function came out zero (see `watertight_exact`).
#[cold]
#[inline(never)]
fn pair_hits_exact(first: &Tri4, second: &Tri4, ray: &Ray4, t_max: f32) -> Hits8 {
    let (origin, shear, [v0, v1, v2], limit) = pair_inputs(first, second, ray, t_max);
    arrays(watertight_exact(&origin, &shear, &v0, &v1, &v2, limit))
}

/// The inputs of [`pair_hits`].
#[inline(always)]
fn pair_inputs(first: &Tri4, second: &Tri4, ray: &Ray4, t_max: f32) -> Inputs8 {
    let s = &ray.sheared;
    let [kx, ky, kz] = [s.axes[0] as usize, s.axes[1] as usize, s.axes[2] as usize];
    let row = |a: &[f32; LANES], b: &[f32; LANES]| {
        let mut lanes = [0.0; RAYS];
        lanes[..LANES].copy_from_slice(a);
        lanes[LANES..].copy_from_slice(b);
        f32x8::from(lanes)
    };
    let both = |a: &[[f32; LANES]; 3], b: &[[f32; LANES]; 3]| {
        [row(&a[kx], &b[kx]), row(&a[ky], &b[ky]), row(&a[kz], &b[kz])]
    };
    let splat = |a: &[f32; 3]| [f32x8::splat(a[0]), f32x8::splat(a[1]), f32x8::splat(a[2])];
    (
        splat(&s.origin),
        splat(&s.shear),
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

    /// The eight rays' frames are the ones `Sheared::new` makes, for directions of
    /// every dominant axis and sign, ties between components and zeros of both signs.
    #[test]
    fn the_frames_of_eight_rays_are_each_rays_own() {
        let mut rnd = crate::accel::tests::uniform(0x7f4a_7c15);
        let pick = |r: f32| [-1.0, -0.5, -0.0, 0.0, 0.5, 1.0, 2.0, -2.0][(r * 8.0) as usize % 8];
        for p in 0..2000 {
            let rays: Vec<Ray> = (0..RAYS)
                .map(|_| {
                    let d = if p % 2 == 0 {
                        Vec3::new(pick(rnd()), pick(rnd()), pick(rnd()))
                    } else {
                        Vec3::new(rnd() - 0.5, rnd() - 0.5, rnd() - 0.5)
                    };
                    let d = if d == Vec3::ZERO {
                        Vec3::new(0.0, 0.0, 1.0)
                    } else {
                        d
                    };
                    Ray::new(Vec3::new(rnd(), rnd() * 3.0, -rnd()), d)
                })
                .collect();
            let n = 1 + p % RAYS;
            let r = Ray8::new(&rays[..n]);
            for k in 0..RAYS {
                assert_eq!(
                    r.sheared(k),
                    Sheared::new(&rays[k.min(n - 1)]),
                    "packet {p} ray {k}"
                );
            }
            let all = (0..RAYS).all(|k| r.axes[k] == r.axes[0]);
            assert_eq!(r.shared_axes, all.then_some(r.axes[0]));
        }
    }

    /// Rays set lane by lane from an origin, a direction and a time are, field for
    /// field, the rays `Ray::with_time` makes (zero and tiny direction components
    /// included, whose inverses are clamped), and their packet pads with the last.
    #[test]
    fn rays_set_in_lanes_are_the_rays_made_one_by_one() {
        let mut rnd = crate::accel::tests::uniform(0x51ed_270b);
        let pick = |r: f32| [-1.0, -0.0, 0.0, 1e-31, -1e-31, 0.3, 2.0, -2.5][(r * 8.0) as usize % 8];
        let bits = |r: &Ray| {
            let v = [r.origin, r.dir, r.inv_dir].map(|v| v.to_array().map(f32::to_bits));
            (v, r.time.to_bits())
        };
        for p in 0..500 {
            let n = 1 + p % RAYS;
            let mut lanes = RayLanes::default();
            let mut made = Vec::new();
            for k in 0..n {
                let o = Vec3::new(rnd() * 4.0 - 2.0, rnd(), -rnd());
                let d = if p % 2 == 0 {
                    Vec3::new(pick(rnd()), pick(rnd()), pick(rnd()))
                } else {
                    Vec3::new(rnd() - 0.5, rnd() - 0.5, rnd() - 0.5)
                };
                let t = rnd();
                lanes.set(k, o, d, t);
                made.push(Ray::with_time(o, d, t));
                assert_eq!(bits(&lanes.ray(k)), bits(&made[k]), "packet {p} ray {k}");
            }
            let packet = lanes.packet(n);
            for k in 0..RAYS {
                let ray = &made[k.min(n - 1)];
                assert_eq!(bits(&packet.ray(k)), bits(ray), "packet {p} lane {k}");
                assert_eq!(packet.sheared(k), Sheared::new(ray), "packet {p} lane {k}");
            }
        }
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
