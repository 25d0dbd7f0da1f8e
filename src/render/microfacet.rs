//! Rough surfaces: the Trowbridge–Reitz (GGX) microfacet distribution, the model of
//! nffrt's fuzzy reflection and rough refraction.
//!
//! A P3F material's `roughness` `r` in [0, 1] sets the distribution's width
//! `alpha = r^2` (Burley's perceptual mapping, as Disney's and Unreal's materials
//! use it); `r = 0` is a perfect mirror or smooth glass, and nffrt then never calls
//! this module. Directions are drawn by sampling a microfacet normal `m` from the
//! normals visible from the outgoing direction `wo` (Heitz, "Sampling the GGX
//! Distribution of Visible Normals", JCGT 2018), then reflecting or refracting about
//! `m`: the sampled `m` has the density `D_wo(m) = G1(wo) max(0, wo.m) D(m) / wo.n`.
//!
//! Everything is in the local frame of the (facing) normal, `n = +z`:
//!
//! ```text
//! D(m)   = 1 / (pi a^2 cos^4(tm) (1 + tan^2(tm) / a^2)^2)       the distribution
//! L(w)   = (sqrt(1 + a^2 tan^2(tw)) - 1) / 2                     Smith's Lambda
//! G1(w)  = 1 / (1 + L(w))                                        masking
//! ```

use crate::math::Vec3;

/// A Trowbridge–Reitz distribution of microfacet normals, isotropic.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct TrowbridgeReitz {
    alpha: f32,
}

/// The smallest width used: below it the distribution's density overflows `f32`.
const MIN_ALPHA: f32 = 1e-4;

impl TrowbridgeReitz {
    /// The distribution of a surface of `roughness` (in [0, 1]): `alpha = roughness^2`.
    pub fn of_roughness(roughness: f32) -> Self {
        TrowbridgeReitz {
            alpha: (roughness * roughness).max(MIN_ALPHA),
        }
    }

    /// The width `alpha`.
    pub fn alpha(&self) -> f32 {
        self.alpha
    }

    /// `D(m)`, the distribution of microfacet normals `m` (unit, local frame),
    /// normalized so that `D(m) cos(tm)` integrates to 1 over the hemisphere.
    pub fn d(&self, m: Vec3) -> f32 {
        let cos2 = m.z * m.z;
        if cos2 <= 0.0 {
            return 0.0;
        }
        let tan2 = (1.0 - cos2).max(0.0) / cos2;
        let a2 = self.alpha * self.alpha;
        let k = 1.0 + tan2 / a2;
        1.0 / (std::f32::consts::PI * a2 * cos2 * cos2 * k * k)
    }

    /// Smith's `Lambda(w)` for the unit direction `w` (local frame).
    pub fn lambda(&self, w: Vec3) -> f32 {
        let cos2 = w.z * w.z;
        if cos2 <= 0.0 {
            return f32::INFINITY;
        }
        let tan2 = (1.0 - cos2).max(0.0) / cos2;
        ((1.0 + self.alpha * self.alpha * tan2).sqrt() - 1.0) * 0.5
    }

    /// Smith's masking `G1(w) = 1 / (1 + Lambda(w))`.
    pub fn g1(&self, w: Vec3) -> f32 {
        1.0 / (1.0 + self.lambda(w))
    }

    /// Smith's height-correlated masking-shadowing `G(wo, wi) = 1 / (1 + L(wo) + L(wi))`.
    pub fn g(&self, wo: Vec3, wi: Vec3) -> f32 {
        1.0 / (1.0 + self.lambda(wo) + self.lambda(wi))
    }

    /// The density of [`TrowbridgeReitz::sample_visible`]'s normal `m` given `wo`:
    /// `G1(wo) max(0, wo.m) D(m) / wo.z`.
    pub fn visible_pdf(&self, wo: Vec3, m: Vec3) -> f32 {
        if wo.z <= 0.0 {
            return 0.0;
        }
        self.g1(wo) * wo.dot(m).max(0.0) * self.d(m) / wo.z
    }

