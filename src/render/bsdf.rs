//! The path tracer's BSDFs: one documented mapping from a P3F or NFF material
//! `(C, Kd, S, Ks, shine, T, ior, emission, roughness)` to a sum of lobes.
//!
//! - **Diffuse**: Lambertian, albedo `Kd C`, times the texel at the point on a
//!   textured (AFF) surface ([`Bsdf::textured`]).
//! - **Mirror** (opaque materials, `T = 0`): reflectance `Ks S`, a perfect mirror at
//!   roughness 0, else the Trowbridge-Reitz (GGX) microfacet reflection of width
//!   `alpha = roughness^2` (`D G / (4 cos_o cos_i)`, no Fresnel: `Ks S` is the
//!   reflectance at every angle, as the course's metals).
//! - **Dielectric** (`T > 0`): an interface of relative index `ior`, Fresnel's
//!   equations for dielectrics (exact, as pbrt-v4 and Mitsuba 3; the Whitted
//!   integrator keeps the course's Schlick approximation), smooth at roughness 0 or
//!   rough by the same microfacet distribution (Walter et al. 2007); its reflection
//!   is tinted by `S`, its transmission scaled by `T`. Inside, the medium absorbs
//!   by Beer-Lambert with the coefficient `1 - C` (see `path.rs`). `Ks` is not used
//!   (the Whitted rules ignore it on glass too).
//!
//! The lobes are summed as the file gives them (a material whose weights add above
//! 1 reflects more than it receives); one lobe is chosen per sample with a
//! probability proportional to its mean weight, and the sample's weight and pdf are
//! those of the whole sum (one-sample MIS over the lobes). Radiance through a
//! dielectric is scaled by `1 / eta^2` (non-symmetric transport, as pbrt's
//! radiance mode).
//!
//! Directions are in the local frame of the shading normal facing the incoming ray
//! (`+z`, [`super::microfacet::Frame`]): `wo` (towards where the ray came from) has
//! `wo.z > 0`.

use std::f32::consts::{FRAC_1_PI, PI};

use super::microfacet::TrowbridgeReitz;
use crate::math::Vec3;
use crate::scene::Material;

/// One material at one hit, seen from `wo` (see the module docs).
#[derive(Clone, Copy, Debug)]
pub struct Bsdf {
    diffuse: Vec3,
    mirror: Vec3,
    /// The dielectric's reflection tint and transmission scale.
    tint: Vec3,
    transmit: f32,
    /// Index on the far side over index on `wo`'s side.
    eta: f32,
    rough: Option<TrowbridgeReitz>,
    /// Lobe choice probabilities: diffuse, mirror, dielectric.
    choice: [f32; 3],
}

/// A [`Bsdf`] of smooth lobes only ([`Bsdf::smooth_lobes`]): what its samples and
/// its values are made of.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SmoothLobes {
    /// The diffuse albedo `Kd C`.
    pub diffuse: Vec3,
    /// The mirror's reflectance `Ks S`.
    pub mirror: Vec3,
    /// The probabilities of choosing the diffuse and the mirror lobe.
    pub choice: [f32; 2],
}

/// A direction drawn from a [`Bsdf`].
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct BsdfSample {
    /// The new direction (local frame).
    pub wi: Vec3,
    /// `f cos / pdf`: what the path's throughput is multiplied by.
    pub weight: Vec3,
    /// The density of `wi` (solid angle) for MIS; for a perfectly specular sample,
    /// the probability of the lobe chosen.
    pub pdf: f32,
    /// Drawn from a perfectly specular lobe (no other direction could be).
    pub delta: bool,
    /// Through the surface, into or out of the object.
    pub transmitted: bool,
}

