//! Spheres (`s cx cy cz r`), including the inside-only variant (negative radius).
//!
//! The quadratic is solved in the form of Haines, Günther, Wald and Akenine-Möller,
//! "Precision Improvements for Ray/Sphere Intersection" (Ray Tracing Gems, ch. 7):
//! the discriminant is taken from the distance between the centre and the ray's
//! closest point rather than from `b² − 4ac`, and the two roots come from
//! `q = b' + sign(b')·√Δ` as `c/q` and `q/a`. The SPD's spheres can be tiny (radius
//! ~0.0006) and far from the eye, where the textbook form loses every significant
//! digit of the discriminant in `f32`.

use super::{Hit, Surface};
use crate::math::{Aabb, Ray, Vec3};

/// A sphere ready for intersection.
///
/// Invariant: `radius2 = r²` and `inv_radius = 1/|r|` for the radius `r` it was built
/// from; `inside` is true when `r < 0` (only the inside is visible).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SphereShape {
    /// Centre (world space).
    pub center: Vec3,
    /// Squared radius.
    pub radius2: f32,
    /// Reciprocal of the (absolute) radius, to scale `p − centre` to a unit normal.
    pub inv_radius: f32,
    /// Inside-only: only hits travelling from the inside outwards count, and the
    /// reported normal points inwards.
    pub inside: bool,
}

impl SphereShape {
    /// Builds a sphere from the NFF centre and signed radius (negative: inside-only).
    pub fn new(center: Vec3, radius: f32) -> SphereShape {
        let r = radius.abs();
        SphereShape {
            center,
            radius2: r * r,
            inv_radius: 1.0 / r,
            inside: radius < 0.0,
        }
    }

    /// The (absolute) radius.
    #[inline]
    pub fn radius(&self) -> f32 {
        self.radius2.sqrt()
    }

    /// Bounding box.
    #[inline]
    pub fn bounds(&self) -> Aabb {
        let r = Vec3::splat(self.radius());
        Aabb::new(self.center - r, self.center + r)
    }

    /// Phase one: the nearest hit with `0 < t < t_max` (for an inside-only sphere, the
    /// nearest hit leaving the sphere).
    #[inline]
    pub fn intersect(&self, ray: &Ray, t_max: f32) -> Option<Hit> {
        let d = ray.dir;
        // f: from the centre to the ray origin (object space, unscaled).
        let f = ray.origin - self.center;
        let a = d.length_squared();
        // b' = −f·d, so the roots are t = (b' ± √(a·Δ)) / a.
        let b = -f.dot(d);
        // RTG ch. 7 eq. 7.5: Δ = r² − |f + (b'/a) d|², where f + (b'/a) d runs from
        // the centre to the point of the ray's line closest to it.
        let l = f + d * (b / a);
        let disc = self.radius2 - l.length_squared();
        // NaN comes from a zero direction.
        if disc < 0.0 || disc.is_nan() {
            return None;
        }
        let c = f.length_squared() - self.radius2;
        // RTG ch. 7 eq. 7.6 / Numerical Recipes: q = b' + sign(b')·√(a·Δ), roots c/q and q/a.
        let q = b + (a * disc).sqrt().copysign(b);
        let (r0, r1) = (c / q, q / a);
        // f32::min/max drop a NaN (q = 0 only for a tangent at the origin, t = 0).
        let (t0, t1) = (r0.min(r1), r0.max(r1));
        if !self.inside && t0 > 0.0 && t0 < t_max {
            return Some(Hit {
                t: t0,
                u: 0.0,
                v: 0.0,
                part: 0,
            });
        }
        // The far root is where the ray leaves the sphere; an inside-only sphere takes
        // it only when the ray truly crosses (a tangent has dot(dir, n) = 0).
        if t1 > 0.0 && t1 < t_max && !(self.inside && disc == 0.0) {
            return Some(Hit {
                t: t1,
                u: 0.0,
                v: 0.0,
                part: 0,
            });
        }
        None
    }

