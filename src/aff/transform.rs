//! Affine transforms and rotations in double precision, as the original code keeps
//! its animation: an AFF transform is `T * R * S` (scale first, then rotation, then
//! translation), nested transforms compose parent first, and normals go by the
//! inverse transpose of the linear part.

use std::ops::{Add, Mul, Neg, Sub};

use crate::math::{mat3, Vec3};

/// A unit quaternion `w + xi + yj + zk` (the rotation code of the original
/// distribution, `quat.cpp`, works on these).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Quat {
    /// Scalar part: `cos(angle / 2)`.
    pub w: f64,
    /// Vector part: `sin(angle / 2) * axis`.
    pub v: [f64; 3],
}

/// Where `sin` of an angle counts as zero in [`Quat::log`], [`Quat::exp`] and
/// [`Quat::slerp`] (the original's cutoff).
const SIN_EPSILON: f64 = 1e-3;

impl Quat {
    /// `cos(angle / 2) + sin(angle / 2) * axis`; the axis is taken as given (the
    /// original asks for a unit axis and does not normalize it).
    pub fn from_angle_axis(angle: f64, axis: [f64; 3]) -> Quat {
        let (s, c) = (0.5 * angle).sin_cos();
        Quat {
            w: c,
            v: axis.map(|a| s * a),
        }
    }

    /// The angle (radians, in [0, 2π]) and unit axis of the rotation; angle 0 about
    /// x when the vector part is zero. `w` is clamped to [-1, 1] first, where the
    /// original would take the arc cosine of a rounded `w` past 1 to NaN.
    pub fn to_angle_axis(self) -> (f64, [f64; 3]) {
        let len2 = dot3(self.v, self.v);
        if len2 > 0.0 {
            let inv = 1.0 / len2.sqrt();
            (2.0 * self.w.clamp(-1.0, 1.0).acos(), self.v.map(|a| a * inv))
        } else {
            (0.0, [1.0, 0.0, 0.0])
        }
    }

    /// The 4-vector dot product.
    pub fn dot(self, o: Quat) -> f64 {
        self.w * o.w + dot3(self.v, o.v)
    }

    /// The inverse of a unit quaternion, its conjugate.
    pub fn conjugate(self) -> Quat {
        Quat {
            w: self.w,
            v: self.v.map(|a| -a),
        }
    }

    /// Every component times `k`.
    pub fn scale(self, k: f64) -> Quat {
        Quat {
            w: self.w * k,
            v: self.v.map(|a| a * k),
        }
    }

    /// `log q = A * axis` for `q = cos A + sin A * axis` (`w` of the result 0); the
    /// vector part unchanged where `sin A` is near zero (`sin A / A` tends to 1).
    pub fn log(self) -> Quat {
        let mut v = self.v;
        if self.w.abs() < 1.0 {
            let angle = self.w.acos();
            let s = angle.sin();
            if s.abs() >= SIN_EPSILON {
                v = v.map(|a| a * angle / s);
            }
        }
        Quat { w: 0.0, v }
    }

    /// `exp(A * axis) = cos A + sin A * axis` for a pure quaternion; the vector part
    /// unchanged where `sin A` is near zero.
    pub fn exp(self) -> Quat {
        let angle = dot3(self.v, self.v).sqrt();
        let s = angle.sin();
        let v = if s.abs() >= SIN_EPSILON {
            self.v.map(|a| a * s / angle)
        } else {
            self.v
        };
        Quat { w: angle.cos(), v }
    }

    /// Spherical linear interpolation from `self` (at 0) to `q` (at 1); `self` where
    /// the two are too close for the sine to divide by.
    pub fn slerp(self, t: f64, q: Quat) -> Quat {
        let angle = self.dot(q).clamp(-1.0, 1.0).acos();
        let s = angle.sin();
        if s < SIN_EPSILON {
            return self;
        }
        let (k0, k1) = (((1.0 - t) * angle).sin() / s, (t * angle).sin() / s);
        self.scale(k0) + q.scale(k1)
    }

    /// Shoemake's spherical quadrangle from `self` (at 0) to `q` (at 1) with inner
    /// control points `a` and `b`: `slerp(2t(1 - t), slerp(t, p, q), slerp(t, a, b))`.
    pub fn squad(self, t: f64, a: Quat, b: Quat, q: Quat) -> Quat {
        self.slerp(t, q).slerp(2.0 * t * (1.0 - t), a.slerp(t, b))
    }

    /// The rotation matrix of a unit quaternion (rows).
    pub fn to_matrix(self) -> [[f64; 3]; 3] {
        let [x, y, z] = self.v;
        let w = self.w;
        let (x2, y2, z2) = (x + x, y + y, z + z);
        let (xx, xy, xz) = (x * x2, x * y2, x * z2);
        let (yy, yz, zz) = (y * y2, y * z2, z * z2);
        let (wx, wy, wz) = (w * x2, w * y2, w * z2);
        [
            [1.0 - (yy + zz), xy - wz, xz + wy],
            [xy + wz, 1.0 - (xx + zz), yz - wx],
            [xz - wy, yz + wx, 1.0 - (xx + yy)],
        ]
    }
}

