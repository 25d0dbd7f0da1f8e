//! The watertight ray/triangle test of Woop, Benthin and Wald ("Watertight
//! Ray/Triangle Intersection", JCGT 2(1), 2013), written once over lanes: the scalar
//! [`Triangle::intersect`](super::Triangle::intersect) runs it on `f32`, the BVH's
//! leaf blocks on `f32x4` and `f32x8` (four or eight triangles against a ray, one
//! triangle against eight rays), each lane with exactly the scalar operations in the
//! scalar order (Rust contracts no multiply-add), so every path gives the same hits,
//! distances and barycentrics, bit for bit. (`accel::traverse::avx` repeats the
//! function in AVX registers, operation for operation.)
//!
//! The test moves the triangle into the ray's frame: the origin to zero, the axes
//! permuted so that the direction's largest component is the third ([`Sheared`]),
//! then sheared so that the direction becomes the third axis. The ray meets the
//! triangle where the three edge functions (the signed areas, in the sheared `xy`
//! plane, of the origin with each edge) share a sign; zero is on the edge and counts
//! (two-sided, inclusive). An edge function depends only on the edge's two vertices
//! and the ray, and swapping the vertices negates it exactly, so two triangles
//! sharing an edge (with the very same floats for its vertices: triangles keep their
//! vertices, not an edge computed from another vertex) see the ray on the two sides
//! of it consistently: a ray never slips between them. Möller and Trumbore's test,
//! used before, holds that only in exact arithmetic.
//!
//! An edge function that comes out exactly zero may be a rounded-off small value; it
//! is recomputed in `f64`, where the products of `f32` values are exact and the one
//! rounding of their difference keeps its sign. The paper recomputes all three
//! functions when one is zero; only the zero ones are recomputed here, so that an
//! edge's value stays a function of the edge and the ray alone (a triangle whose
//! other edge was zero would otherwise see a shared edge in `f64` and its neighbour
//! in `f32`, possibly with opposite signs). Lanes with a zero go through the same
//! scalar recomputation (`exact_lanes`, from `watertight_exact`).

use std::ops::{Add, BitAnd, BitOr, Div, Mul, Sub};

use wide::{f32x4, f32x8};

use crate::math::{lanes, Ray, Vec3};

/// A coordinate axis (an index into a point's coordinates that needs no bounds
/// check).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[repr(u8)]
pub enum Axis {
    /// The first coordinate.
    X = 0,
    /// The second.
    Y = 1,
    /// The third.
    Z = 2,
}

/// A ray in the test's frame: the axes `kx, ky, kz` (`kz` the direction's largest
/// component in magnitude, `kx, ky` the next two cyclically, swapped when the
/// direction along `kz` is negative, which keeps the triangles' winding), the origin's
/// coordinates on them, and the shear `(dx/dz, dy/dz, 1/dz)`, computed as
/// `(dx·Sz, dy·Sz, Sz)` with `Sz` the ray's `inv_dir` along `kz` (no division).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Sheared {
    /// `[kx, ky, kz]`.
    pub axes: [Axis; 3],
    /// The origin's coordinates along `axes`.
    pub origin: [f32; 3],
    /// `[Sx, Sy, Sz]` along `axes`.
    pub shear: [f32; 3],
}

impl Sheared {
    /// `[kx, ky, kz]` by `2 kz + (direction along kz < 0)` (and two unused rows,
    /// for an index masked to three bits).
    pub const AXES: [[Axis; 3]; 8] = {
        use Axis::{X, Y, Z};
        [
            [Y, Z, X],
            [Z, Y, X],
            [Z, X, Y],
            [X, Z, Y],
            [X, Y, Z],
            [Y, X, Z],
            [Y, Z, X],
            [Y, Z, X],
        ]
    };

    /// Prepares `ray` (a zero direction gives no hits). Without a branch: the axes of
    /// random rays would be a branch mispredicted at every other query.
    #[inline(always)]
    pub fn new(ray: &Ray) -> Sheared {
        // (Arrays of four, indexed by an axis masked to two bits: no bounds checks.)
        let four = |v: Vec3| [v.x, v.y, v.z, 0.0];
        let (o, d, inv) = (four(ray.origin), four(ray.dir), four(ray.inv_dir));
        let a = ray.dir.abs();
        // `Vec3::dominant_axis`: x unless y or z is larger, then y unless z is larger.
        let not_x = !(a.x >= a.y && a.x >= a.z);
        let y_over_z = a.y >= a.z;
        let kz = usize::from(not_x) * (2 - usize::from(y_over_z));
        let signs = usize::from(d[0] < 0.0) | usize::from(d[1] < 0.0) << 1 | usize::from(d[2] < 0.0) << 2;
        let axes = Self::AXES[(2 * kz + (signs >> kz & 1)) & 7];
        let [kx, ky, kz] = axes.map(|axis| axis as usize & 3);
        // `1 / dz` (`dz`, the largest component, is below `TINY_DIR` only for a
        // direction of next to nothing).
        let sz = inv[kz];
        Sheared {
            axes,
            origin: [o[kx], o[ky], o[kz]],
            shear: [d[kx] * sz, d[ky] * sz, sz],
        }
    }