/// Fresnel's reflectance of a dielectric interface (unpolarized light) at the
/// cosine `cos_i` of the incident angle, for `eta` = index of the far side over the
/// near side (a negative cosine turns the interface around); 1 under total internal
/// reflection.
pub fn fresnel_dielectric(cos_i: f32, eta: f32) -> f32 {
    let (mut cos_i, mut eta) = (cos_i.clamp(-1.0, 1.0), eta);
    if cos_i < 0.0 {
        eta = 1.0 / eta;
        cos_i = -cos_i;
    }
    let sin2_t = (1.0 - cos_i * cos_i) / (eta * eta);
    if sin2_t >= 1.0 {
        return 1.0;
    }
    let cos_t = (1.0 - sin2_t).max(0.0).sqrt();
    let parallel = (eta * cos_i - cos_t) / (eta * cos_i + cos_t);
    let perpendicular = (cos_i - eta * cos_t) / (cos_i + eta * cos_t);
    (parallel * parallel + perpendicular * perpendicular) * 0.5
}

/// `w` (pointing away from the surface) refracted through the unit normal `n` of
/// its side (`w.n > 0`) into the far side, `eta` = far index over near: `None` under
/// total internal reflection.
fn refract_away(w: Vec3, n: Vec3, eta: f32) -> Option<Vec3> {
    let cos_i = w.dot(n);
    let sin2_t = (1.0 - cos_i * cos_i).max(0.0) / (eta * eta);
    if sin2_t >= 1.0 {
        return None;
    }
    let cos_t = (1.0 - sin2_t).sqrt();
    Some(-w / eta + n * (cos_i / eta - cos_t))
}

/// The mean of a colour's channels.
fn mean(c: Vec3) -> f32 {
    (c.x + c.y + c.z) / 3.0
}

impl Bsdf {
    /// The BSDF of `m` for a ray that `entering` the object (crossing against the
    /// primitive's own normal) or leaving it; smooth whatever `m`'s roughness unless
    /// `roughness`.
    pub fn new(m: &Material, entering: bool, roughness: bool) -> Bsdf {
        Bsdf::with_diffuse(m, entering, roughness, (m.color * m.kd).max(Vec3::ZERO))
    }

    /// [`Bsdf::new`] at a point of a textured surface: its diffuse albedo `Kd C`
    /// times the point's `texel` (AFF's textures; the other lobes are the
    /// material's).
    pub fn textured(m: &Material, entering: bool, roughness: bool, texel: Vec3) -> Bsdf {
        let diffuse = (m.color * m.kd).max(Vec3::ZERO).mul_elem(texel.max(Vec3::ZERO));
        Bsdf::with_diffuse(m, entering, roughness, diffuse)
    }

    /// The BSDF of `m` with the diffuse albedo `diffuse`.
    fn with_diffuse(m: &Material, entering: bool, roughness: bool, diffuse: Vec3) -> Bsdf {
        let dielectric = m.t > 0.0;
        let mirror = if dielectric {
            Vec3::ZERO
        } else {
            (m.specular * m.ks).max(Vec3::ZERO)
        };
        let ior = if m.ior > 0.0 { m.ior } else { 1.0 };
        let weights = [
            mean(diffuse),
            mean(mirror),
            if dielectric { m.t.min(1.0) } else { 0.0 },
        ];
        let total: f32 = weights.iter().sum();
        let choice = if total > 0.0 {
            weights.map(|w| w / total)
        } else {
            [0.0; 3]
        };
        Bsdf {
            diffuse,
            mirror,
            tint: m.specular.max(Vec3::ZERO),
            transmit: m.t.max(0.0),
            eta: if entering { ior } else { 1.0 / ior },
            rough: (roughness && m.roughness > 0.0).then(|| TrowbridgeReitz::of_roughness(m.roughness)),
            choice,
        }
    }

    /// The lobes of a BSDF of smooth diffuse and mirror lobes only (no dielectric,
    /// no roughness), which the wavefront samples eight paths at a time; `None` for
    /// any other.
    pub fn smooth_lobes(&self) -> Option<SmoothLobes> {
        (self.rough.is_none() && self.choice[2] == 0.0).then_some(SmoothLobes {
            diffuse: self.diffuse,
            mirror: self.mirror,
            choice: [self.choice[0], self.choice[1]],
        })
    }

