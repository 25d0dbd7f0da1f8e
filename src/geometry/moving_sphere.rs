//! Moving spheres (P3F `sm cx0 cy0 cz0  cx1 cy1 cz1  r  t0 t1`): a sphere whose centre
//! moves in a straight line at constant speed, intersected at the ray's time.
//!
//! The centre at time `t` is `c0 + (t - t0) v`, `v = (c1 - c0) / (t1 - t0)`, computed
//! as [`MovingSphere::center_at`] computes it (so the scene's bounds and the
//! shape's agree to the bit). The shape is built for one shutter interval
//! `[open, close]`: its bounds are the union of the sphere at `open` and at `close`,
//! which holds it at every time in between (each coordinate of the centre is a
//! correctly rounded, hence monotonic, function of `t`). A ray time outside the
//! shutter is clamped to it: the sphere stands where it is when the shutter opens
//! (before) or closes (after), so it never leaves the box the BVH files it in and
//! the BVH finds what a scan of the primitives finds at every time. Eye rays sample
//! times within the shutter, so this only decides what stray times mean.
//!
//! At its time the sphere is a [`SphereShape`], intersected and shaded by the very
//! same arithmetic (inside-only for a negative radius, as `s`).

use super::{Hit, SphereShape, Surface};
use crate::math::{Aabb, Ray, Vec3};
use crate::scene::MovingSphere;

/// A moving sphere ready for intersection.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct MovingSphereShape {
    /// The sphere at `time0` (centre `c0`), radius and side as for a still sphere.
    pub sphere: SphereShape,
    /// The centre's displacement per unit of time.
    pub velocity: Vec3,
    /// The time at which the centre is `sphere.center`.
    pub time0: f32,
    /// The shutter interval `[open, close]` the shape was built for; ray times are
    /// clamped into it.
    pub shutter: [f32; 2],
}

impl MovingSphereShape {
    /// The shape of `m` for a camera whose shutter is open over `shutter`
    /// (`[open, close]`, `open <= close`).
    pub fn new(m: &MovingSphere, shutter: [f32; 2]) -> MovingSphereShape {
        debug_assert!(shutter[0] <= shutter[1], "shutter {shutter:?}");
        MovingSphereShape {
            sphere: SphereShape::new(m.center0, m.radius),
            velocity: m.velocity(),
            time0: m.time0,
            shutter,
        }
    }

    /// The centre at `time`, clamped into the shutter (see the module docs).
    #[inline]
    pub fn center_at(&self, time: f32) -> Vec3 {
        // max then min, not `clamp`: no panic for a reversed interval, and a NaN
        // time becomes the opening time.
        let t = time.max(self.shutter[0]).min(self.shutter[1]);
        self.sphere.center + self.velocity * (t - self.time0)
    }

    /// The still sphere at `time`.
    #[inline]
    fn at(&self, time: f32) -> SphereShape {
        SphereShape {
            center: self.center_at(time),
            ..self.sphere
        }
    }

    /// Bounding box over the shutter: the sphere at its opening and at its closing.
    #[inline]
    pub fn bounds(&self) -> Aabb {
        let [open, close] = self.shutter;
        self.at(open).bounds().union(self.at(close).bounds())
    }

    /// Phase one: the nearest hit with `0 < t < t_max` of the sphere at the ray's time.
    #[inline]
    pub fn intersect(&self, ray: &Ray, t_max: f32) -> Option<Hit> {
        self.at(ray.time).intersect(ray, t_max)
    }

