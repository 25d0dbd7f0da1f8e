//! Optics of a smooth interface and of a transmissive volume: mirror reflection,
//! Snell refraction, Schlick's Fresnel reflectance, Beer-Lambert absorption. The
//! shading rules and the integrators build on them.

use crate::math::Vec3;

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

/// The fraction of light left after `distance` through a medium of absorption
/// coefficient `sigma` per unit length (per channel): Beer-Lambert,
/// `exp(-sigma distance)`.
#[inline]
pub fn beer_lambert(sigma: Vec3, distance: f32) -> Vec3 {
    Vec3::new(
        (-sigma.x * distance).exp(),
        (-sigma.y * distance).exp(),
        (-sigma.z * distance).exp(),
    )
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
    fn beer_lambert_halves_at_ln2_over_sigma() {
        let sigma = Vec3::new(0.0, 1.0, 2.0);
        let t = beer_lambert(sigma, std::f32::consts::LN_2);
        assert!(close(t, Vec3::new(1.0, 0.5, 0.25)), "{t:?}");
        assert_eq!(beer_lambert(sigma, 0.0), Vec3::ONE);
    }
}