    /// True if no lobe scatters anything (black and not transmissive).
    pub fn is_black(&self) -> bool {
        self.choice == [0.0; 3]
    }

    /// True if [`Bsdf::sample`]'s `lobe` number can change its outcome: false when
    /// one diffuse or mirror lobe is all there is (whatever number in [0, 1) then
    /// chooses it), so a caller need not draw one.
    pub fn needs_lobe_number(&self) -> bool {
        !matches!(self.choice, [1.0, 0.0, 0.0] | [0.0, 1.0, 0.0])
    }

    /// True if some lobe spreads light over directions (a light can be sampled).
    pub fn has_spread(&self) -> bool {
        self.choice[0] > 0.0 || (self.rough.is_some() && (self.choice[1] > 0.0 || self.choice[2] > 0.0))
    }

    /// `f(wo, wi)` of the spreading lobes and their mixture density of `wi`.
    pub fn eval(&self, wo: Vec3, wi: Vec3) -> (Vec3, f32) {
        let mut f = Vec3::ZERO;
        let mut pdf = 0.0;
        if self.choice[0] > 0.0 && wi.z > 0.0 {
            f += self.diffuse * FRAC_1_PI;
            pdf += self.choice[0] * wi.z * FRAC_1_PI;
        }
        if let Some(dist) = self.rough {
            if self.choice[1] > 0.0 && wi.z > 0.0 {
                let (fm, pm) = rough_mirror(&dist, wo, wi);
                f += self.mirror * fm;
                pdf += self.choice[1] * pm;
            }
            if self.choice[2] > 0.0 {
                let (fd, pd) = self.rough_dielectric(&dist, wo, wi);
                f += fd;
                pdf += self.choice[2] * pd;
            }
        }
        (f, pdf)
    }

    /// A direction for the numbers `lobe` (choosing the lobe) and `u`, or `None` if
    /// the drawn direction carries nothing (below the surface, say).
    pub fn sample(&self, wo: Vec3, lobe: f32, u: (f32, f32)) -> Option<BsdfSample> {
        let [pd, pm, _] = self.choice;
        if self.is_black() {
            return None;
        }
        if lobe < pd {
            let wi = cosine_hemisphere(u);
            return self.spread(wo, wi, false);
        }
        if lobe < pd + pm {
            let Some(dist) = self.rough else {
                let wi = Vec3::new(-wo.x, -wo.y, wo.z);
                return Some(BsdfSample {
                    wi,
                    weight: self.mirror / pm,
                    pdf: pm,
                    delta: true,
                    transmitted: false,
                });
            };
            let m = dist.sample_visible(wo, u);
            let wi = m * (2.0 * wo.dot(m)) - wo;
            return if wi.z > 0.0 {
                self.spread(wo, wi, false)
            } else {
                None
            };
        }
        // The dielectric: `lobe` rescaled to [0, 1) chooses reflection or transmission.
        let pt = self.choice[2];
        let uc = ((lobe - pd - pm) / pt).clamp(0.0, 1.0);
        match self.rough {
            None => self.smooth_dielectric(wo, uc, pt),
            Some(dist) => {
                let m = dist.sample_visible(wo, u);
                let f = fresnel_dielectric(wo.dot(m), self.eta);
                let wi = if uc < f {
                    let wi = m * (2.0 * wo.dot(m)) - wo;
                    (wi.z > 0.0).then_some(wi)?
                } else {
                    let wi = refract_away(wo, m, self.eta)?;
                    (wi.z < 0.0).then_some(wi)?
                };
                self.spread(wo, wi, wi.z < 0.0)
            }
        }
    }