    /// A microfacet normal visible from `wo` (unit, `wo.z > 0`, local frame) for the
    /// uniform numbers `(u1, u2)` in [0, 1)^2 (Heitz 2018): `wo` stretched into the
    /// configuration of unit roughness, a point drawn on the projected hemisphere
    /// there (a disc, its half behind `wo` squashed), lifted and unstretched.
    pub fn sample_visible(&self, wo: Vec3, (u1, u2): (f32, f32)) -> Vec3 {
        let a = self.alpha;
        let vh = Vec3::new(a * wo.x, a * wo.y, wo.z).normalize();
        let len2 = vh.x * vh.x + vh.y * vh.y;
        let t1 = if len2 > 0.0 {
            Vec3::new(-vh.y, vh.x, 0.0) * (1.0 / len2.sqrt())
        } else {
            Vec3::new(1.0, 0.0, 0.0)
        };
        let t2 = vh.cross(t1);
        let r = u1.sqrt();
        let phi = 2.0 * std::f32::consts::PI * u2;
        let (p1, mut p2) = (r * phi.cos(), r * phi.sin());
        let s = 0.5 * (1.0 + vh.z);
        p2 = (1.0 - s) * (1.0 - p1 * p1).max(0.0).sqrt() + s * p2;
        let lift = (1.0 - p1 * p1 - p2 * p2).max(0.0).sqrt();
        let nh = t1 * p1 + t2 * p2 + vh * lift;
        Vec3::new(a * nh.x, a * nh.y, nh.z.max(0.0)).normalize()
    }
}

/// An orthonormal frame around a unit normal `n`: world directions to and from the
/// local frame in which `n` is `+z` (Duff et al., "Building an Orthonormal Basis,
/// Revisited", JCGT 2017).
#[derive(Clone, Copy, Debug)]
pub struct Frame {
    s: Vec3,
    t: Vec3,
    n: Vec3,
}

impl Frame {
    /// The frame of the unit normal `n`.
    pub fn new(n: Vec3) -> Frame {
        let sign = 1.0f32.copysign(n.z);
        let a = -1.0 / (sign + n.z);
        let b = n.x * n.y * a;
        Frame {
            s: Vec3::new(1.0 + sign * n.x * n.x * a, sign * b, -sign * n.x),
            t: Vec3::new(b, sign + n.y * n.y * a, -n.y),
            n,
        }
    }

    /// A world direction in local coordinates.
    pub fn to_local(&self, v: Vec3) -> Vec3 {
        Vec3::new(v.dot(self.s), v.dot(self.t), v.dot(self.n))
    }

    /// A local direction in world coordinates.
    pub fn to_world(&self, v: Vec3) -> Vec3 {
        self.s * v.x + self.t * v.y + self.n * v.z
    }