impl Add for Quat {
    type Output = Quat;

    /// The component-wise sum.
    fn add(self, o: Quat) -> Quat {
        Quat {
            w: self.w + o.w,
            v: [self.v[0] + o.v[0], self.v[1] + o.v[1], self.v[2] + o.v[2]],
        }
    }
}

impl Sub for Quat {
    type Output = Quat;

    /// The component-wise difference.
    fn sub(self, o: Quat) -> Quat {
        self + -o
    }
}

impl Neg for Quat {
    type Output = Quat;

    /// `-q`, the same rotation.
    fn neg(self) -> Quat {
        self.scale(-1.0)
    }
}

impl Mul for Quat {
    type Output = Quat;

    /// The Hamilton product (`self` applied after `o`).
    fn mul(self, o: Quat) -> Quat {
        let ([x1, y1, z1], [x2, y2, z2]) = (self.v, o.v);
        let (w1, w2) = (self.w, o.w);
        Quat {
            w: w1 * w2 - x1 * x2 - y1 * y2 - z1 * z2,
            v: [
                w1 * x2 + x1 * w2 + y1 * z2 - z1 * y2,
                w1 * y2 + y1 * w2 + z1 * x2 - x1 * z2,
                w1 * z2 + z1 * w2 + x1 * y2 - y1 * x2,
            ],
        }
    }
}

fn dot3(a: [f64; 3], b: [f64; 3]) -> f64 {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}

/// The matrix of a rotation by `angle` radians about `axis`, normalized first: the
/// identity for a zero axis.
pub fn rotation_about(axis: [f64; 3], angle: f64) -> [[f64; 3]; 3] {
    let len = dot3(axis, axis).sqrt();
    if len == 0.0 || !len.is_finite() {
        return IDENTITY3;
    }
    Quat::from_angle_axis(angle, axis.map(|a| a / len)).to_matrix()
}

const IDENTITY3: [[f64; 3]; 3] = [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]];

/// An affine transform `p -> L p + t`, stored as the three rows of `[L | t]`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Affine {
    /// Rows of the linear part with the translation as a fourth column.
    pub rows: [[f64; 4]; 3],
}

impl Affine {
    /// The identity.
    pub const IDENTITY: Affine = Affine {
        rows: [[1.0, 0.0, 0.0, 0.0], [0.0, 1.0, 0.0, 0.0], [0.0, 0.0, 1.0, 0.0]],
    };

    /// `T * R * S`: scale by `scale`, then rotate by the matrix `rotation`, then
    /// translate by `translation` (the order of `xs` and of keyframes).
    pub fn trs(translation: [f64; 3], rotation: [[f64; 3]; 3], scale: [f64; 3]) -> Affine {
        let mut rows = [[0.0; 4]; 3];
        for (i, row) in rows.iter_mut().enumerate() {
            for j in 0..3 {
                row[j] = rotation[i][j] * scale[j];
            }
            row[3] = translation[i];
        }
        Affine { rows }
    }

    /// The linear part.
    pub fn linear(&self) -> [[f64; 3]; 3] {
        self.rows.map(|r| [r[0], r[1], r[2]])
    }

    /// The column `j` of the linear part.
    pub fn column(&self, j: usize) -> [f64; 3] {
        self.rows.map(|r| r[j])
    }

    /// The image of point `p`.
    pub fn point(&self, p: Vec3) -> Vec3 {
        let [x, y, z] = [p.x as f64, p.y as f64, p.z as f64];
        let r = self.rows.map(|r| (r[0] * x + r[1] * y + r[2] * z + r[3]) as f32);
        Vec3::from_array(r)
    }

    /// The image of normal `n`, of unit length (zero for a zero normal): the inverse
    /// transpose of the linear part applied to it, by way of the cofactor matrix
    /// with the determinant's sign (the same direction, and defined for a singular
    /// transform too), normalized in f64 so that a large scale does not overflow it.
    pub fn normal(&self, n: Vec3) -> Vec3 {
        let c = self.cofactors();
        let sign = if self.determinant() < 0.0 { -1.0 } else { 1.0 };
        let [x, y, z] = [n.x as f64, n.y as f64, n.z as f64];
        let image = c.map(|r| sign * (r[0] * x + r[1] * y + r[2] * z));
        let len = dot3(image, image).sqrt();
        if len == 0.0 || !len.is_finite() {
            return Vec3::from_array(image.map(|v| v as f32));
        }
        Vec3::from_array(image.map(|v| (v / len) as f32))
    }

    /// The determinant of the linear part.
    pub fn determinant(&self) -> f64 {
        mat3::determinant(self.linear(), self.cofactors())
    }

    /// The cofactor matrix of the linear part: its determinant times its inverse
    /// transpose.
    fn cofactors(&self) -> [[f64; 3]; 3] {
        mat3::cofactors(self.linear())
    }