    /// Phase two: hit point and unit normal of the sphere at the ray's time.
    #[inline]
    pub fn surface(&self, ray: &Ray, hit: &Hit) -> Surface {
        self.at(ray.time).surface(ray, hit)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    const INF: f32 = f32::INFINITY;

    /// Centre (1, 0, 0) at t = 0.5 to (3, 0, 0) at t = 1.5 (two units a unit of time,
    /// so (0, 0, 0) at t = 0 and (4, 0, 0) at t = 2), radius `r`, for the shutter.
    fn rolling(r: f32, shutter: [f32; 2]) -> MovingSphereShape {
        let m = MovingSphere {
            center0: Vec3::new(1.0, 0.0, 0.0),
            center1: Vec3::new(3.0, 0.0, 0.0),
            radius: r,
            time0: 0.5,
            time1: 1.5,
            material: 0,
            line: 1,
        };
        MovingSphereShape::new(&m, shutter)
    }

    fn close(a: f32, b: f32) -> bool {
        (a - b).abs() <= 1e-5 * (1.0 + b.abs())
    }

    #[test]
    fn a_ray_meets_the_sphere_where_it_is_at_the_rays_time() {
        let s = rolling(1.0, [0.0, 2.0]);
        // Along +x from x = -10: the near side at x = 2 t - 1, distance 2 t + 9,
        // between the two times and beyond them (t = 0 and 2: extrapolated).
        for time in [0.0f32, 0.5, 0.8, 1.0, 1.5, 2.0] {
            let ray = Ray::with_time(Vec3::new(-10.0, 0.0, 0.0), Vec3::new(1.0, 0.0, 0.0), time);
            let h = s.intersect(&ray, INF).unwrap();
            assert!(close(h.t, 2.0 * time + 9.0), "{time}: {}", h.t);
            let sf = s.surface(&ray, &h);
            assert!((sf.point - Vec3::new(2.0 * time - 1.0, 0.0, 0.0)).length() < 1e-5);
            assert!((sf.normal - Vec3::new(-1.0, 0.0, 0.0)).length() < 1e-6);
        }
        // Across the path at x = 2, along +z from z = -10: the centre passes x = 2 at
        // t = 1 (hit at z = -1), is half a radius off at t = 0.75 (z = -sqrt(3/4)),
        // touches at t = 0.5 and is gone by t = 0.25 and t = 1.6.
        let across = |time| Ray::with_time(Vec3::new(2.0, 0.0, -10.0), Vec3::new(0.0, 0.0, 1.0), time);
        assert!(close(s.intersect(&across(1.0), INF).unwrap().t, 9.0));
        let t = s.intersect(&across(0.75), INF).unwrap().t;
        assert!(close(t, 10.0 - 0.75f32.sqrt()), "{t}");
        for time in [0.25, 1.6] {
            assert_eq!(s.intersect(&across(time), INF), None, "{time}");
        }
        // t_max still cuts off.
        assert_eq!(s.intersect(&across(1.0), 9.0), None);
    }

    #[test]
    fn the_centre_is_the_scenes_to_the_bit_within_the_shutter() {
        let m = MovingSphere {
            center0: Vec3::new(0.1, -0.7, 3.3),
            center1: Vec3::new(2.9, 0.3, -1.1),
            radius: 0.4,
            time0: 0.3,
            time1: 0.7,
            material: 0,
            line: 1,
        };
        let s = MovingSphereShape::new(&m, [0.0, 1.0]);
        for time in [0.0, 0.1, 0.3, 0.5, 0.7, 0.93, 1.0] {
            assert_eq!(s.center_at(time), m.center_at(time), "{time}");
        }
    }

    #[test]
    fn bounds_cover_the_motion_while_the_shutter_is_open() {
        let b = rolling(1.0, [0.0, 2.0]).bounds();
        assert_eq!(
            b,
            Aabb::new(Vec3::new(-1.0, -1.0, -1.0), Vec3::new(5.0, 1.0, 1.0))
        );
        // Over [0.5, 1]: centres 1 to 2.
        let b = rolling(-1.0, [0.5, 1.0]).bounds();
        assert_eq!(b, Aabb::new(Vec3::new(0.0, -1.0, -1.0), Vec3::new(3.0, 1.0, 1.0)));
        // A shutter of one instant: the still sphere then.
        let b = rolling(1.0, [1.0, 1.0]).bounds();
        assert_eq!(b, Aabb::new(Vec3::new(1.0, -1.0, -1.0), Vec3::new(3.0, 1.0, 1.0)));
    }

    #[test]
    fn times_outside_the_shutter_see_the_sphere_where_the_shutter_leaves_it() {
        let s = rolling(1.0, [0.5, 1.0]);
        let along = |time| Ray::with_time(Vec3::new(-10.0, 0.0, 0.0), Vec3::new(1.0, 0.0, 0.0), time);
        // Before the opening: as at t = 0.5 (near side x = 0); after the closing: as
        // at t = 1 (near side x = 1). A NaN time counts as the opening.
        for (time, t) in [
            (-3.0, 10.0),
            (0.0, 10.0),
            (f32::NAN, 10.0),
            (1.5, 11.0),
            (9.0, 11.0),
        ] {
            let h = s.intersect(&along(time), INF).unwrap();
            assert!(close(h.t, t), "{time}: {}", h.t);
        }
    }

    #[test]
    fn an_inside_only_moving_sphere_is_seen_from_within() {
        let s = rolling(-1.0, [0.0, 2.0]);
        // From its centre at t = 1 (x = 2): only the exit, with the normal inwards.
        let ray = Ray::with_time(Vec3::new(2.0, 0.0, 0.0), Vec3::new(0.0, 1.0, 0.0), 1.0);
        let h = s.intersect(&ray, INF).unwrap();
        assert!(close(h.t, 1.0));
        assert!((s.surface(&ray, &h).normal - Vec3::new(0.0, -1.0, 0.0)).length() < 1e-6);
        // From outside, along +x at t = 1: the far side, x = 3 (13 units).
        let ray = Ray::with_time(Vec3::new(-10.0, 0.0, 0.0), Vec3::new(1.0, 0.0, 0.0), 1.0);
        assert!(close(s.intersect(&ray, INF).unwrap().t, 13.0));
    }
}
