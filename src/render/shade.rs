//! The shading model: the local illumination at a hit and the secondary rays it
//! spawns, with their weights. Two models, chosen by the scene's dialect.
//!
//! Both share the form of the local term. For a hit with material
//! `(C, Kd, S, Ks, shine, T, ior)` (`S`, the specular colour, is white in NFF), facing
//! normal `n` (the geometric normal turned towards the incoming ray), shading normal
//! `ns`, view direction `v = -d` and lights of intensity `I_l` sampled at points `p_j`
//! (one for a point light, `M` for an area light, see `light.rs`):
//!
//! ```text
//! colour = A * Kd * C                                                  ambient
//!        + sum over lights, over their points with dot(n, l_j) > 0, unshadowed:
//!            I_l / M * (Kd * C * max(0, ns.l_j) + Ks * S * c_j^shine)  Lambert + highlight
//!        + secondary rays (below)
//! ```
//!
//! The highlight's cosine `c_j` (clamped to [0, 1]) is the model's: NFF's is
//! Blinn-Phong's `ns.h_j`, `h_j = normalize(l_j + v)` (the SPD's); P3F's is Phong's
//! `r_j.v`, `r_j = 2 (ns.l_j) ns - l_j` the light's mirror direction. The course's
//! texts name Blinn-Phong, but its pictures have Phong's narrower highlights: against
//! `reference/p3f/balls_low-whitted.png` the mean difference per channel falls from
//! 4.96/4.19/5.11 with `ns.h` to 3.51/2.83/4.13 with `r.v` (P3F-SPEC).
//!
//! **NFF (the SPD's Whitted rules)**: every hit on a surface with `Ks > 0` or `T > 0`
//! spawns a mirror ray of weight `Ks`, and one with `T > 0` a refracted ray of weight
//! `T` (Snell, `ior` entering and `1/ior` leaving; `ior <= 0` means 1); under total
//! internal reflection the mirror ray carries `Ks + T`. `A` and every uncoloured light
//! have intensity `sqrt(n) / (2n)` for n lights (`A = 1` without lights).
//!
//! **P3F (the course's)**: lights have their colours as intensities and there is no
//! ambient term (`A = 0`). The colour a secondary ray returns is clamped to 1 in each
//! channel before the hit that spawned it weights it, as the course's template does:
//! its pictures show the over-exposed yellow floor reflected pale in the spheres of
//! `2025/balls_low.p3f`, and the clamp takes the mean difference from the course's
//! Whitted picture from 3.53/2.84/4.15 to 2.25/1.90/4.13 levels of 255. An opaque surface (`T = 0`) with `Ks > 0` spawns a mirror
//! ray of weight `Ks * S`. A transmissive one (`T > 0`) spawns a mirror ray of weight
//! `R * S` and a refracted ray of weight `(1 - R) * T * C` — the diffuse colour
//! absorbs, as the course's glass does — where `R` is Schlick's approximation of the
//! Fresnel reflectance (see [`schlick`]), 1 under total internal reflection.

use crate::math::Vec3;
use crate::scene::{Dialect, Material, SceneInfo};

use super::light::LightSource;

/// The kind of a secondary ray.
#[derive(Clone, Copy, Debug, PartialEq, Eq, serde::Serialize)]
pub enum Branch {
    /// Mirror reflection.
    Reflection,
    /// Mirror reflection under total internal reflection (carries the transmitted share).
    TotalInternalReflection,
    /// Refraction.
    Refraction,
}

/// Which rules shade the scene (see the module docs).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Model {
    /// NFF: the SPD's Whitted rules.
    Spd,
    /// P3F: the course's, with Schlick-Fresnel dielectrics.
    P3f,
}

/// The model's light intensities and ambient term for one scene.
#[derive(Clone, Debug)]
pub struct Lighting {
    /// The rules.
    pub model: Model,
    /// Ambient intensity.
    pub ambient: Vec3,
    /// Every light with its intensity.
    pub lights: Vec<LightSource>,
}