    /// A sample of a spreading lobe at `wi`: the weight and density of the sum.
    fn spread(&self, wo: Vec3, wi: Vec3, transmitted: bool) -> Option<BsdfSample> {
        let (f, pdf) = self.eval(wo, wi);
        (pdf > 0.0).then(|| BsdfSample {
            wi,
            weight: f * (wi.z.abs() / pdf),
            pdf,
            delta: false,
            transmitted,
        })
    }

    /// The smooth dielectric: reflection with Fresnel's probability, else
    /// refraction; `p` the lobe's choice probability.
    fn smooth_dielectric(&self, wo: Vec3, uc: f32, p: f32) -> Option<BsdfSample> {
        let f = fresnel_dielectric(wo.z, self.eta);
        let normal = Vec3::new(0.0, 0.0, 1.0);
        if uc < f {
            return Some(BsdfSample {
                wi: Vec3::new(-wo.x, -wo.y, wo.z),
                weight: self.tint / p,
                pdf: p * f,
                delta: true,
                transmitted: false,
            });
        }
        let wi = refract_away(wo, normal, self.eta)?;
        Some(BsdfSample {
            wi,
            weight: Vec3::splat(self.transmit / (self.eta * self.eta) / p),
            pdf: p * (1.0 - f),
            delta: true,
            transmitted: true,
        })
    }

    /// The rough dielectric's `f(wo, wi)` (reflection tinted, transmission scaled
    /// by `T / eta^2`) and its density of `wi` (Walter et al. 2007, visible normals).
    fn rough_dielectric(&self, dist: &TrowbridgeReitz, wo: Vec3, wi: Vec3) -> (Vec3, f32) {
        let reflect = wi.z > 0.0;
        let etap = if reflect { 1.0 } else { self.eta };
        let mut m = wi * etap + wo;
        if m.length_squared() == 0.0 || wi.z == 0.0 {
            return (Vec3::ZERO, 0.0);
        }
        m = m.normalize();
        if m.z < 0.0 {
            m = -m;
        }
        // Microfacets seen from behind by either direction scatter nothing.
        if m.dot(wi) * wi.z < 0.0 || m.dot(wo) * wo.z < 0.0 {
            return (Vec3::ZERO, 0.0);
        }
        let fr = fresnel_dielectric(wo.dot(m), self.eta);
        let d = dist.d(m);
        let g = dist.g(wo, wi);
        let visible = dist.visible_pdf(wo, m);
        if reflect {
            let f = d * g * fr / (4.0 * wi.z * wo.z).abs();
            let pdf = visible / (4.0 * wo.dot(m).abs()) * fr;
            return (self.tint * f, pdf);
        }
        let denom = wi.dot(m) + wo.dot(m) / etap;
        let denom2 = denom * denom;
        if denom2 == 0.0 {
            return (Vec3::ZERO, 0.0);
        }
        let f = d * (1.0 - fr) * g * (wi.dot(m) * wo.dot(m) / (wi.z * wo.z * denom2)).abs() / (etap * etap);
        let pdf = visible * (wi.dot(m).abs() / denom2) * (1.0 - fr);
        (Vec3::splat(self.transmit * f), pdf)
    }
}

/// The rough mirror's `D G / (4 cos_o cos_i)` and its density of `wi` (visible
/// normals reflected: `D_wo(m) / (4 wo.m)`).
fn rough_mirror(dist: &TrowbridgeReitz, wo: Vec3, wi: Vec3) -> (f32, f32) {
    let m = wo + wi;
    if m.length_squared() == 0.0 {
        return (0.0, 0.0);
    }
    let m = m.normalize();
    let f = dist.d(m) * dist.g(wo, wi) / (4.0 * wo.z * wi.z);
    let pdf = dist.visible_pdf(wo, m) / (4.0 * wo.dot(m));
    (f, pdf)
}