    /// The frame's axes: the two tangents and the normal (local `x`, `y`, `z`).
    pub fn axes(&self) -> [Vec3; 3] {
        [self.s, self.t, self.n]
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Uniform numbers from a fixed-seed hash, independent of the renderer's.
    fn uniforms(n: usize) -> impl Iterator<Item = (f32, f32)> {
        let mut state = 0x2545_f491_4f6c_dd1du64;
        std::iter::repeat_with(move || {
            state ^= state << 13;
            state ^= state >> 7;
            state ^= state << 17;
            let u1 = (state >> 40) as f32 / (1u64 << 24) as f32;
            let u2 = ((state >> 16) & 0xFF_FFFF) as f32 / (1u64 << 24) as f32;
            (u1, u2)
        })
        .take(n)
    }

    #[test]
    fn d_cos_integrates_to_one_over_the_hemisphere() {
        for alpha in [0.05f32, 0.3, 0.8, 1.0] {
            let dist = TrowbridgeReitz { alpha };
            // Midpoint rule in (cos t, phi): the integral of D(m) cos(t) dw.
            let n = 4000;
            let mut sum = 0.0f64;
            for i in 0..n {
                let c = (i as f64 + 0.5) / n as f64;
                let m = Vec3::new((1.0 - c * c).sqrt() as f32, 0.0, c as f32);
                sum += dist.d(m) as f64 * c * 2.0 * std::f64::consts::PI / n as f64;
            }
            assert!((sum - 1.0).abs() < 0.01, "alpha {alpha}: {sum}");
        }
    }

    /// At normal incidence the visible normals are D(m) cos(tm): then
    /// u = tan^2(tm) / (a^2 + tan^2(tm)) is uniform on [0, 1) (the distribution's
    /// cumulative function), so its mean is 1/2 and its variance 1/12, and the
    /// azimuth is uniform: the sampler against the distribution's analytic moments.
    #[test]
    fn normal_incidence_samples_have_the_distributions_moments() {
        let n = 200_000;
        for alpha in [0.04f32, 0.25, 0.7] {
            let dist = TrowbridgeReitz { alpha };
            let (mut s1, mut s2, mut cx, mut cy) = (0.0f64, 0.0f64, 0.0f64, 0.0f64);
            for u in uniforms(n) {
                let m = dist.sample_visible(Vec3::new(0.0, 0.0, 1.0), u);
                assert!((m.length() - 1.0).abs() < 1e-5 && m.z > 0.0);
                let tan2 = ((1.0 - m.z * m.z) / (m.z * m.z)) as f64;
                let v = tan2 / (alpha as f64 * alpha as f64 + tan2);
                s1 += v;
                s2 += v * v;
                let phi = (m.y as f64).atan2(m.x as f64);
                cx += phi.cos();
                cy += phi.sin();
            }
            let mean = s1 / n as f64;
            let var = s2 / n as f64 - mean * mean;
            // Standard errors: 1/sqrt(12 n) for the mean, about 0.0007 here.
            assert!((mean - 0.5).abs() < 0.004, "alpha {alpha}: mean {mean}");
            assert!((var - 1.0 / 12.0).abs() < 0.003, "alpha {alpha}: variance {var}");
            assert!((cx / n as f64).abs() < 0.01 && (cy / n as f64).abs() < 0.01);
        }
    }

    /// The sampled normals' density is `visible_pdf`: the histogram of cos(tm) at an
    /// oblique `wo` matches the pdf integrated over each bin (by the midpoint rule
    /// over azimuth and angle), within a few standard errors.
    #[test]
    fn oblique_samples_follow_the_visible_pdf() {
        let dist = TrowbridgeReitz { alpha: 0.5 };
        let wo = Vec3::new(0.6, 0.0, 0.8);
        let bins = 10;
        let n = 200_000;
        let mut hist = vec![0usize; bins];
        for u in uniforms(n) {
            let m = dist.sample_visible(wo, u);
            hist[((m.z * bins as f32) as usize).min(bins - 1)] += 1;
        }
        for (b, &count) in hist.iter().enumerate() {
            let (steps_c, steps_p) = (200, 400);
            let mut p = 0.0f64;
            for i in 0..steps_c {
                let c = (b as f64 + (i as f64 + 0.5) / steps_c as f64) / bins as f64;
                let s = (1.0 - c * c).sqrt();
                for j in 0..steps_p {
                    let phi = 2.0 * std::f64::consts::PI * (j as f64 + 0.5) / steps_p as f64;
                    let m = Vec3::new((s * phi.cos()) as f32, (s * phi.sin()) as f32, c as f32);
                    p += dist.visible_pdf(wo, m) as f64;
                }
            }
            let want = p / (steps_c * steps_p) as f64 * 2.0 * std::f64::consts::PI / bins as f64;
            let got = count as f64 / n as f64;
            let sigma = (want * (1.0 - want) / n as f64).sqrt();
            assert!(
                (got - want).abs() < 5.0 * sigma + 1e-4,
                "bin {b}: {got} against {want}"
            );
        }
    }

    #[test]
    fn the_frame_is_orthonormal_and_round_trips() {
        for n in [
            Vec3::new(0.0, 0.0, 1.0),
            Vec3::new(0.0, 0.0, -1.0),
            Vec3::new(0.3, -0.5, 0.2).normalize(),
            Vec3::new(-1.0, 1e-7, 0.0).normalize(),
        ] {
            let f = Frame::new(n);
            assert!((f.to_local(n) - Vec3::new(0.0, 0.0, 1.0)).length() < 1e-6);
            let v = Vec3::new(0.2, 0.7, -0.4).normalize();
            assert!((f.to_world(f.to_local(v)) - v).length() < 1e-6);
            assert!(f.s.dot(f.t).abs() < 1e-6 && f.s.dot(n).abs() < 1e-6 && f.t.dot(n).abs() < 1e-6);
        }
    }
}