    /// `p`'s coordinates (or rows of lanes) in the order of [`Sheared::axes`].
    #[inline(always)]
    pub fn permute<X: Copy>(&self, p: &[X; 3]) -> [X; 3] {
        self.axes.map(|axis| p[axis as usize])
    }
}

/// What the test needs of its lanes: IEEE arithmetic, comparisons giving masks,
/// `minps`-like min and max, and the lanes as an array.
pub(crate) trait Lanes:
    Copy + Add<Output = Self> + Sub<Output = Self> + Mul<Output = Self> + Div<Output = Self>
{
    /// A comparison's result per lane.
    type Mask: Copy + BitAnd<Output = Self::Mask> + BitOr<Output = Self::Mask>;
    /// The lanes as an array.
    type Array: AsRef<[f32]> + AsMut<[f32]>;
    /// Zero in every lane.
    const ZERO: Self;
    /// One in every lane.
    const ONE: Self;
    /// `self == rhs` (false on NaN).
    fn eq(self, rhs: Self) -> Self::Mask;
    /// `self >= rhs` (false on NaN).
    fn ge(self, rhs: Self) -> Self::Mask;
    /// `self <= rhs` (false on NaN).
    fn le(self, rhs: Self) -> Self::Mask;
    /// `self > rhs` (false on NaN).
    fn gt(self, rhs: Self) -> Self::Mask;
    /// `self < rhs` (false on NaN).
    fn lt(self, rhs: Self) -> Self::Mask;
    /// `self < rhs ? self : rhs`, as `minps`.
    fn min(self, rhs: Self) -> Self;
    /// `self > rhs ? self : rhs`, as `maxps`.
    fn max(self, rhs: Self) -> Self;
    /// A mask's lanes as bits.
    fn bits(mask: Self::Mask) -> u32;
    /// The lanes.
    fn to_lanes(self) -> Self::Array;
    /// Lanes back into a vector.
    fn from_lanes(lanes: Self::Array) -> Self;
}

impl Lanes for f32 {
    type Mask = bool;
    type Array = [f32; 1];
    const ZERO: Self = 0.0;
    const ONE: Self = 1.0;
    #[inline(always)]
    fn eq(self, rhs: Self) -> bool {
        self == rhs
    }
    #[inline(always)]
    fn ge(self, rhs: Self) -> bool {
        self >= rhs
    }
    #[inline(always)]
    fn le(self, rhs: Self) -> bool {
        self <= rhs
    }
    #[inline(always)]
    fn gt(self, rhs: Self) -> bool {
        self > rhs
    }
    #[inline(always)]
    fn lt(self, rhs: Self) -> bool {
        self < rhs
    }
    #[inline(always)]
    fn min(self, rhs: Self) -> Self {
        if self < rhs {
            self
        } else {
            rhs
        }
    }
    #[inline(always)]
    fn max(self, rhs: Self) -> Self {
        if self > rhs {
            self
        } else {
            rhs
        }
    }
    #[inline(always)]
    fn bits(mask: bool) -> u32 {
        u32::from(mask)
    }
    #[inline(always)]
    fn to_lanes(self) -> [f32; 1] {
        [self]
    }
    #[inline(always)]
    fn from_lanes(lanes: [f32; 1]) -> Self {
        lanes[0]
    }
}