    /// The common length its linear part gives every vector, if it is a similarity
    /// (a rotation, perhaps a mirror, times a uniform scale) within a relative
    /// `1e-4`: what a sphere or a cone stays a sphere or a cone under.
    pub fn uniform_scale(&self) -> Option<f64> {
        let m = self.linear();
        let cols = [0, 1, 2].map(|j| [m[0][j], m[1][j], m[2][j]]);
        let len2 = cols.map(|c| dot3(c, c));
        let s2 = (len2[0] + len2[1] + len2[2]) / 3.0;
        let tolerance = 1e-4 * s2;
        let orthogonal = [(0, 1), (0, 2), (1, 2)]
            .iter()
            .all(|&(a, b)| dot3(cols[a], cols[b]).abs() <= tolerance);
        let uniform = len2.iter().all(|l| (l - s2).abs() <= 2.0 * tolerance);
        (orthogonal && uniform && s2.is_finite()).then(|| s2.sqrt())
    }

    /// True if every entry is finite.
    pub fn is_finite(&self) -> bool {
        self.rows.iter().flatten().all(|v| v.is_finite())
    }
}

impl Mul for Affine {
    type Output = Affine;

    /// `self * o`: `o` applied first (a parent times its child).
    fn mul(self, o: Affine) -> Affine {
        let (a, b) = (self.rows, o.rows);
        let mut rows = [[0.0; 4]; 3];
        for i in 0..3 {
            for j in 0..4 {
                let mut v = a[i][0] * b[0][j] + a[i][1] * b[1][j] + a[i][2] * b[2][j];
                if j == 3 {
                    v += a[i][3];
                }
                rows[i][j] = v;
            }
        }
        Affine { rows }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::f64::consts::FRAC_PI_2;

    fn close(a: Vec3, b: Vec3) -> bool {
        (a - b).length() < 1e-6
    }

    #[test]
    fn trs_scales_then_rotates_then_translates() {
        // Scale x by 2, rotate 90 degrees about z (x -> y), move by (0, 0, 5):
        // (1, 0, 0) -> (2, 0, 0) -> (0, 2, 0) -> (0, 2, 5).
        let m = Affine::trs(
            [0.0, 0.0, 5.0],
            rotation_about([0.0, 0.0, 3.0], FRAC_PI_2),
            [2.0, 1.0, 1.0],
        );
        assert!(close(m.point(Vec3::new(1.0, 0.0, 0.0)), Vec3::new(0.0, 2.0, 5.0)));
        // A parent moving everything by (1, 0, 0) applies after the child.
        let parent = Affine::trs([1.0, 0.0, 0.0], IDENTITY3, [1.0; 3]);
        assert!(close(
            (parent * m).point(Vec3::new(1.0, 0.0, 0.0)),
            Vec3::new(1.0, 2.0, 5.0)
        ));
    }

    #[test]
    fn normals_go_by_the_inverse_transpose() {
        // The plane x + y = 0 (normal (1, 1, 0)) scaled by 2 in x becomes x/2 + y = 0,
        // whose normal is (1/2, 1, 0), along (1, 2, 0).
        let m = Affine::trs([3.0, 0.0, 0.0], IDENTITY3, [2.0, 1.0, 1.0]);
        let n = m.normal(Vec3::new(1.0, 1.0, 0.0));
        assert!(close(n, Vec3::new(1.0, 2.0, 0.0).normalize()), "{n:?}");
        // A mirror keeps the normal on the side its inverse transpose gives.
        let mirror = Affine::trs([0.0; 3], IDENTITY3, [-1.0, 1.0, 1.0]);
        assert!(close(
            mirror.normal(Vec3::new(1.0, 0.0, 0.0)),
            Vec3::new(-1.0, 0.0, 0.0)
        ));
    }

    #[test]
    fn quaternion_round_trips_and_slerps_halfway() {
        let q = Quat::from_angle_axis(1.0, [0.0, 1.0, 0.0]);
        let (angle, axis) = q.to_angle_axis();
        assert!((angle - 1.0).abs() < 1e-12 && (axis[1] - 1.0).abs() < 1e-12);
        let id = Quat::from_angle_axis(0.0, [1.0, 0.0, 0.0]);
        let half = id.slerp(0.5, q).to_angle_axis().0;
        assert!((half - 0.5).abs() < 1e-12);
        // exp(log q) = q.
        let back = q.log().exp();
        assert!((back.w - q.w).abs() < 1e-12 && (back.v[1] - q.v[1]).abs() < 1e-12);
    }

    #[test]
    fn similarity_is_told_from_a_stretch() {
        let r = rotation_about([1.0, 1.0, 0.0], 0.7);
        assert_eq!(
            Affine::trs([1.0; 3], r, [3.0; 3])
                .uniform_scale()
                .map(|s| (s * 1e6).round()),
            Some(3e6)
        );
        assert_eq!(Affine::trs([0.0; 3], r, [1.0, 2.0, 1.0]).uniform_scale(), None);
    }
}