impl Lighting {
    /// Resolves the scene's model and intensities (see the module docs).
    pub fn new(scene: &SceneInfo) -> Lighting {
        if scene.dialect != Dialect::Nff {
            return Lighting {
                model: Model::P3f,
                ambient: Vec3::ZERO,
                lights: LightSource::of(&scene.lights, Vec3::ONE),
            };
        }
        let n = scene.lights.len();
        let default = if n == 0 {
            1.0
        } else {
            (n as f32).sqrt() / (2.0 * n as f32)
        };
        Lighting {
            model: Model::Spd,
            ambient: Vec3::splat(default),
            lights: LightSource::of(&scene.lights, Vec3::splat(default)),
        }
    }
}

/// The local term of a unit-intensity light in unit direction `l` under the rules
/// `M`: Lambert on `diffuse` (`Kd * C`) plus the highlight `Ks * S * c^shine`, `c`
/// the model's highlight cosine ([`Rules::highlight_cosine`]).
#[inline]
pub fn local<M: Rules>(m: &Material, diffuse: Vec3, ns: Vec3, l: Vec3, view: Vec3) -> Vec3 {
    let lambert = ns.dot(l).max(0.0);
    // A negative exponent would turn a zero cosine into infinity, and a cosine that
    // rounds above 1 a huge exponent (shine 1e30) into infinity too.
    let highlight = if m.ks > 0.0 {
        let c = M::highlight_cosine(ns, l, view);
        m.ks * c.clamp(0.0, 1.0).powf(m.shine.max(0.0))
    } else {
        0.0
    };
    diffuse * lambert + m.specular * highlight
}

/// The secondary rays of a hit: the refracted ray's direction and weight, and the
/// mirror ray's kind and weight.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Secondary {
    /// Direction and weight of the refracted ray.
    pub refraction: Option<(Vec3, Vec3)>,
    /// Kind and weight of the mirror ray.
    pub reflection: Option<(Branch, Vec3)>,
}

/// The rules of one model for the secondary rays of a hit: a type per model, so the
/// recursion is compiled once per model and pays for no choice at every hit.
pub trait Rules {
    /// The secondary rays of a hit on `m` by unit direction `d`, with unit normal
    /// `n` facing the ray; `entering` says whether the ray crosses into the object.
    fn secondary(m: &Material, d: Vec3, n: Vec3, entering: bool) -> Secondary;

    /// The cosine whose power `shine` is the highlight of a light in unit direction
    /// `l` seen from unit direction `view` on the unit shading normal `ns` (see the
    /// module docs; not clamped).
    fn highlight_cosine(ns: Vec3, l: Vec3, view: Vec3) -> f32;

    /// The colour a secondary ray returns to the hit that spawned it, given the
    /// colour at its end (see the module docs).
    fn returned(color: Vec3) -> Vec3;
}

/// [`Model::Spd`]'s rules.
pub struct SpdRules;

/// [`Model::P3f`]'s rules.
pub struct P3fRules;

/// The indices of refraction on the incident and the transmitted side (`ior <= 0`,
/// seen on opaque materials, means 1).
#[inline(always)]
fn indices(m: &Material, entering: bool) -> (f32, f32) {
    let ior = if m.ior > 0.0 { m.ior } else { 1.0 };
    if entering {
        (1.0, ior)
    } else {
        (ior, 1.0)
    }
}

impl Rules for SpdRules {
    /// Blinn-Phong: `ns.h`, `h` the half vector.
    #[inline(always)]
    fn highlight_cosine(ns: Vec3, l: Vec3, view: Vec3) -> f32 {
        ns.dot((l + view).normalize())
    }

    /// As it is: the SPD's rules clamp only the pixel.
    #[inline(always)]
    fn returned(color: Vec3) -> Vec3 {
        color
    }

    #[inline(always)]
    fn secondary(m: &Material, d: Vec3, n: Vec3, entering: bool) -> Secondary {
        if m.ks <= 0.0 && m.t <= 0.0 {
            return Secondary {
                refraction: None,
                reflection: None,
            };
        }
        let mut weight = m.ks;
        let mut kind = Branch::Reflection;
        let mut refraction = None;
        if m.t > 0.0 {
            let (n1, n2) = indices(m, entering);
            match refract(d, n, n1 / n2) {
                Some(dir) => refraction = Some((dir, Vec3::splat(m.t))),
                // Total internal reflection: the transmitted share goes to the mirror ray.
                None => {
                    weight += m.t;
                    kind = Branch::TotalInternalReflection;
                }
            }
        }
        Secondary {
            refraction,
            reflection: Some((kind, Vec3::splat(weight))),
        }
    }
}