    /// Phase two: hit point and unit normal (outward; inward if inside-only).
    #[inline]
    pub fn surface(&self, ray: &Ray, hit: &Hit) -> Surface {
        let point = ray.at(hit.t);
        let mut n = ((point - self.center) * self.inv_radius).normalize();
        if n == Vec3::ZERO {
            // Only reachable through rounding on a degenerate sphere: any unit vector.
            n = Vec3::new(0.0, 0.0, 1.0);
        }
        if self.inside {
            n = -n;
        }
        Surface {
            point,
            normal: n,
            shading_normal: n,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    const INF: f32 = f32::INFINITY;

    fn close(a: f32, b: f32, tol: f32) -> bool {
        (a - b).abs() <= tol * (1.0 + b.abs())
    }

    fn close_v(a: Vec3, b: Vec3, tol: f32) -> bool {
        close(a.x, b.x, tol) && close(a.y, b.y, tol) && close(a.z, b.z, tol)
    }

    fn unit() -> SphereShape {
        SphereShape::new(Vec3::new(1.0, 2.0, 3.0), 2.0)
    }

    #[test]
    fn hit_from_outside_gives_near_root_point_and_normal() {
        let s = unit();
        let ray = Ray::new(Vec3::new(1.0, 2.0, -7.0), Vec3::new(0.0, 0.0, 1.0));
        let h = s.intersect(&ray, INF).unwrap();
        // Centre z = 3, radius 2: entry at z = 1, 8 units from z = -7.
        assert!(close(h.t, 8.0, 1e-6));
        let sf = s.surface(&ray, &h);
        assert!(close_v(sf.point, Vec3::new(1.0, 2.0, 1.0), 1e-6));
        assert!(close_v(sf.normal, Vec3::new(0.0, 0.0, -1.0), 1e-6));
        assert_eq!(sf.shading_normal, sf.normal);
    }

    #[test]
    fn non_unit_direction_scales_t() {
        let s = unit();
        let ray = Ray::new(Vec3::new(1.0, 2.0, -7.0), Vec3::new(0.0, 0.0, 4.0));
        assert!(close(s.intersect(&ray, INF).unwrap().t, 2.0, 1e-6));
    }

    #[test]
    fn hit_from_inside_gives_exit_point() {
        let s = unit();
        let ray = Ray::new(Vec3::new(1.0, 2.0, 3.0), Vec3::new(1.0, 0.0, 0.0));
        let h = s.intersect(&ray, INF).unwrap();
        assert!(close(h.t, 2.0, 1e-6));
        let sf = s.surface(&ray, &h);
        assert!(close_v(sf.normal, Vec3::new(1.0, 0.0, 0.0), 1e-6));
    }

    #[test]
    fn oblique_hit_matches_pythagoras() {
        // Unit sphere at the origin, ray along x at height y = 0.6: enters at x = -0.8.
        let s = SphereShape::new(Vec3::ZERO, 1.0);
        let ray = Ray::new(Vec3::new(-5.0, 0.6, 0.0), Vec3::new(1.0, 0.0, 0.0));
        let h = s.intersect(&ray, INF).unwrap();
        assert!(close(h.t, 4.2, 1e-6));
        let n = s.surface(&ray, &h).normal;
        assert!(close_v(n, Vec3::new(-0.8, 0.6, 0.0), 1e-6));
    }

    #[test]
    fn grazing_and_miss() {
        let s = SphereShape::new(Vec3::ZERO, 1.0);
        // Tangent at (0, 1, 0): a double root at t = 5.
        let graze = Ray::new(Vec3::new(-5.0, 1.0, 0.0), Vec3::new(1.0, 0.0, 0.0));
        let h = s.intersect(&graze, INF).unwrap();
        assert!(close(h.t, 5.0, 1e-6));
        let miss = Ray::new(Vec3::new(-5.0, 1.001, 0.0), Vec3::new(1.0, 0.0, 0.0));
        assert_eq!(s.intersect(&miss, INF), None);
    }

    #[test]
    fn sphere_behind_origin_is_rejected() {
        let s = unit();
        let ray = Ray::new(Vec3::new(1.0, 2.0, 10.0), Vec3::new(0.0, 0.0, 1.0));
        assert_eq!(s.intersect(&ray, INF), None);
    }

    #[test]
    fn t_max_cuts_off() {
        let s = unit();
        let ray = Ray::new(Vec3::new(1.0, 2.0, -7.0), Vec3::new(0.0, 0.0, 1.0));
        assert_eq!(s.intersect(&ray, 8.0), None);
        assert_eq!(s.intersect(&ray, 7.9), None);
        assert!(s.intersect(&ray, 8.1).is_some());
    }

    #[test]
    fn inside_only_sphere_takes_exit_and_points_inward() {
        let s = SphereShape::new(Vec3::ZERO, -2.0);
        assert!(s.inside);
        // From outside: the entry (t = 3) does not count, the exit (t = 7) does.
        let ray = Ray::new(Vec3::new(-5.0, 0.0, 0.0), Vec3::new(1.0, 0.0, 0.0));
        let h = s.intersect(&ray, INF).unwrap();
        assert!(close(h.t, 7.0, 1e-6));
        let sf = s.surface(&ray, &h);
        assert!(close_v(sf.point, Vec3::new(2.0, 0.0, 0.0), 1e-6));
        assert!(close_v(sf.normal, Vec3::new(-1.0, 0.0, 0.0), 1e-6));
        // From inside: the exit.
        let ray = Ray::new(Vec3::ZERO, Vec3::new(0.0, -1.0, 0.0));
        let h = s.intersect(&ray, INF).unwrap();
        assert!(close(h.t, 2.0, 1e-6));
        assert!(close_v(
            s.surface(&ray, &h).normal,
            Vec3::new(0.0, 1.0, 0.0),
            1e-6
        ));
        // Past the exit: nothing; and t_max before the exit: nothing.
        assert_eq!(s.intersect(&ray, 1.5), None);
        let away = Ray::new(Vec3::new(3.0, 0.0, 0.0), Vec3::new(1.0, 0.0, 0.0));
        assert_eq!(s.intersect(&away, INF), None);
    }

    #[test]
    fn tiny_far_sphere_is_hit_in_f32() {
        // An SPD-sized sphere (r = 0.0006) 1000 units away: the textbook b² − 4ac
        // cancels completely in f32 here.
        let c = Vec3::new(0.0, 0.0, -1000.0);
        let s = SphereShape::new(c, 0.0006);
        let ray = Ray::new(Vec3::ZERO, Vec3::new(0.0, 0.0, -1.0));
        let h = s.intersect(&ray, INF).unwrap();
        assert!(close(h.t, 999.9994, 1e-6));
        // Half a radius off-axis still hits; 1.5 radii off misses.
        let ray = Ray::new(Vec3::new(0.0003, 0.0, 0.0), Vec3::new(0.0, 0.0, -1.0));
        assert!(s.intersect(&ray, INF).is_some());
        let ray = Ray::new(Vec3::new(0.0009, 0.0, 0.0), Vec3::new(0.0, 0.0, -1.0));
        assert_eq!(s.intersect(&ray, INF), None);
    }

    #[test]
    fn axis_aligned_and_zero_direction_rays_do_not_produce_nan() {
        let s = SphereShape::new(Vec3::ZERO, 1.0);
        let ray = Ray::new(Vec3::new(0.0, 0.0, -3.0), Vec3::new(0.0, 0.0, 1.0));
        assert!(close(s.intersect(&ray, INF).unwrap().t, 2.0, 1e-6));
        let zero = Ray::new(Vec3::new(0.0, 0.0, -3.0), Vec3::ZERO);
        assert_eq!(s.intersect(&zero, INF), None);
    }

    #[test]
    fn bounds_enclose_the_sphere() {
        let b = SphereShape::new(Vec3::new(1.0, 2.0, 3.0), -0.5).bounds();
        assert_eq!(b, Aabb::new(Vec3::new(0.5, 1.5, 2.5), Vec3::new(1.5, 2.5, 3.5)));
    }
}
