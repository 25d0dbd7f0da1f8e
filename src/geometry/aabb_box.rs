//! Solid axis-aligned boxes (`aabb xmin xmax ymin ymax zmin zmax`, an extension of
//! NFF), intersected with the slab method (Kay and Kajiya, "Ray Tracing Complex
//! Scenes", SIGGRAPH 1986).
//!
//! A ray starting outside meets the face through which it enters; a ray starting
//! inside meets the face through which it leaves. Either way the normal is the
//! face's outward axis normal.

use super::{Hit, Surface};
use crate::math::{Aabb, Ray, Vec3};

/// A solid box ready for intersection. Invariant: `min <= max` component-wise.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct BoxShape {
    /// Lower corner.
    pub min: Vec3,
    /// Upper corner.
    pub max: Vec3,
}

/// Where a ray crosses a box's slabs: entry and exit distances and the axes they
/// come from.
struct Slabs {
    enter: f32,
    enter_axis: usize,
    exit: f32,
    exit_axis: usize,
}

impl BoxShape {
    /// Builds a box from two opposite corners (in any order).
    pub fn new(a: Vec3, b: Vec3) -> BoxShape {
        BoxShape {
            min: a.min(b),
            max: a.max(b),
        }
    }

    /// Bounding box (the box itself).
    #[inline]
    pub fn bounds(&self) -> Aabb {
        Aabb::new(self.min, self.max)
    }

    /// Crosses the three slabs. Where a direction component is zero, the reciprocal is
    /// infinite: the slab distances are ±∞ (the ray never leaves or never enters
    /// that slab), or one of them is NaN (0·∞) when the origin lies exactly on a face
    /// plane. `f32::min`/`max` drop that NaN and keep the other, infinite, distance,
    /// so a ray running exactly within a face's plane misses, on every face alike.
    #[inline]
    fn slabs(&self, ray: &Ray) -> Slabs {
        // The exact reciprocal (infinite for a zero component), not `ray.inv_dir`, which
        // is clamped finite for the BVH and would make face planes asymmetric here.
        let d = ray.dir;
        let inv = Vec3::new(1.0 / d.x, 1.0 / d.y, 1.0 / d.z);
        let t0 = (self.min - ray.origin).mul_elem(inv);
        let t1 = (self.max - ray.origin).mul_elem(inv);
        let mut s = Slabs {
            enter: f32::NEG_INFINITY,
            enter_axis: 0,
            exit: f32::INFINITY,
            exit_axis: 0,
        };
        for i in 0..3 {
            let (near, far) = (t0[i].min(t1[i]), t0[i].max(t1[i]));
            if near > s.enter {
                s.enter = near;
                s.enter_axis = i;
            }
            if far < s.exit {
                s.exit = far;
                s.exit_axis = i;
            }
        }
        s
    }

    /// Phase one: the entry distance if it lies in `(0, t_max)`, else the exit
    /// distance if the origin is inside the box and it lies in `(0, t_max)`.
    #[inline]
    pub fn intersect(&self, ray: &Ray, t_max: f32) -> Option<Hit> {
        let s = self.slabs(ray);
        // Neither is ever NaN: both start infinite and only take non-NaN values.
        if s.enter > s.exit {
            return None;
        }
        let t = if s.enter > 0.0 { s.enter } else { s.exit };
        (t > 0.0 && t < t_max).then_some(Hit {
            t,
            u: 0.0,
            v: 0.0,
            part: 0,
        })
    }

    /// Phase two: the hit point and the outward normal of the face it lies on (the
    /// face is found again by the same slab computation as in phase one).
    #[inline]
    pub fn surface(&self, ray: &Ray, hit: &Hit) -> Surface {
        let s = self.slabs(ray);
        let d = ray.dir.to_array();
        let mut n = [0.0f32; 3];
        if s.enter > 0.0 && hit.t == s.enter {
            // Entering through the face that faces the ray: against the direction.
            n[s.enter_axis] = -d[s.enter_axis].signum();
        } else {
            // Leaving through the face ahead: along the direction.
            n[s.exit_axis] = d[s.exit_axis].signum();
        }
        let normal = Vec3::from_array(n);
        Surface {
            point: ray.at(hit.t),
            normal,
            shading_normal: normal,
        }
    }
}

