//! The local illumination model and the reflection/refraction directions.
//!
//! For a hit with material `(C, Kd, Ks, shine, T, ior)`, facing normal `n` (the
//! geometric normal turned towards the incoming ray), shading normal `ns`, view
//! direction `v = -d` and point lights of intensity `I_l`:
//!
//! ```text
//! colour = A * Kd * C                                       ambient
//!        + sum over unshadowed lights with dot(n, l) > 0:
//!            I_l * (Kd * C * max(0, ns.l) + Ks * max(0, ns.h)^shine)   Lambert + Blinn-Phong,
//!                                                                       h = normalize(l + v)
//!        + (Ks + T if total internal reflection) * trace(reflected ray)
//!        + T * trace(refracted ray)
//! ```
//!
//! `A` and every uncoloured light have intensity `sqrt(n) / (2n)` for n lights (the
//! SPD's suggestion; `A = 1` without lights).

use crate::math::Vec3;
use crate::scene::Scene;

/// Light intensities resolved from the scene.
#[derive(Clone, Debug)]
pub struct Lighting {
    /// Ambient intensity.
    pub ambient: Vec3,
    /// Each light's position and intensity.
    pub lights: Vec<(Vec3, Vec3)>,
}

impl Lighting {
    /// Resolves the scene's light intensities (see the module docs).
    pub fn new(scene: &Scene) -> Lighting {
        let n = scene.lights.len();
        let default = if n == 0 {
            1.0
        } else {
            (n as f32).sqrt() / (2.0 * n as f32)
        };
        Lighting {
            ambient: Vec3::splat(default),
            lights: scene
                .lights
                .iter()
                .map(|l| (l.position, l.color.unwrap_or(Vec3::splat(default))))
                .collect(),
        }
    }
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
        let mut scene = Scene::default();
        for _ in 0..4 {
            scene.lights.push(crate::scene::Light {
                position: Vec3::ZERO,
                color: None,
            });
        }
        let l = Lighting::new(&scene);
        assert_eq!(l.ambient, Vec3::splat(0.25));
        assert_eq!(l.lights[3].1, Vec3::splat(0.25));
    }
}
