//! A ray with its precomputed reciprocal direction (for the slab test).

use super::Vec3;

/// A half-line `origin + t * dir`, `t >= 0`.
#[derive(Clone, Copy, Debug)]
pub struct Ray {
    /// Where the ray starts (world space).
    pub origin: Vec3,
    /// Direction; not necessarily unit length, though the renderer keeps it so.
    pub dir: Vec3,
    /// Component-wise `1 / dir` (infinite where `dir` is zero), for box tests.
    pub inv_dir: Vec3,
}

impl Ray {
    /// Builds a ray and precomputes its reciprocal direction.
    #[inline]
    pub fn new(origin: Vec3, dir: Vec3) -> Ray {
        debug_assert!(origin.is_finite() && dir.is_finite());
        Ray {
            origin,
            dir,
            inv_dir: Vec3::new(1.0 / dir.x, 1.0 / dir.y, 1.0 / dir.z),
        }
    }

    /// The point at parameter `t`.
    #[inline]
    pub fn at(&self, t: f32) -> Vec3 {
        self.origin + self.dir * t
    }
}