impl Rules for P3fRules {
    /// Phong: `r.v`, `r` the light's mirror direction about `ns`.
    #[inline(always)]
    fn highlight_cosine(ns: Vec3, l: Vec3, view: Vec3) -> f32 {
        (ns * (2.0 * ns.dot(l)) - l).dot(view)
    }

    /// Clamped to 1 in each channel, as the course's pictures show it.
    #[inline(always)]
    fn returned(color: Vec3) -> Vec3 {
        color.min(Vec3::ONE)
    }

    #[inline(always)]
    fn secondary(m: &Material, d: Vec3, n: Vec3, entering: bool) -> Secondary {
        if m.t <= 0.0 {
            return Secondary {
                refraction: None,
                reflection: (m.ks > 0.0).then_some((Branch::Reflection, m.specular * m.ks)),
            };
        }
        let (n1, n2) = indices(m, entering);
        match refract(d, n, n1 / n2) {
            Some(dir) => {
                let r = schlick(-d.dot(n), -dir.dot(n), n1, n2);
                Secondary {
                    refraction: Some((dir, m.color * ((1.0 - r) * m.t))),
                    reflection: Some((Branch::Reflection, m.specular * r)),
                }
            }
            None => Secondary {
                refraction: None,
                reflection: Some((Branch::TotalInternalReflection, m.specular)),
            },
        }
    }
}

impl Model {
    /// The secondary rays of a hit under this model's rules (see [`Rules`]).
    pub fn secondary(self, m: &Material, d: Vec3, n: Vec3, entering: bool) -> Secondary {
        match self {
            Model::Spd => SpdRules::secondary(m, d, n, entering),
            Model::P3f => P3fRules::secondary(m, d, n, entering),
        }
    }
}

/// Schlick's approximation of the Fresnel reflectance of a dielectric interface from
/// index `n1` into `n2`: `R0 + (1 - R0) (1 - cos)^5`, `R0 = ((n1 - n2) / (n1 + n2))^2`,
/// with `cos` the cosine of the angle on the optically thinner side (the incident
/// angle `cos_i` entering a denser medium, the transmitted angle `cos_t` leaving
/// one), which keeps the approximation symmetric and close to Fresnel's equations.
#[inline]
pub fn schlick(cos_i: f32, cos_t: f32, n1: f32, n2: f32) -> f32 {
    let r0 = ((n1 - n2) / (n1 + n2)).powi(2);
    let cos = if n1 <= n2 { cos_i } else { cos_t };
    let k = (1.0 - cos.clamp(0.0, 1.0)).powi(5);
    r0 + (1.0 - r0) * k
}

/// Mirror reflection of `d` about the unit normal `n`.
#[inline]
pub fn reflect(d: Vec3, n: Vec3) -> Vec3 {
    d - n * (2.0 * d.dot(n))
}

/// Snell refraction of the unit direction `d` through a surface with unit normal `n`
/// facing the incoming ray (`dot(d, n) < 0`), for `eta` = n_incident / n_transmitted.
/// `None` under total internal reflection.
#[inline]
pub fn refract(d: Vec3, n: Vec3, eta: f32) -> Option<Vec3> {
    let cos_i = -d.dot(n);
    // sin^2 of the transmitted angle, from Snell's law eta * sin_i = sin_t.
    let sin2_t = eta * eta * (1.0 - cos_i * cos_i).max(0.0);
    if sin2_t > 1.0 {
        return None;
    }
    let cos_t = (1.0 - sin2_t).sqrt();
    Some((d * eta + n * (eta * cos_i - cos_t)).normalize())
}

#[cfg(test)]
mod tests {
    use super::*;

    fn close(a: Vec3, b: Vec3) -> bool {
        (a - b).length() < 1e-5
    }

    #[test]
    fn reflection_mirrors_about_the_normal() {
        let d = Vec3::new(1.0, -1.0, 0.0).normalize();
        let r = reflect(d, Vec3::new(0.0, 1.0, 0.0));
        assert!(close(r, Vec3::new(1.0, 1.0, 0.0).normalize()));
    }

