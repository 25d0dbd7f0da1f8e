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
//! scalar recomputation ([`exact_lanes`]).

use std::ops::{Add, BitAnd, BitOr, Div, Mul, Sub};

use wide::{f32x4, f32x8};

use crate::math::Ray;

/// A ray in the test's frame: the axes `kx, ky, kz` (`kz` the direction's largest
/// component in magnitude, `kx, ky` the next two cyclically, swapped when the
/// direction along `kz` is negative, which keeps the triangles' winding), the origin's
/// coordinates on them, and the shear `(dx/dz, dy/dz, 1/dz)`, computed as
/// `(dx·Sz, dy·Sz, Sz)` with `Sz` the ray's `inv_dir` along `kz` (no division).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Sheared {
    /// `[kx, ky, kz]`.
    pub axes: [u8; 3],
    /// The origin's coordinates along `axes`.
    pub origin: [f32; 3],
    /// `[Sx, Sy, Sz]` along `axes`.
    pub shear: [f32; 3],
}

impl Sheared {
    /// Prepares `ray` (a zero direction gives no hits). Without a branch: the axes of
    /// random rays would be a branch mispredicted at every other query.
    #[inline(always)]
    pub fn new(ray: &Ray) -> Sheared {
        /// `[kx, ky, kz]` by `2 kz + (direction along kz < 0)`.
        const AXES: [[u8; 3]; 6] = [[1, 2, 0], [2, 1, 0], [2, 0, 1], [0, 2, 1], [0, 1, 2], [1, 0, 2]];
        let d = ray.dir.to_array();
        let a = ray.dir.abs();
        // `Vec3::dominant_axis`: x unless y or z is larger, then y unless z is larger.
        let not_x = !(a.x >= a.y && a.x >= a.z);
        let kz = usize::from(not_x) * (1 + usize::from(!(a.y >= a.z)));
        let axes = AXES[2 * kz + usize::from(d[kz] < 0.0)];
        let [kx, ky] = [axes[0] as usize, axes[1] as usize];
        let o = ray.origin.to_array();
        // `1 / dz` (`dz`, the largest component, is below `TINY_DIR` only for a
        // direction of next to nothing).
        let sz = ray.inv_dir[kz];
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
    /// `self != rhs` (true on NaN).
    fn ne(self, rhs: Self) -> Self::Mask;
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
    fn ne(self, rhs: Self) -> bool {
        self != rhs
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
            fn ne(self, rhs: Self) -> Self {
                self.simd_ne(rhs)
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

/// The edge function of the edge from `p` to `q` (sheared `x, y`): `qx·py − qy·px`.
#[inline(always)]
fn edge<T: Lanes>((px, py): (T, T), (qx, qy): (T, T)) -> T {
    qx * py - qy * px
}

/// The test on lanes of (ray, triangle) pairs: `origin` and `shear` the rays'
/// [`Sheared::origin`] and [`Sheared::shear`], `v0, v1, v2` the vertices permuted
/// by the rays' [`Sheared::axes`]. Returns per lane the distance `t` and the
/// barycentrics `u` (weight of `v1`) and `v` (weight of `v2`), and the lanes hit with
/// `0 < t < limit` as bits (read `t`, `u`, `v` only there).
#[inline(always)]
pub(crate) fn watertight<T: Lanes>(
    origin: &[T; 3],
    shear: &[T; 3],
    v0: &[T; 3],
    v1: &[T; 3],
    v2: &[T; 3],
    limit: T,
) -> (T, T, T, u32) {
    let [sx, sy, sz] = *shear;
    let relative = |p: &[T; 3]| [p[0] - origin[0], p[1] - origin[1], p[2] - origin[2]];
    let (a, b, c) = (relative(v0), relative(v1), relative(v2));
    let sheared = |p: &[T; 3]| (p[0] - sx * p[2], p[1] - sy * p[2]);
    let (a_xy, b_xy, c_xy) = (sheared(&a), sheared(&b), sheared(&c));
    // The edge functions opposite `v0`, `v1` and `v2`.
    let mut e = [edge(b_xy, c_xy), edge(c_xy, a_xy), edge(a_xy, b_xy)];
    let zero = T::bits(e[0].eq(T::ZERO) | e[1].eq(T::ZERO) | e[2].eq(T::ZERO));
    if zero != 0 {
        e = exact_edges(zero, [a_xy.0, a_xy.1, b_xy.0, b_xy.1, c_xy.0, c_xy.1], e);
    }
    let [e0, e1, e2] = e;
    let det = e0 + e1 + e2;
    let t_scaled = e0 * (sz * a[2]) + e1 * (sz * b[2]) + e2 * (sz * c[2]);
    let inv_det = T::ONE / det;
    let t = t_scaled * inv_det;
    // One sign for the three (zero counts as either), a triangle seen other than
    // edge-on, and the distance within bounds. Comparisons with a NaN are false
    // (`≠` true), and a NaN anywhere (an empty lane) makes `t` NaN: no hit.
    let same_sign = e0.min(e1).min(e2).ge(T::ZERO) | e0.max(e1).max(e2).le(T::ZERO);
    let ok = same_sign & det.ne(T::ZERO) & t.gt(T::ZERO) & t.lt(limit);
    (t, e1 * inv_det, e2 * inv_det, T::bits(ok))
}

/// `e` with the edge functions that are zero in the lanes of `mask` recomputed in
/// `f64` ([`exact_lanes`]); `xy` holds the sheared `ax, ay, bx, by, cx, cy`.
#[cold]
#[inline(never)]
fn exact_edges<T: Lanes>(mask: u32, xy: [T; 6], e: [T; 3]) -> [T; 3] {
    let xy = xy.map(T::to_lanes);
    let mut e = e.map(T::to_lanes);
    let [e0, e1, e2] = &mut e;
    exact_lanes(
        mask,
        xy.each_ref().map(|a| a.as_ref()),
        [e0.as_mut(), e1.as_mut(), e2.as_mut()],
    );
    e.map(T::from_lanes)
}

/// In each lane of `mask`, each of the edge functions `e` that is zero recomputed in
/// `f64` from the lane's sheared vertices `xy` (`ax, ay, bx, by, cx, cy`): the products
/// are exact there and the difference is rounded once, so its sign is the exact one
/// (and it is zero only on the edge's line). Back in `f32` it may underflow to zero.
#[inline(always)]
pub(crate) fn exact_lanes(mut mask: u32, xy: [&[f32]; 6], e: [&mut [f32]; 3]) {
    let exact = |(px, py): (f32, f32), (qx, qy): (f32, f32)| {
        (f64::from(qx) * f64::from(py) - f64::from(qy) * f64::from(px)) as f32
    };
    let [e0, e1, e2] = e;
    while mask != 0 {
        let k = mask.trailing_zeros() as usize;
        mask &= mask - 1;
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
    use crate::math::Vec3;

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
            let dir = Vec3::new(d.0, d.1, d.2);
            let ray = Ray::new(Vec3::new(1.0, 2.0, 3.0), dir);
            let s = Sheared::new(&ray);
            assert_eq!(s.axes, axes, "{dir:?}");
            assert_eq!(usize::from(s.axes[2]), dir.dominant_axis(), "{dir:?}");
            assert_eq!(s.origin, s.permute(&[1.0, 2.0, 3.0]));
            let p = s.permute(&dir.to_array());
            if p[2] != 0.0 {
                let sz = 1.0 / p[2];
                assert_eq!(s.shear, [p[0] * sz, p[1] * sz, sz], "{dir:?}");
            }
        }
    }
}
