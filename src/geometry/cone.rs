//! Open cones and cylinders (`c bx by bz br ax ay az ar`), without end caps.
//!
//! The surface is the set of points whose distance to the axis equals the radius
//! interpolated linearly from the base (axial coordinate 0) to the apex (axial
//! coordinate `length`). Both radii negative make the cone inside-only, like a
//! sphere with a negative radius.
//!
//! Precision: like the SPD's spheres, its cylinders and cones can be small and far
//! from the eye. Before solving, the ray origin is moved along the ray to the point
//! closest to the cone's middle (the idea behind "Precision Improvements for
//! Ray/Sphere Intersection", Ray Tracing Gems ch. 7), so the quadratic's
//! coefficients are of the cone's size rather than of the distance to the eye.

use super::{Hit, Surface};
use crate::math::{Aabb, Ray, Vec3};

/// An open cone or cylinder ready for intersection.
///
/// Invariants: `axis` is unit length and `length > 0`, except for a degenerate cone
/// (base = apex) which has `axis = 0`, `length = −1` and is never hit; radii are
/// non-negative; the radius at axial coordinate `h` is `base_radius + slope · h`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ConeShape {
    /// Centre of the base disc.
    pub base: Vec3,
    /// Unit vector from the base to the apex.
    pub axis: Vec3,
    /// Distance from the base to the apex.
    pub length: f32,
    /// Radius at the base (absolute value of the NFF radius).
    pub base_radius: f32,
    /// Change of radius per unit of axial distance: `(apex_radius − base_radius) / length`.
    pub slope: f32,
    /// Inside-only: only hits travelling from the inside outwards count, and the
    /// reported normal points inwards.
    pub inside: bool,
}

impl ConeShape {
    /// Builds a cone from the NFF operands. Both radii ≤ 0 (and not both 0) make it
    /// inside-only; radii of opposite signs are taken by absolute value and the cone
    /// is visible from outside (as the parser announces in its warning).
    pub fn new(base: Vec3, base_radius: f32, apex: Vec3, apex_radius: f32) -> ConeShape {
        let v = apex - base;
        let len = v.length();
        let (br, ar) = (base_radius.abs(), apex_radius.abs());
        let inside = base_radius <= 0.0 && apex_radius <= 0.0 && (br > 0.0 || ar > 0.0);
        if !(len > 0.0 && len.is_finite()) {
            return ConeShape {
                base,
                axis: Vec3::ZERO,
                length: -1.0,
                base_radius: br,
                slope: 0.0,
                inside,
            };
        }
        ConeShape {
            base,
            axis: v * (1.0 / len),
            length: len,
            base_radius: br,
            slope: (ar - br) / len,
            inside,
        }
    }

    /// Radius at the apex.
    #[inline]
    pub fn apex_radius(&self) -> f32 {
        self.base_radius + self.slope * self.length.max(0.0)
    }

    /// Centre of the apex disc.
    #[inline]
    pub fn apex(&self) -> Vec3 {
        self.base + self.axis * self.length.max(0.0)
    }

    /// Bounding box: the union of the boxes of the two end discs.
    pub fn bounds(&self) -> Aabb {
        self.disc_bounds(self.base, self.base_radius)
            .union(self.disc_bounds(self.apex(), self.apex_radius()))
    }

    /// Bounding box of the part of the side between the axial distances `from` and
    /// `to` (`0 ≤ from < to ≤ length`): the union of the boxes of the discs there,
    /// widened by 2^-16 of its coordinates' magnitude so that it also holds every
    /// computed hit on that part (the disc centres and radii here, and the hit points
    /// of [`ConeShape::intersect`], are each a few roundings off the exact ones).
    pub fn piece_bounds(&self, from: f32, to: f32) -> Aabb {
        let disc = |s: f32| self.disc_bounds(self.base + self.axis * s, self.base_radius + self.slope * s);
        let b = disc(from).union(disc(to));
        let magnitude = b.min.abs().max(b.max.abs()).max(b.max - b.min);
        let pad = magnitude * (1.0 / 65536.0);
        Aabb::new(b.min - pad, b.max + pad)
    }