impl BoxShape {
    /// The displacement off the box at `p` by `error`, to the side of the hit face's
    /// outward normal `normal`: outward along that face and along every other face
    /// whose plane lies within `error` of `p` (the faces of an edge or a corner that
    /// `p` may lie on). Away from edges it is `normal * error`.
    #[inline]
    pub fn origin_offset(&self, p: Vec3, normal: Vec3, error: f32) -> Vec3 {
        let mut o = (normal * error).to_array();
        for i in 0..3 {
            if o[i] != 0.0 {
                continue;
            }
            if (p[i] - self.max[i]).abs() <= error {
                o[i] = error;
            } else if (p[i] - self.min[i]).abs() <= error {
                o[i] = -error;
            }
        }
        Vec3::from_array(o)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    const INF: f32 = f32::INFINITY;

    /// [−1, 1] × [−2, 2] × [−3, 3].
    fn bx() -> BoxShape {
        BoxShape::new(Vec3::new(1.0, 2.0, 3.0), Vec3::new(-1.0, -2.0, -3.0))
    }

    fn hit_normal(b: &BoxShape, o: Vec3, d: Vec3) -> Option<(f32, Vec3, Vec3)> {
        let ray = Ray::new(o, d);
        let h = b.intersect(&ray, INF)?;
        let sf = b.surface(&ray, &h);
        assert_eq!(sf.shading_normal, sf.normal);
        Some((h.t, sf.point, sf.normal))
    }

    #[test]
    fn corners_are_sorted() {
        let b = bx();
        assert_eq!(b.min, Vec3::new(-1.0, -2.0, -3.0));
        assert_eq!(b.bounds(), Aabb::new(b.min, b.max));
    }

    #[test]
    fn entry_faces_from_outside() {
        let b = bx();
        let cases = [
            (
                Vec3::new(-5.0, 0.0, 0.0),
                Vec3::new(1.0, 0.0, 0.0),
                4.0,
                Vec3::new(-1.0, 0.0, 0.0),
            ),
            (
                Vec3::new(5.0, 0.0, 0.0),
                Vec3::new(-2.0, 0.0, 0.0),
                2.0,
                Vec3::new(1.0, 0.0, 0.0),
            ),
            (
                Vec3::new(0.0, -5.0, 0.0),
                Vec3::new(0.0, 1.0, 0.0),
                3.0,
                Vec3::new(0.0, -1.0, 0.0),
            ),
            (
                Vec3::new(0.0, 5.0, 0.0),
                Vec3::new(0.0, -1.0, 0.0),
                3.0,
                Vec3::new(0.0, 1.0, 0.0),
            ),
            (
                Vec3::new(0.0, 0.0, -5.0),
                Vec3::new(0.0, 0.0, 1.0),
                2.0,
                Vec3::new(0.0, 0.0, -1.0),
            ),
            (
                Vec3::new(0.0, 0.0, 5.0),
                Vec3::new(0.0, 0.0, -1.0),
                2.0,
                Vec3::new(0.0, 0.0, 1.0),
            ),
        ];
        for (o, d, t, n) in cases {
            let (ht, p, hn) = hit_normal(&b, o, d).unwrap();
            assert_eq!((ht, hn), (t, n), "{o:?} {d:?}");
            assert_eq!(p, o + d * t);
        }
    }

    #[test]
    fn oblique_entry_picks_the_last_slab_entered() {
        // From (−3, −3, 0) along (1, 1, 0): enters the y slab at t = 1 and the x slab
        // at t = 2, so it enters the box at t = 2 through the x = −1 face.
        let b = bx();
        let (t, p, n) = hit_normal(&b, Vec3::new(-3.0, -3.0, 0.0), Vec3::new(1.0, 1.0, 0.0)).unwrap();
        assert_eq!(
            (t, p, n),
            (2.0, Vec3::new(-1.0, -1.0, 0.0), Vec3::new(-1.0, 0.0, 0.0))
        );
    }

    #[test]
    fn exit_faces_from_inside() {
        let b = bx();
        let (t, _, n) = hit_normal(&b, Vec3::ZERO, Vec3::new(0.0, 0.0, 1.0)).unwrap();
        assert_eq!((t, n), (3.0, Vec3::new(0.0, 0.0, 1.0)));
        let (t, _, n) = hit_normal(&b, Vec3::new(0.5, 0.0, 0.0), Vec3::new(-1.0, 0.0, 0.0)).unwrap();
        assert_eq!((t, n), (1.5, Vec3::new(-1.0, 0.0, 0.0)));
        let (t, p, n) = hit_normal(&b, Vec3::ZERO, Vec3::new(0.0, 1.0, 1.0)).unwrap();
        assert_eq!(
            (t, p, n),
            (2.0, Vec3::new(0.0, 2.0, 2.0), Vec3::new(0.0, 1.0, 0.0))
        );
    }

    #[test]
    fn misses_behind_and_t_max() {
        let b = bx();
        assert!(hit_normal(&b, Vec3::new(-5.0, 2.5, 0.0), Vec3::new(1.0, 0.0, 0.0)).is_none());
        assert!(hit_normal(&b, Vec3::new(5.0, 0.0, 0.0), Vec3::new(1.0, 0.0, 0.0)).is_none());
        let ray = Ray::new(Vec3::new(-5.0, 0.0, 0.0), Vec3::new(1.0, 0.0, 0.0));
        assert_eq!(b.intersect(&ray, 4.0), None);
        assert!(b.intersect(&ray, 4.5).is_some());
        // From inside, t_max before the exit.
        let ray = Ray::new(Vec3::ZERO, Vec3::new(1.0, 0.0, 0.0));
        assert_eq!(b.intersect(&ray, 0.5), None);
    }

    #[test]
    fn grazing_along_a_face_and_through_an_edge() {
        let b = bx();
        // Within the face planes y = 2 and y = −2 (0·∞ = NaN in the slab test): miss.
        let along = Vec3::new(1.0, 0.0, 0.0);
        assert!(hit_normal(&b, Vec3::new(-5.0, 2.0, 0.0), along).is_none());
        assert!(hit_normal(&b, Vec3::new(-5.0, -2.0, 0.0), along).is_none());
        // Just inside that plane: a hit on the x = −1 face.
        let (t, _, n) = hit_normal(&b, Vec3::new(-5.0, 1.999, 0.0), along).unwrap();
        assert_eq!((t, n), (4.0, Vec3::new(-1.0, 0.0, 0.0)));
        // Through the edge x = −1, y = −2: a hit at the corner line, finite normal.
        let (t, _, n) = hit_normal(&b, Vec3::new(-3.0, -4.0, 0.0), Vec3::new(1.0, 1.0, 0.0)).unwrap();
        assert_eq!(t, 2.0);
        assert!(n == Vec3::new(-1.0, 0.0, 0.0) || n == Vec3::new(0.0, -1.0, 0.0));
    }
}
