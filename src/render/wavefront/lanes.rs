//! Vectors of eight lanes for the wavefront's shading, over the lane type of the
//! traversal kernels (`wide::f32x8`). Every operation is the scalar one of
//! [`Vec3`] lane by lane, in the same order, so a lane computes exactly what the
//! scalar path tracer computes for its path: sums, products, quotients and square
//! roots are correctly rounded either way, and no operation is fused.

use std::ops::{Add, Mul, Neg, Sub};

use wide::f32x8;

use crate::math::Vec3;

/// Paths handled together.
pub const LANES: usize = 8;

/// Eight vectors, one a lane.
#[derive(Clone, Copy, Debug)]
pub struct V3x8 {
    pub x: f32x8,
    pub y: f32x8,
    pub z: f32x8,
}

impl V3x8 {
    /// Lane `k` is `f(k)` for `k` below `n`, and `f(0)` past it (lanes past the
    /// paths repeat a real one, so their arithmetic stays tame).
    #[inline(always)]
    pub fn gather(n: usize, f: impl Fn(usize) -> Vec3) -> V3x8 {
        let mut v = [Vec3::ZERO; LANES];
        for (k, v) in v.iter_mut().enumerate() {
            *v = f(if k < n { k } else { 0 });
        }
        V3x8::from_lanes(&v)
    }

    /// Lane `k` is `v[k]`. (Here and below loops rather than
    /// `std::array::from_fn` and `map`, which the compiler left as calls: 5 % of a
    /// path-traced render's instructions.)
    #[inline(always)]
    pub fn from_lanes(v: &[Vec3; LANES]) -> V3x8 {
        let (mut x, mut y, mut z) = ([0.0; LANES], [0.0; LANES], [0.0; LANES]);
        for k in 0..LANES {
            (x[k], y[k], z[k]) = (v[k].x, v[k].y, v[k].z);
        }
        V3x8 {
            x: f32x8::from(x),
            y: f32x8::from(y),
            z: f32x8::from(z),
        }
    }

    /// The same vector in every lane.
    #[inline(always)]
    pub fn splat(v: Vec3) -> V3x8 {
        V3x8 {
            x: f32x8::splat(v.x),
            y: f32x8::splat(v.y),
            z: f32x8::splat(v.z),
        }
    }

    /// The lanes as vectors.
    #[inline(always)]
    pub fn lanes(self) -> [Vec3; LANES] {
        let (x, y, z) = (self.x.to_array(), self.y.to_array(), self.z.to_array());
        let mut v = [Vec3::ZERO; LANES];
        for k in 0..LANES {
            v[k] = Vec3::new(x[k], y[k], z[k]);
        }
        v
    }

    /// [`Vec3::dot`].
    #[inline(always)]
    pub fn dot(self, o: V3x8) -> f32x8 {
        self.x * o.x + self.y * o.y + self.z * o.z
    }

    /// [`Vec3::mul_elem`].
    #[inline(always)]
    pub fn mul_elem(self, o: V3x8) -> V3x8 {
        V3x8 {
            x: self.x * o.x,
            y: self.y * o.y,
            z: self.z * o.z,
        }
    }

    /// [`Vec3::normalize`]: the zero vector stays zero.
    #[inline(always)]
    pub fn normalize(self) -> V3x8 {
        let l2 = self.dot(self);
        let unit = self * (f32x8::ONE / l2.sqrt());
        V3x8::select(l2.simd_gt(f32x8::ZERO), unit, self)
    }

    /// [`Vec3::max_elem`].
    #[inline(always)]
    pub fn max_elem(self) -> f32x8 {
        self.x.fast_max(self.y).fast_max(self.z)
    }

    /// Lanes where every component is zero (`== Vec3::ZERO`).
    #[inline(always)]
    pub fn is_zero(self) -> f32x8 {
        let zero = f32x8::ZERO;
        self.x.simd_eq(zero) & self.y.simd_eq(zero) & self.z.simd_eq(zero)
    }

    /// Lanes where every component is finite ([`Vec3::is_finite`]).
    #[inline(always)]
    pub fn is_finite(self) -> f32x8 {
        let inf = f32x8::splat(f32::INFINITY);
        self.x.abs().simd_lt(inf) & self.y.abs().simd_lt(inf) & self.z.abs().simd_lt(inf)
    }

    /// `a` in the lanes of `mask`, `b` in the others.
    #[inline(always)]
    pub fn select(mask: f32x8, a: V3x8, b: V3x8) -> V3x8 {
        V3x8 {
            x: mask.bitselect(a.x, b.x),
            y: mask.bitselect(a.y, b.y),
            z: mask.bitselect(a.z, b.z),
        }
    }
}

impl Add for V3x8 {
    type Output = V3x8;
    #[inline(always)]
    fn add(self, o: V3x8) -> V3x8 {
        V3x8 {
            x: self.x + o.x,
            y: self.y + o.y,
            z: self.z + o.z,
        }
    }
}

impl Sub for V3x8 {
    type Output = V3x8;
    #[inline(always)]
    fn sub(self, o: V3x8) -> V3x8 {
        V3x8 {
            x: self.x - o.x,
            y: self.y - o.y,
            z: self.z - o.z,
        }
    }
}

impl Mul<f32x8> for V3x8 {
    type Output = V3x8;
    /// Each lane's vector times the lane's number.
    #[inline(always)]
    fn mul(self, s: f32x8) -> V3x8 {
        V3x8 {
            x: self.x * s,
            y: self.y * s,
            z: self.z * s,
        }
    }
}

impl Neg for V3x8 {
    type Output = V3x8;
    #[inline(always)]
    fn neg(self) -> V3x8 {
        V3x8 {
            x: -self.x,
            y: -self.y,
            z: -self.z,
        }
    }
}

/// A shading frame in each lane (`microfacet::Frame`): its two tangents and normal.
#[derive(Clone, Copy, Debug)]
pub struct Frame8 {
    pub s: V3x8,
    pub t: V3x8,
    pub n: V3x8,
}

impl Frame8 {
    /// `Frame::to_local`.
    #[inline(always)]
    pub fn to_local(self, v: V3x8) -> V3x8 {
        V3x8 {
            x: v.dot(self.s),
            y: v.dot(self.t),
            z: v.dot(self.n),
        }
    }

    /// `Frame::to_world`.
    #[inline(always)]
    pub fn to_world(self, v: V3x8) -> V3x8 {
        self.s * v.x + self.t * v.y + self.n * v.z
    }
}

/// The lanes of `mask` as bits, lane `k` bit `k`.
#[inline(always)]
pub fn bits(mask: f32x8) -> u32 {
    mask.to_bitmask()
}

/// Lanes `0..n` as a mask (all ones in them).
#[inline(always)]
pub fn first(n: usize) -> f32x8 {
    let mut lanes = [0.0; LANES];
    for lane in &mut lanes[..n.min(LANES)] {
        *lane = f32::from_bits(u32::MAX);
    }
    f32x8::from(lanes)
}

/// `f(k)` in lane `k` for `k` below `n`, `f(0)` past it.
#[inline(always)]
pub fn gather1(n: usize, f: impl Fn(usize) -> f32) -> f32x8 {
    let mut lanes = [0.0; LANES];
    for (k, lane) in lanes.iter_mut().enumerate() {
        *lane = f(if k < n { k } else { 0 });
    }
    f32x8::from(lanes)
}