    /// Bounding box of the disc of radius `r` around `centre` across the axis: a
    /// disc of radius r and unit normal w reaches r·√(1 − w_i²) along axis i.
    fn disc_bounds(&self, centre: Vec3, r: f32) -> Aabb {
        Aabb::of_disc(centre, self.axis, r)
    }

    /// Phase one: the nearest hit with `0 < t < t_max` whose axial coordinate lies in
    /// `[0, length]` (for an inside-only cone, the nearest hit leaving the cone).
    #[inline]
    pub fn intersect(&self, ray: &Ray, t_max: f32) -> Option<Hit> {
        let d = ray.dir;
        let w = self.axis;
        let s = self.slope;
        // Quick rejection, without a division: a ray whose line passes farther from the
        // axis line than the larger radius misses. That distance is |g| / |d × w| with
        // g = (base − o)·(d × w); the margin (1e-4 of the coordinates involved) is far
        // above the rounding of these products, so no ray the full test below would
        // hit is rejected. Rays parallel to the axis (d × w = 0) always pass.
        let to_base = self.base - ray.origin;
        let n = d.cross(w);
        let g = to_base.dot(n);
        let reach =
            self.base_radius.max(self.apex_radius()) + 1e-4 * (to_base.abs().max_elem() + self.length.abs());
        if g * g > reach * reach * n.length_squared() {
            return None;
        }
        // Shift the origin to the ray's point closest to the cone's middle; t = t_c + τ.
        let mid = self.base + w * (0.5 * self.length);
        let t_c = (mid - ray.origin).dot(d) / d.length_squared();
        if !t_c.is_finite() {
            return None;
        }
        // Cone frame: f is the shifted origin relative to the base; the `_w` parts are
        // axial coordinates and the `_p` parts the components perpendicular to the axis.
        let f = ray.at(t_c) - self.base;
        let (f_w, d_w) = (f.dot(w), d.dot(w));
        let (f_p, d_p) = (f - w * f_w, d - w * d_w);
        // |f_p + τ d_p|² = (r0 + s d_w τ)², r0 the radius at the shifted origin's level:
        // A τ² + 2 B τ + C = 0.
        let r0 = self.base_radius + s * f_w;
        let a = d_p.length_squared() - s * s * d_w * d_w;
        let b = f_p.dot(d_p) - s * d_w * r0;
        let c = f_p.length_squared() - r0 * r0;
        let disc = b * b - a * c;
        if disc < 0.0 || disc.is_nan() {
            return None;
        }
        // Stable roots (Numerical Recipes §5.6): q = −(B + sign(B)√disc), τ = C/q, q/A.
        // With A = 0 (ray parallel to a generator) C/q is the single root; NaNs and
        // infinities from q = 0 or A = 0 fail the range tests below.
        let q = -(b + disc.sqrt().copysign(b));
        let (x0, x1) = (c / q, q / a);
        for tau in [x0.min(x1), x0.max(x1)] {
            let t = t_c + tau;
            let h = f_w + tau * d_w;
            // Half the derivative of |q|² − r² along the ray: > 0 where the ray leaves.
            let leaving = a * tau + b > 0.0;
            if t > 0.0 && t < t_max && h >= 0.0 && h <= self.length && (!self.inside || leaving) {
                return Some(Hit {
                    t,
                    u: 0.0,
                    v: 0.0,
                    part: 0,
                });
            }
        }
        None
    }

