//! A ray with its precomputed reciprocal direction (for the slab test) and its time
//! (for moving geometry).

use super::Vec3;

/// A half-line `origin + t * dir`, `t >= 0`.
#[derive(Clone, Copy, Debug)]
pub struct Ray {
    /// Where the ray starts (world space).
    pub origin: Vec3,
    /// Direction; not necessarily unit length (the renderer's eye, reflected and
    /// refracted rays have unit directions, its shadow rays run to the light, which
    /// they reach at t = 1).
    pub dir: Vec3,
    /// Component-wise `1 / dir`, for box tests. Always finite: a zero component of
    /// `dir` is replaced by a tiny one of the same sign first, so the slab test never
    /// computes `0 * inf` and its min/max need no NaN handling.
    pub inv_dir: Vec3,
    /// The time at which the ray sees the scene: moving spheres are where they are at
    /// this time. An eye ray samples it within the camera's shutter; a ray spawned
    /// from another (reflected, refracted, shadow) carries its parent's.
    pub time: f32,
}

impl Ray {
    /// Builds a ray at time 0 and precomputes its reciprocal direction.
    #[inline]
    pub fn new(origin: Vec3, dir: Vec3) -> Ray {
        Ray::with_time(origin, dir, 0.0)
    }

    /// Builds a ray that sees the scene at `time` and precomputes its reciprocal
    /// direction.
    #[inline]
    pub fn with_time(origin: Vec3, dir: Vec3, time: f32) -> Ray {
        debug_assert!(origin.is_finite() && dir.is_finite());
        Ray {
            origin,
            dir,
            inv_dir: Vec3::new(safe_recip(dir.x), safe_recip(dir.y), safe_recip(dir.z)),
            time,
        }
    }

    /// The point at parameter `t`.
    #[inline]
    pub fn at(&self, t: f32) -> Vec3 {
        self.origin + self.dir * t
    }
}

/// Direction components smaller than this in magnitude count as zero in
/// [`Ray::inv_dir`] (they are raised to it, sign kept).
pub const TINY_DIR: f32 = 1e-30;

/// `1 / x`, finite for every finite `x`: tiny magnitudes (including zero) are raised
/// to [`TINY_DIR`] with their sign kept.
#[inline]
pub fn safe_recip(x: f32) -> f32 {
    1.0 / if x.abs() < TINY_DIR {
        TINY_DIR.copysign(x)
    } else {
        x
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn inverse_direction_is_finite_even_for_zero_components() {
        let r = Ray::new(Vec3::ZERO, Vec3::new(0.0, -0.0, 2.0));
        assert!(r.inv_dir.is_finite());
        assert!(r.inv_dir.x > 1e29 && r.inv_dir.y < -1e29);
        assert_eq!(r.inv_dir.z, 0.5);
    }

    #[test]
    fn a_ray_is_at_time_zero_unless_given_one() {
        let (o, d) = (Vec3::new(1.0, 2.0, 3.0), Vec3::new(0.0, 0.0, 2.0));
        assert_eq!(Ray::new(o, d).time, 0.0);
        let r = Ray::with_time(o, d, 0.75);
        assert_eq!(
            (r.origin, r.dir, r.inv_dir, r.time),
            (o, d, Ray::new(o, d).inv_dir, 0.75)
        );
    }
}
