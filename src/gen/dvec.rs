//! Double-precision vectors and affine maps for the generators.
//!
//! The SPD computes in C `double`; doing the same keeps our geometry within a few
//! units in the last place of theirs before both are rounded for output. Rotations
//! here are right-handed and act on column vectors (the SPD's matrices act on row
//! vectors, which is the same rotation written transposed).

use std::ops::{Add, Mul, Neg, Sub};

use crate::math::Vec3;

/// A three-component `f64` vector.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub(crate) struct D3 {
    pub x: f64,
    pub y: f64,
    pub z: f64,
}

impl D3 {
    pub const ZERO: D3 = D3::new(0.0, 0.0, 0.0);
    pub const Z: D3 = D3::new(0.0, 0.0, 1.0);

    pub const fn new(x: f64, y: f64, z: f64) -> Self {
        D3 { x, y, z }
    }

    pub fn dot(self, o: D3) -> f64 {
        self.x * o.x + self.y * o.y + self.z * o.z
    }

    pub fn cross(self, o: D3) -> D3 {
        D3::new(
            self.y * o.z - self.z * o.y,
            self.z * o.x - self.x * o.z,
            self.x * o.y - self.y * o.x,
        )
    }

    pub fn length(self) -> f64 {
        self.dot(self).sqrt()
    }

    /// The unit vector along `self`; the zero vector stays zero.
    pub fn normalized(self) -> D3 {
        let len = self.length();
        if len > 0.0 {
            D3::new(self.x / len, self.y / len, self.z / len)
        } else {
            self
        }
    }

    /// Rounds to the crate's `f32` geometry.
    pub fn to_f32(self) -> Vec3 {
        Vec3::new(self.x as f32, self.y as f32, self.z as f32)
    }
}

impl Add for D3 {
    type Output = D3;
    fn add(self, o: D3) -> D3 {
        D3::new(self.x + o.x, self.y + o.y, self.z + o.z)
    }
}

impl Sub for D3 {
    type Output = D3;
    fn sub(self, o: D3) -> D3 {
        D3::new(self.x - o.x, self.y - o.y, self.z - o.z)
    }
}

impl Mul<f64> for D3 {
    type Output = D3;
    fn mul(self, s: f64) -> D3 {
        D3::new(self.x * s, self.y * s, self.z * s)
    }
}

impl Neg for D3 {
    type Output = D3;
    fn neg(self) -> D3 {
        D3::new(-self.x, -self.y, -self.z)
    }
}

/// A 3x3 matrix acting on column vectors: `m.apply(v)` is `M v`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct M3 {
    /// Rows.
    pub r: [D3; 3],
}

impl M3 {
    pub const IDENTITY: M3 = M3 {
        r: [D3::new(1.0, 0.0, 0.0), D3::new(0.0, 1.0, 0.0), D3::Z],
    };

    /// Uniform scale.
    pub fn scale(s: f64) -> M3 {
        M3 {
            r: [D3::new(s, 0.0, 0.0), D3::new(0.0, s, 0.0), D3::new(0.0, 0.0, s)],
        }
    }

    /// Right-handed rotation by `angle` radians about the unit vector `a`
    /// (Rodrigues: `v cos + (a x v) sin + a (a.v)(1 - cos)`).
    pub fn rotation(a: D3, angle: f64) -> M3 {
        let (s, c) = angle.sin_cos();
        let k = 1.0 - c;
        M3 {
            r: [
                D3::new(
                    a.x * a.x * k + c,
                    a.x * a.y * k - a.z * s,
                    a.x * a.z * k + a.y * s,
                ),
                D3::new(
                    a.y * a.x * k + a.z * s,
                    a.y * a.y * k + c,
                    a.y * a.z * k - a.x * s,
                ),
                D3::new(
                    a.z * a.x * k - a.y * s,
                    a.z * a.y * k + a.x * s,
                    a.z * a.z * k + c,
                ),
            ],
        }
    }

    /// Right-handed rotation about the x axis.
    pub fn rotation_x(angle: f64) -> M3 {
        M3::rotation(D3::new(1.0, 0.0, 0.0), angle)
    }

    /// Right-handed rotation about the z axis.
    pub fn rotation_z(angle: f64) -> M3 {
        M3::rotation(D3::Z, angle)
    }

    pub fn apply(&self, v: D3) -> D3 {
        D3::new(self.r[0].dot(v), self.r[1].dot(v), self.r[2].dot(v))
    }

    /// The product `self * o`: apply `o` first, then `self`.
    pub fn then_after(&self, o: &M3) -> M3 {
        let col = |j: usize| match j {
            0 => D3::new(o.r[0].x, o.r[1].x, o.r[2].x),
            1 => D3::new(o.r[0].y, o.r[1].y, o.r[2].y),
            _ => D3::new(o.r[0].z, o.r[1].z, o.r[2].z),
        };
        let row = |i: usize| {
            D3::new(
                self.r[i].dot(col(0)),
                self.r[i].dot(col(1)),
                self.r[i].dot(col(2)),
            )
        };
        M3 {
            r: [row(0), row(1), row(2)],
        }
    }
}

/// An affine map `p -> m p + t`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct Affine {
    pub m: M3,
    pub t: D3,
}

impl Affine {
    pub const IDENTITY: Affine = Affine {
        m: M3::IDENTITY,
        t: D3::ZERO,
    };

    pub fn apply(&self, p: D3) -> D3 {
        self.m.apply(p) + self.t
    }

    /// The composition `self ∘ o`: apply `o` first, then `self`.
    pub fn then_after(&self, o: &Affine) -> Affine {
        Affine {
            m: self.m.then_after(&o.m),
            t: self.m.apply(o.t) + self.t,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn close(a: D3, b: D3) -> bool {
        (a - b).length() < 1e-12
    }

    #[test]
    fn rotations_are_right_handed() {
        let q = std::f64::consts::FRAC_PI_2;
        assert!(close(
            M3::rotation_z(q).apply(D3::new(1.0, 0.0, 0.0)),
            D3::new(0.0, 1.0, 0.0)
        ));
        assert!(close(M3::rotation_x(q).apply(D3::new(0.0, 1.0, 0.0)), D3::Z));
        let y = D3::new(0.0, 1.0, 0.0);
        assert!(close(M3::rotation(y, q).apply(D3::Z), D3::new(1.0, 0.0, 0.0)));
    }

    #[test]
    fn composition_applies_right_operand_first() {
        let a = Affine {
            m: M3::rotation_z(0.3),
            t: D3::new(1.0, 2.0, 3.0),
        };
        let b = Affine {
            m: M3::scale(2.0),
            t: D3::new(-1.0, 0.5, 0.0),
        };
        let p = D3::new(0.2, -0.7, 1.1);
        assert!(close(a.then_after(&b).apply(p), a.apply(b.apply(p))));
    }

    #[test]
    fn normalizing_zero_keeps_zero() {
        assert_eq!(D3::ZERO.normalized(), D3::ZERO);
        assert!((D3::new(3.0, 4.0, 0.0).normalized().length() - 1.0).abs() < 1e-15);
    }
}