/// A cosine-weighted direction of the upper hemisphere (Malley's method: a uniform
/// point of the unit disc, lifted).
pub fn cosine_hemisphere((u1, u2): (f32, f32)) -> Vec3 {
    let r = u1.sqrt();
    let phi = 2.0 * PI * u2;
    Vec3::new(r * phi.cos(), r * phi.sin(), (1.0 - u1).max(0.0).sqrt())
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Uniform numbers from a fixed-seed xorshift, independent of the renderer's.
    fn uniforms(n: usize, seed: u64) -> impl Iterator<Item = (f32, f32, f32)> {
        let mut state = seed | 1;
        let mut next = move || {
            state ^= state << 13;
            state ^= state >> 7;
            state ^= state << 17;
            (state >> 40) as f32 / (1u64 << 24) as f32
        };
        std::iter::repeat_with(move || (next(), next(), next())).take(n)
    }

    impl Bsdf {
        fn new_test(m: &Material, entering: bool) -> Bsdf {
            Bsdf::new(m, entering, true)
        }
    }

    fn material(kd: f32, ks: f32, t: f32, ior: f32, roughness: f32) -> Material {
        Material {
            color: Vec3::ONE,
            kd,
            specular: Vec3::ONE,
            ks,
            t,
            ior,
            roughness,
            ..Material::DEFAULT
        }
    }

    #[test]
    fn fresnel_at_normal_incidence_grazing_and_past_the_critical_angle() {
        assert!((fresnel_dielectric(1.0, 1.5) - 0.04).abs() < 1e-6);
        assert!((fresnel_dielectric(-1.0, 1.5) - 0.04).abs() < 1e-6);
        assert!((fresnel_dielectric(1e-6, 1.5) - 1.0).abs() < 1e-3);
        // Leaving glass past asin(1/1.5) = 41.8 degrees: total internal reflection.
        let c = 45f32.to_radians().cos();
        assert_eq!(fresnel_dielectric(c, 1.0 / 1.5), 1.0);
        assert!(fresnel_dielectric(41f32.to_radians().cos(), 1.0 / 1.5) < 1.0);
    }

    /// A BSDF of one diffuse or mirror lobe (smooth or rough, any colour) samples
    /// the same whatever its lobe number, as `needs_lobe_number` says; with two
    /// lobes, or a dielectric's reflection and transmission, the number decides.
    #[test]
    fn the_lobe_number_matters_only_when_it_chooses() {
        let wo = Vec3::new(0.3, -0.2, 0.93).normalize();
        let lobes = [0.0, 0.25, 0.5, 0.75, 1.0 - f32::EPSILON / 2.0];
        let samples = |b: &Bsdf, u| lobes.map(|lobe| b.sample(wo, lobe, u));
        // (material, whether its lobe number matters)
        let cases = [
            (material(0.7, 0.0, 0.0, 1.0, 0.0), false),
            (material(0.7, 0.0, 0.0, 1.0, 0.4), false),
            (material(0.0, 0.8, 0.0, 1.0, 0.0), false),
            (material(0.0, 0.8, 0.0, 1.0, 0.4), false),
            (material(0.5, 0.5, 0.0, 1.0, 0.0), true),
            (material(0.0, 0.0, 1.0, 1.5, 0.0), true),
            (material(0.0, 0.0, 1.0, 1.5, 0.3), true),
            (material(0.4, 0.0, 0.6, 1.5, 0.0), true),
        ];
        for (m, matters) in &cases {
            let b = Bsdf::new_test(m, true);
            assert_eq!(b.needs_lobe_number(), *matters, "{m:?}");
            let differs = uniforms(200, 3).any(|(_, u1, u2)| {
                let s = samples(&b, (u1, u2));
                s.iter().any(|x| *x != s[0])
            });
            assert_eq!(differs, *matters, "{m:?}");
        }
    }

    /// The directional albedo `E[weight]` of lobes that conserve energy: the
    /// Lambertian's is its albedo exactly; a smooth dielectric's (tint and T 1, with
    /// the radiance scaling undone) is 1; a rough mirror's is below 1 (single
    /// scattering loses some) and near it at low roughness.
    #[test]
    fn albedos_of_the_lobes() {
        let wo = Vec3::new(0.5, 0.1, 0.86).normalize();
        let n = 100_000;
        let albedo = |b: &Bsdf, undo_eta: bool| {
            let mut sum = 0.0f64;
            for (a, u1, u2) in uniforms(n, 7) {
                if let Some(s) = b.sample(wo, a, (u1, u2)) {
                    let scale = if undo_eta && s.transmitted {
                        b.eta * b.eta
                    } else {
                        1.0
                    };
                    sum += (mean(s.weight) * scale) as f64;
                }
            }
            sum / n as f64
        };
        let lambert = Bsdf::new_test(&material(0.5, 0.0, 0.0, 1.0, 0.0), true);
        assert!((albedo(&lambert, false) - 0.5).abs() < 1e-4);
        let glass = Bsdf::new_test(&material(0.0, 0.0, 1.0, 1.5, 0.0), true);
        assert!((albedo(&glass, true) - 1.0).abs() < 0.01);
        let rough_glass = Bsdf::new_test(&material(0.0, 0.0, 1.0, 1.5, 0.3), true);
        let a = albedo(&rough_glass, true);
        assert!(a > 0.9 && a < 1.01, "rough glass albedo {a}");
        let metal = Bsdf::new_test(&material(0.0, 1.0, 0.0, 1.0, 0.2), true);
        let a = albedo(&metal, false);
        assert!(a > 0.95 && a < 1.001, "rough mirror albedo {a}");
    }

    /// `sample`'s weight is `f cos / pdf` of `eval` at the drawn direction, and the
    /// pdf integrates to the chance of drawing a spreading direction: the sampler and
    /// the evaluator agree (what MIS needs).
    #[test]
    fn sample_weights_and_pdfs_agree_with_eval() {
        let wo = Vec3::new(-0.3, 0.2, 0.93).normalize();
        for m in [
            material(0.6, 0.0, 0.0, 1.0, 0.0),
            material(0.3, 0.5, 0.0, 1.0, 0.4),
            material(0.0, 0.0, 1.0, 1.33, 0.25),
            material(0.0, 0.0, 1.0, 1.0 / 1.5, 0.5),
        ] {
            for entering in [true, false] {
                let b = Bsdf::new(&m, entering, true);
                for (a, u1, u2) in uniforms(2000, 3) {
                    let Some(s) = b.sample(wo, a, (u1, u2)) else {
                        continue;
                    };
                    assert!(!s.delta);
                    let (f, pdf) = b.eval(wo, s.wi);
                    assert!(
                        (pdf - s.pdf).abs() <= 1e-3 * pdf.max(1.0),
                        "{m:?} {pdf} {}",
                        s.pdf
                    );
                    let w = f * (s.wi.z.abs() / pdf);
                    assert!((w - s.weight).length() <= 1e-3 * w.length().max(1.0));
                }
            }
        }
    }

    /// The mixture pdf integrates to at most 1 over the sphere (midpoint rule), and
    /// nearly to 1 where no sample is lost.
    #[test]
    fn the_pdf_integrates_to_one() {
        let wo = Vec3::new(0.4, 0.0, 0.92).normalize();
        let b = Bsdf::new_test(&material(0.4, 0.6, 0.0, 1.0, 0.5), true);
        let (nc, np) = (400, 400);
        let mut sum = 0.0f64;
        for i in 0..nc {
            let c = -1.0 + 2.0 * (i as f64 + 0.5) / nc as f64;
            let s = (1.0 - c * c).sqrt();
            for j in 0..np {
                let phi = 2.0 * std::f64::consts::PI * (j as f64 + 0.5) / np as f64;
                let wi = Vec3::new((s * phi.cos()) as f32, (s * phi.sin()) as f32, c as f32);
                sum += b.eval(wo, wi).1 as f64;
            }
        }
        let integral = sum * 4.0 * std::f64::consts::PI / (nc * np) as f64;
        assert!(integral > 0.95 && integral < 1.01, "{integral}");
    }
}