macro_rules! simd_lanes {
    ($t:ty, $n:expr) => {
        impl Lanes for $t {
            type Mask = $t;
            type Array = [f32; $n];
            const ZERO: Self = <$t>::ZERO;
            const ONE: Self = <$t>::ONE;
            #[inline(always)]
            fn eq(self, rhs: Self) -> Self {
                self.simd_eq(rhs)
            }
            #[inline(always)]
            fn ge(self, rhs: Self) -> Self {
                self.simd_ge(rhs)
            }
            #[inline(always)]
            fn le(self, rhs: Self) -> Self {
                self.simd_le(rhs)
            }
            #[inline(always)]
            fn gt(self, rhs: Self) -> Self {
                self.simd_gt(rhs)
            }
            #[inline(always)]
            fn lt(self, rhs: Self) -> Self {
                self.simd_lt(rhs)
            }
            #[inline(always)]
            fn min(self, rhs: Self) -> Self {
                self.fast_min(rhs)
            }
            #[inline(always)]
            fn max(self, rhs: Self) -> Self {
                self.fast_max(rhs)
            }
            #[inline(always)]
            fn bits(mask: Self) -> u32 {
                mask.to_bitmask()
            }
            #[inline(always)]
            fn to_lanes(self) -> [f32; $n] {
                self.to_array()
            }
            #[inline(always)]
            fn from_lanes(lanes: [f32; $n]) -> Self {
                <$t>::from(lanes)
            }
        }
    };
}

simd_lanes!(f32x4, 4);
simd_lanes!(f32x8, 8);

/// The triangle in the ray's frame: its vertices relative to the origin and sheared,
/// `[ax, ay, bx, by, cx, cy]`, and their distances along the third axis (not yet
/// scaled by `Sz`), `[az, bz, cz]`.
#[inline(always)]
fn frame<T: Lanes>(origin: &[T; 3], shear: &[T; 3], [v0, v1, v2]: [&[T; 3]; 3]) -> ([T; 6], [T; 3]) {
    let [sx, sy, _] = *shear;
    let [ox, oy, oz] = *origin;
    let (ax, ay, az) = (v0[0] - ox, v0[1] - oy, v0[2] - oz);
    let (bx, by, bz) = (v1[0] - ox, v1[1] - oy, v1[2] - oz);
    let (cx, cy, cz) = (v2[0] - ox, v2[1] - oy, v2[2] - oz);
    (
        [
            ax - sx * az,
            ay - sy * az,
            bx - sx * bz,
            by - sy * bz,
            cx - sx * cz,
            cy - sy * cz,
        ],
        [az, bz, cz],
    )
}

/// The edge functions opposite `v0`, `v1` and `v2`, each `qx·py − qy·px` for the
/// edge from `p` to `q` (the next two vertices).
#[inline(always)]
fn edges<T: Lanes>([ax, ay, bx, by, cx, cy]: [T; 6]) -> [T; 3] {
    [cx * by - cy * bx, ax * cy - ay * cx, bx * ay - by * ax]
}

/// The lanes (as bits) where an edge function is zero and the others share a sign
/// or are zero too: there a zero's exact sign may decide (where two others have
/// opposite signs, the ray misses whatever it is). The least times the greatest is
/// zero there (or underflows to zero: a recomputation with nothing to do).
#[inline(always)]
fn zero_edge<T: Lanes>([e0, e1, e2]: [T; 3]) -> u32 {
    T::bits((e0.min(e1).min(e2) * e0.max(e1).max(e2)).eq(T::ZERO))
}

/// The rest of the test from the edge functions `e`, the distances `z` and `Sz`.
#[inline(always)]
fn finish<T: Lanes>([e0, e1, e2]: [T; 3], [az, bz, cz]: [T; 3], sz: T, limit: T) -> (T, T, T, u32) {
    let det = e0 + e1 + e2;
    let t_unscaled = e0 * az + e1 * bz + e2 * cz;
    let inv_det = T::ONE / det;
    let t = t_unscaled * (sz * inv_det);
    // One sign for the three (zero counts as either) and the distance within
    // bounds. Comparisons with a NaN are false, and a NaN anywhere (an empty lane)
    // makes `t` NaN: no hit. A triangle seen edge-on (or degenerate) needs no test of
    // its own: with one sign, `det = 0` only when all three are zero, and then `t` is
    // `0 · ∞`, NaN.
    let same_sign = e0.min(e1).min(e2).ge(T::ZERO) | e0.max(e1).max(e2).le(T::ZERO);
    let ok = same_sign & t.gt(T::ZERO) & t.lt(limit);
    (t, e1 * inv_det, e2 * inv_det, T::bits(ok))
}

