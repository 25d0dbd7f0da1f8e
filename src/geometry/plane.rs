//! Infinite planes (`pl x1 y1 z1 x2 y2 z2 x3 y3 z3`, an extension of NFF).
//!
//! Unbounded, so they have no bounding box and stay outside the BVH.

use super::{Hit, Surface};
use crate::math::{Ray, Vec3};

/// An infinite plane ready for intersection.
///
/// Invariant: `normal` is unit length, or zero for collinear input points (such a
/// plane is never hit).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PlaneShape {
    /// A point of the plane (the first point given). Keeping a point rather than an
    /// offset `n · p` keeps precision when the plane is far from the world origin.
    pub point: Vec3,
    /// Unit normal, on the side from which the three points run counter-clockwise.
    pub normal: Vec3,
}

impl PlaneShape {
    /// Builds the plane through three points; the normal is `(p1 − p0) × (p2 − p0)`,
    /// normalized.
    pub fn new(points: [Vec3; 3]) -> PlaneShape {
        let [p0, p1, p2] = points;
        PlaneShape {
            point: p0,
            normal: (p1 - p0).cross(p2 - p0).normalize(),
        }
    }

    /// Phase one: the hit with `0 < t < t_max` (`u`, `v` unused).
    #[inline]
    pub fn intersect(&self, ray: &Ray, t_max: f32) -> Option<Hit> {
        let denom = self.normal.dot(ray.dir);
        if denom == 0.0 {
            return None;
        }
        // n · (o + t d − p) = 0.
        let t = self.normal.dot(self.point - ray.origin) / denom;
        (t > 0.0 && t < t_max).then_some(Hit {
            t,
            u: 0.0,
            v: 0.0,
            part: 0,
        })
    }

    /// Phase two: the hit point and the plane's normal.
    #[inline]
    pub fn surface(&self, ray: &Ray, hit: &Hit) -> Surface {
        Surface {
            point: ray.at(hit.t),
            normal: self.normal,
            shading_normal: self.normal,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    const INF: f32 = f32::INFINITY;

    /// The plane y = −1, counter-clockwise seen from above: normal +y.
    fn floor() -> PlaneShape {
        PlaneShape::new([
            Vec3::new(0.0, -1.0, 0.0),
            Vec3::new(0.0, -1.0, 1.0),
            Vec3::new(1.0, -1.0, 0.0),
        ])
    }

    #[test]
    fn normal_follows_counter_clockwise_order() {
        assert_eq!(floor().normal, Vec3::new(0.0, 1.0, 0.0));
        let p = PlaneShape::new([Vec3::ZERO, Vec3::new(2.0, 0.0, 0.0), Vec3::new(0.0, 3.0, 0.0)]);
        assert_eq!(p.normal, Vec3::new(0.0, 0.0, 1.0));
    }

    #[test]
    fn hit_from_above_and_from_below() {
        let p = floor();
        let ray = Ray::new(Vec3::new(3.0, 4.0, -2.0), Vec3::new(0.0, -2.0, 0.0));
        let h = p.intersect(&ray, INF).unwrap();
        assert_eq!(h.t, 2.5);
        let sf = p.surface(&ray, &h);
        assert_eq!(sf.point, Vec3::new(3.0, -1.0, -2.0));
        assert_eq!(sf.normal, Vec3::new(0.0, 1.0, 0.0));
        assert_eq!(sf.shading_normal, sf.normal);
        // From below (the back side): still a hit, same normal.
        let ray = Ray::new(Vec3::new(0.0, -3.0, 0.0), Vec3::new(0.6, 0.8, 0.0));
        let h = p.intersect(&ray, INF).unwrap();
        assert!((h.t - 2.5).abs() < 1e-6);
        let sf = p.surface(&ray, &h);
        assert!((sf.point.x - 1.5).abs() < 1e-6 && (sf.point.y + 1.0).abs() < 1e-6);
    }

    #[test]
    fn parallel_behind_and_t_max() {
        let p = floor();
        // Grazing: parallel to the plane, in it or above it.
        let ray = Ray::new(Vec3::new(0.0, -1.0, 0.0), Vec3::new(1.0, 0.0, 0.0));
        assert_eq!(p.intersect(&ray, INF), None);
        let ray = Ray::new(Vec3::new(0.0, 1.0, 0.0), Vec3::new(1.0, 0.0, 0.0));
        assert_eq!(p.intersect(&ray, INF), None);
        // Pointing away.
        let ray = Ray::new(Vec3::new(0.0, 1.0, 0.0), Vec3::new(0.0, 1.0, 0.0));
        assert_eq!(p.intersect(&ray, INF), None);
        let ray = Ray::new(Vec3::new(0.0, 1.0, 0.0), Vec3::new(0.0, -1.0, 0.0));
        assert_eq!(p.intersect(&ray, 2.0), None);
        assert!(p.intersect(&ray, 2.5).is_some());
    }

    #[test]
    fn collinear_points_give_a_plane_that_is_never_hit() {
        let p = PlaneShape::new([Vec3::ZERO, Vec3::ONE, Vec3::splat(2.0)]);
        let ray = Ray::new(Vec3::new(0.0, 5.0, 0.0), Vec3::new(0.0, -1.0, 0.0));
        assert_eq!(p.intersect(&ray, INF), None);
    }
}