    #[test]
    fn refraction_obeys_snell() {
        // 45 degrees into glass (ior 1.5): sin_t = sin 45 / 1.5.
        let n = Vec3::new(0.0, 1.0, 0.0);
        let d = Vec3::new(1.0, -1.0, 0.0).normalize();
        let t = refract(d, n, 1.0 / 1.5).unwrap();
        let sin_t = (0.5f32).sqrt() / 1.5;
        assert!(close(t, Vec3::new(sin_t, -(1.0 - sin_t * sin_t).sqrt(), 0.0)));
        // Normal incidence passes straight through.
        assert!(close(refract(-n, n, 1.0 / 1.5).unwrap(), -n));
    }

    #[test]
    fn total_internal_reflection_past_the_critical_angle() {
        // Leaving glass (eta 1.5): the critical angle is asin(1/1.5) = 41.8 degrees.
        let n = Vec3::new(0.0, 1.0, 0.0);
        let at = |deg: f32| Vec3::new(deg.to_radians().sin(), -deg.to_radians().cos(), 0.0);
        assert!(refract(at(41.0), n, 1.5).is_some());
        assert!(refract(at(42.5), n, 1.5).is_none());
    }

    #[test]
    fn default_intensity_is_sqrt_n_over_2n() {
        let mut scene = crate::scene::Scene::default();
        for _ in 0..4 {
            scene.lights.push(crate::scene::Light::point(Vec3::ZERO, None));
        }
        let l = Lighting::new(&scene.info());
        assert_eq!(l.ambient, Vec3::splat(0.25));
        assert_eq!(l.lights[3].intensity, Vec3::splat(0.25));
    }

    #[test]
    fn schlick_at_normal_and_grazing_incidence() {
        // Normal incidence, air into glass of index 1.5: R0 = (0.5 / 2.5)^2 = 0.04,
        // the same from either side.
        assert!((schlick(1.0, 1.0, 1.0, 1.5) - 0.04).abs() < 1e-6);
        assert!((schlick(1.0, 1.0, 1.5, 1.0) - 0.04).abs() < 1e-6);
        // Grazing incidence reflects everything.
        assert!((schlick(0.0, 0.745, 1.0, 1.5) - 1.0).abs() < 1e-6);
        // At 60 degrees into water (1.33): R0 = (0.33 / 2.33)^2, (1 - 0.5)^5 = 1/32.
        let r0 = (0.33f32 / 2.33).powi(2);
        assert!((schlick(0.5, 0.8, 1.0, 1.33) - (r0 + (1.0 - r0) / 32.0)).abs() < 1e-6);
    }

    #[test]
    fn p3f_glass_splits_by_fresnel_and_absorbs_by_its_colour() {
        let glass = Material {
            color: Vec3::new(1.0, 0.5, 0.25),
            kd: 0.0,
            specular: Vec3::ONE,
            ks: 0.2,
            shine: 20.0,
            t: 1.0,
            ior: 1.5,
            ..Material::DEFAULT
        };
        let n = Vec3::new(0.0, 1.0, 0.0);
        let s = Model::P3f.secondary(&glass, -n, n, true);
        let (dir, tw) = s.refraction.unwrap();
        assert!(close(dir, -n));
        assert!(close(tw, Vec3::new(0.96, 0.48, 0.24)));
        assert_eq!(s.reflection.map(|(k, _)| k), Some(Branch::Reflection));
        assert!(close(s.reflection.unwrap().1, Vec3::splat(0.04)));
        // Leaving past the critical angle: everything goes to the mirror ray.
        let d = Vec3::new(0.8, -0.6, 0.0);
        let s = Model::P3f.secondary(&glass, d, n, false);
        assert_eq!(s.refraction, None);
        assert_eq!(s.reflection, Some((Branch::TotalInternalReflection, Vec3::ONE)));
        // Opaque P3F: a mirror ray of Ks times the specular colour, only if Ks > 0.
        let metal = Material {
            t: 0.0,
            specular: Vec3::new(1.0, 0.5, 0.0),
            ks: 0.5,
            ..glass
        };
        let s = Model::P3f.secondary(&metal, -n, n, true);
        assert_eq!(
            s.reflection,
            Some((Branch::Reflection, Vec3::new(0.5, 0.25, 0.0)))
        );
        let matte = Material { ks: 0.0, ..metal };
        assert_eq!(Model::P3f.secondary(&matte, -n, n, true).reflection, None);
    }
}