/// The test on lanes of (ray, triangle) pairs: `origin` and `shear` the rays'
/// [`Sheared::origin`] and [`Sheared::shear`], `v0, v1, v2` the vertices permuted
/// by the rays' [`Sheared::axes`]. Returns per lane the distance `t` and the
/// barycentrics `u` (weight of `v1`) and `v` (weight of `v2`), and the lanes hit with
/// `0 < t < limit` as bits (read `t`, `u`, `v` only there); or `None` when an edge
/// function came out zero where its sign may matter: the caller then runs
/// [`watertight_exact`] on the same lanes, from a function of its own kept out of
/// line (`#[cold]`), which takes the inputs from where they are in memory (were the
/// recomputation a call from here, the values it takes would be stored ahead of the
/// branch, on the common path).
#[inline(always)]
pub(crate) fn watertight<T: Lanes>(
    origin: &[T; 3],
    shear: &[T; 3],
    v0: &[T; 3],
    v1: &[T; 3],
    v2: &[T; 3],
    limit: T,
) -> Option<(T, T, T, u32)> {
    let (xy, z) = frame(origin, shear, [v0, v1, v2]);
    let e = edges(xy);
    if zero_edge(e) != 0 {
        return None;
    }
    Some(finish(e, z, shear[2], limit))
}

/// [`watertight`] with the edge functions that came out zero recomputed in `f64`
/// ([`exact_lanes`]), the rest the same arithmetic.
#[inline(always)]
pub(crate) fn watertight_exact<T: Lanes>(
    origin: &[T; 3],
    shear: &[T; 3],
    v0: &[T; 3],
    v1: &[T; 3],
    v2: &[T; 3],
    limit: T,
) -> (T, T, T, u32) {
    let (xy, z) = frame(origin, shear, [v0, v1, v2]);
    let e = edges(xy);
    let mask = zero_edge(e);
    let xy = xy.map(T::to_lanes);
    let mut e = e.map(T::to_lanes);
    let [e0, e1, e2] = &mut e;
    exact_lanes(
        mask,
        xy.each_ref().map(|a| a.as_ref()),
        [e0.as_mut(), e1.as_mut(), e2.as_mut()],
    );
    finish(e.map(T::from_lanes), z, shear[2], limit)
}

/// In each lane of `mask`, each of the edge functions `e` that is zero recomputed in
/// `f64` from the lane's sheared vertices `xy` (`ax, ay, bx, by, cx, cy`): the products
/// are exact there and the difference is rounded once, so its sign is the exact one
/// (and it is zero only on the edge's line). Back in `f32` it may underflow to zero.
#[inline(always)]
pub(crate) fn exact_lanes(mask: u32, xy: [&[f32]; 6], e: [&mut [f32]; 3]) {
    let exact = |(px, py): (f32, f32), (qx, qy): (f32, f32)| {
        (f64::from(qx) * f64::from(py) - f64::from(qy) * f64::from(px)) as f32
    };
    let [e0, e1, e2] = e;
    for k in lanes(mask) {
        let (a, b, c) = ((xy[0][k], xy[1][k]), (xy[2][k], xy[3][k]), (xy[4][k], xy[5][k]));
        for (value, (p, q)) in [(&mut e0[k], (b, c)), (&mut e1[k], (c, a)), (&mut e2[k], (a, b))] {
            if *value == 0.0 {
                *value = exact(p, q);
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The axes: `kz` as `Vec3::dominant_axis` (ties included), then the next two
    /// cyclically, swapped for a negative `dz`; the shear from `inv_dir`.
    #[test]
    fn axes_and_shear() {
        for (d, axes) in [
            ((1.0, 0.5, 0.25), [1, 2, 0]),
            ((-1.0, 0.5, 0.25), [2, 1, 0]),
            ((0.1, 2.0, -1.0), [2, 0, 1]),
            ((0.1, -2.0, -1.0), [0, 2, 1]),
            ((0.1, 0.2, 0.3), [0, 1, 2]),
            ((0.1, 0.2, -0.3), [1, 0, 2]),
            ((1.0, 1.0, 1.0), [1, 2, 0]),
            ((0.5, -1.0, 1.0), [0, 2, 1]),
            ((0.0, 0.0, 0.0), [1, 2, 0]),
        ] {
            let axes: [usize; 3] = axes;
            let dir = Vec3::new(d.0, d.1, d.2);
            let ray = Ray::new(Vec3::new(1.0, 2.0, 3.0), dir);
            let s = Sheared::new(&ray);
            assert_eq!(s.axes.map(|a| a as usize), axes, "{dir:?}");
            assert_eq!(s.axes[2] as usize, dir.dominant_axis(), "{dir:?}");
            assert_eq!(s.origin, s.permute(&[1.0, 2.0, 3.0]));
            let p = s.permute(&dir.to_array());
            if p[2] != 0.0 {
                let sz = 1.0 / p[2];
                assert_eq!(s.shear, [p[0] * sz, p[1] * sz, sz], "{dir:?}");
            }
        }
    }
}