    /// Phase two: hit point and unit normal (outward, tilted by the slope; inward if
    /// inside-only).
    #[inline]
    pub fn surface(&self, ray: &Ray, hit: &Hit) -> Surface {
        let point = ray.at(hit.t);
        let w = self.axis;
        let f = point - self.base;
        let radial = (f - w * f.dot(w)).normalize();
        // Gradient of |q|² − r(h)², q the radial vector: 2(q − r s w) = 2r(q̂ − s w).
        let mut n = (radial - w * self.slope).normalize();
        if radial == Vec3::ZERO || n == Vec3::ZERO {
            // At the tip of a pointed cone: the axis direction pointing out of the tip.
            n = if self.slope > 0.0 { -w } else { w };
            if n == Vec3::ZERO {
                n = Vec3::new(0.0, 0.0, 1.0);
            }
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

    fn close(a: f32, b: f32) -> bool {
        (a - b).abs() <= 1e-5 * (1.0 + b.abs())
    }

    fn close_v(a: Vec3, b: Vec3) -> bool {
        close(a.x, b.x) && close(a.y, b.y) && close(a.z, b.z)
    }

    /// The cylinder of radius 1 around the z axis, from z = 0 to z = 2.
    fn cylinder(r: f32) -> ConeShape {
        ConeShape::new(Vec3::ZERO, r, Vec3::new(0.0, 0.0, 2.0), r)
    }

    fn x_ray(y: f32, z: f32) -> Ray {
        Ray::new(Vec3::new(-5.0, y, z), Vec3::new(1.0, 0.0, 0.0))
    }

    /// Rays crossing a diagonal cylinder at right angles, just inside and just outside
    /// its radius (the quick rejection must keep the first, the full test drop the
    /// second). Hand computation: a ray at distance e < r from the axis, perpendicular
    /// to it, enters at t = 5 − √(r² − e²).
    #[test]
    fn grazing_rays_past_a_diagonal_cylinder() {
        let r = 0.07;
        let c = ConeShape::new(Vec3::ZERO, r, Vec3::new(1.0, 1.0, 0.0), r);
        let side = Vec3::new(1.0, -1.0, 0.0).normalize();
        for e in [0.0, 0.5 * r, 0.99 * r, 0.999 * r] {
            let ray = Ray::new(Vec3::new(0.5, 0.5, -5.0) + side * e, Vec3::new(0.0, 0.0, 1.0));
            let hit = c.intersect(&ray, INF).expect("inside the radius");
            let expected = 5.0 - (r * r - e * e).sqrt();
            assert!((hit.t - expected).abs() < 1e-4, "e {e}: {} vs {expected}", hit.t);
        }
        for e in [1.001 * r, 1.01 * r, 2.0 * r, 100.0 * r] {
            let ray = Ray::new(Vec3::new(0.5, 0.5, -5.0) + side * e, Vec3::new(0.0, 0.0, 1.0));
            assert!(c.intersect(&ray, INF).is_none(), "e {e}");
        }
    }

    #[test]
    fn cylinder_hit_from_outside() {
        let c = cylinder(1.0);
        assert_eq!(c.slope, 0.0);
        let ray = x_ray(0.0, 1.0);
        let h = c.intersect(&ray, INF).unwrap();
        assert!(close(h.t, 4.0));
        let sf = c.surface(&ray, &h);
        assert!(close_v(sf.point, Vec3::new(-1.0, 0.0, 1.0)));
        assert!(close_v(sf.normal, Vec3::new(-1.0, 0.0, 0.0)));
        assert_eq!(sf.shading_normal, sf.normal);
        // Oblique: at y = 0.6 the wall is at x = −0.8.
        let ray = x_ray(0.6, 0.5);
        let h = c.intersect(&ray, INF).unwrap();
        assert!(close(h.t, 4.2));
        assert!(close_v(c.surface(&ray, &h).normal, Vec3::new(-0.8, 0.6, 0.0)));
    }

    #[test]
    fn cylinder_hit_from_inside_and_through_the_open_end() {
        let c = cylinder(1.0);
        let ray = Ray::new(Vec3::new(0.0, 0.0, 1.0), Vec3::new(1.0, 0.0, 0.0));
        let h = c.intersect(&ray, INF).unwrap();
        assert!(close(h.t, 1.0));
        assert!(close_v(c.surface(&ray, &h).normal, Vec3::new(1.0, 0.0, 0.0)));
        // In through the open top (z = 2 at x = 0.5), onto the inner wall at z = 1.
        let ray = Ray::new(Vec3::new(0.0, 0.0, 3.0), Vec3::new(0.5, 0.0, -1.0));
        let h = c.intersect(&ray, INF).unwrap();
        assert!(close(h.t, 2.0));
        let sf = c.surface(&ray, &h);
        assert!(close_v(sf.point, Vec3::new(1.0, 0.0, 1.0)));
        assert!(close_v(sf.normal, Vec3::new(1.0, 0.0, 0.0)));
        // Down the axis: no caps, no hit.
        let ray = Ray::new(Vec3::new(0.0, 0.0, 5.0), Vec3::new(0.0, 0.0, -1.0));
        assert_eq!(c.intersect(&ray, INF), None);
    }

    #[test]
    fn cylinder_misses_beyond_its_ends_and_beside_it() {
        let c = cylinder(1.0);
        assert_eq!(c.intersect(&x_ray(0.0, 2.5), INF), None);
        assert_eq!(c.intersect(&x_ray(0.0, -0.5), INF), None);
        assert_eq!(c.intersect(&x_ray(1.5, 1.0), INF), None);
    }

    #[test]
    fn grazing_ray_touches_once() {
        let c = cylinder(1.0);
        let h = c.intersect(&x_ray(1.0, 1.0), INF).unwrap();
        assert!(close(h.t, 5.0));
        assert_eq!(c.intersect(&x_ray(1.001, 1.0), INF), None);
    }

    #[test]
    fn behind_origin_and_t_max() {
        let c = cylinder(1.0);
        let ray = Ray::new(Vec3::new(5.0, 0.0, 1.0), Vec3::new(1.0, 0.0, 0.0));
        assert_eq!(c.intersect(&ray, INF), None);
        let ray = x_ray(0.0, 1.0);
        assert_eq!(c.intersect(&ray, 4.0), None);
        assert!(c.intersect(&ray, 4.01).is_some());
    }

    #[test]
    fn pointed_cone_hit_and_normal() {
        // Radius 1 at z = 0 narrowing to a point at z = 1 (slope −1).
        let c = ConeShape::new(Vec3::ZERO, 1.0, Vec3::new(0.0, 0.0, 1.0), 0.0);
        assert!(close(c.slope, -1.0));
        let ray = x_ray(0.0, 0.5);
        let h = c.intersect(&ray, INF).unwrap();
        // Radius 0.5 at z = 0.5.
        assert!(close(h.t, 4.5));
        let sf = c.surface(&ray, &h);
        assert!(close_v(sf.point, Vec3::new(-0.5, 0.0, 0.5)));
        let k = 0.5f32.sqrt();
        assert!(close_v(sf.normal, Vec3::new(-k, 0.0, k)));
        // The other nappe of the double cone (above the tip) and below the base: miss.
        assert_eq!(c.intersect(&x_ray(0.0, 1.5), INF), None);
        assert_eq!(c.intersect(&x_ray(0.0, -0.5), INF), None);
        // Straight down onto the tip.
        let ray = Ray::new(Vec3::new(0.0, 0.0, 3.0), Vec3::new(0.0, 0.0, -1.0));
        if let Some(h) = c.intersect(&ray, INF) {
            let n = c.surface(&ray, &h).normal;
            assert!(close(n.length(), 1.0));
        }
    }

    #[test]
    fn truncated_cone_along_x_normal_at_known_point() {
        // Radius 2 at x = 0 to radius 1 at x = 4: slope −1/4.
        let c = ConeShape::new(Vec3::ZERO, 2.0, Vec3::new(4.0, 0.0, 0.0), 1.0);
        let ray = Ray::new(Vec3::new(2.0, 5.0, 0.0), Vec3::new(0.0, -1.0, 0.0));
        let h = c.intersect(&ray, INF).unwrap();
        // Radius 1.5 at x = 2.
        assert!(close(h.t, 3.5));
        let sf = c.surface(&ray, &h);
        assert!(close_v(sf.point, Vec3::new(2.0, 1.5, 0.0)));
        // Outward normal ∝ (slope-tilt 1/4 along +x, 1 radially).
        let n = Vec3::new(0.25, 1.0, 0.0).normalize();
        assert!(close_v(sf.normal, n));
    }

    #[test]
    fn inside_only_cylinder_takes_exits_and_points_inward() {
        let c = cylinder(-1.0);
        assert!(c.inside);
        let ray = x_ray(0.0, 1.0);
        let h = c.intersect(&ray, INF).unwrap();
        // The entry at x = −1 does not count; the exit at x = 1 does.
        assert!(close(h.t, 6.0));
        let sf = c.surface(&ray, &h);
        assert!(close_v(sf.point, Vec3::new(1.0, 0.0, 1.0)));
        assert!(close_v(sf.normal, Vec3::new(-1.0, 0.0, 0.0)));
        let ray = Ray::new(Vec3::new(0.0, 0.0, 1.0), Vec3::new(0.0, 1.0, 0.0));
        let h = c.intersect(&ray, INF).unwrap();
        assert!(close(h.t, 1.0));
        assert!(close_v(c.surface(&ray, &h).normal, Vec3::new(0.0, -1.0, 0.0)));
        // Leaving the cylinder outward from outside: nothing.
        let ray = Ray::new(Vec3::new(2.0, 0.0, 1.0), Vec3::new(1.0, 0.0, 0.0));
        assert_eq!(c.intersect(&ray, INF), None);
    }

    #[test]
    fn inside_only_cone_with_a_zero_radius() {
        let c = ConeShape::new(Vec3::ZERO, -1.0, Vec3::new(0.0, 0.0, 1.0), 0.0);
        assert!(c.inside);
        let ray = x_ray(0.0, 0.5);
        let h = c.intersect(&ray, INF).unwrap();
        assert!(close(h.t, 5.5));
        let k = 0.5f32.sqrt();
        assert!(close_v(c.surface(&ray, &h).normal, Vec3::new(-k, 0.0, -k)));
        // Opposite signs: visible from outside.
        assert!(!ConeShape::new(Vec3::ZERO, -1.0, Vec3::new(0.0, 0.0, 1.0), 1.0).inside);
    }

    #[test]
    fn thin_far_cylinder_is_hit_in_f32() {
        // Radius 0.001, 1000 units away, across the ray.
        let base = Vec3::new(0.0, -1.0, -1000.0);
        let c = ConeShape::new(base, 0.001, Vec3::new(0.0, 1.0, -1000.0), 0.001);
        let dir = Vec3::new(0.0, 0.0, -1.0);
        let h = c.intersect(&Ray::new(Vec3::ZERO, dir), INF).unwrap();
        assert!((h.t - 999.999).abs() < 1e-3);
        assert!(c
            .intersect(&Ray::new(Vec3::new(0.0005, 0.0, 0.0), dir), INF)
            .is_some());
        assert_eq!(
            c.intersect(&Ray::new(Vec3::new(0.0015, 0.0, 0.0), dir), INF),
            None
        );
    }

    #[test]
    fn degenerate_input_never_hits_or_panics() {
        let c = ConeShape::new(Vec3::ZERO, 1.0, Vec3::ZERO, 1.0);
        assert_eq!(c.intersect(&x_ray(0.0, 0.0), INF), None);
        let c = cylinder(1.0);
        assert_eq!(c.intersect(&Ray::new(Vec3::ZERO, Vec3::ZERO), INF), None);
    }

    #[test]
    fn bounds_of_cylinder_and_tilted_cone() {
        assert_eq!(
            cylinder(-1.0).bounds(),
            Aabb::new(Vec3::new(-1.0, -1.0, 0.0), Vec3::new(1.0, 1.0, 2.0))
        );
        // Axis along (1,1,0)/√2: each disc reaches r/√2 in x and y, r in z.
        let c = ConeShape::new(Vec3::ZERO, 1.0, Vec3::new(1.0, 1.0, 0.0), 0.5);
        let b = c.bounds();
        let k = 0.5f32.sqrt();
        assert!(close_v(b.min, Vec3::new(-k, -k, -1.0)));
        assert!(close_v(b.max, Vec3::new(1.0 + 0.5 * k, 1.0 + 0.5 * k, 1.0)));
    }
}
