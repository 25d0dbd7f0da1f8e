//! Instances: a prototype's primitives, built once in their own space, placed in a
//! scene by an affine transform ([`Placement`]). A ray meets an instance by being
//! carried into the prototype's space, its parameter `t` unchanged (the direction is
//! not renormalized), where the prototype's own structure answers ([`Prototype`]);
//! the hit's point and normals are carried back. The prototype's primitive that was
//! met travels in [`Hit::part`].

use std::sync::Arc;

use super::{Hit, Surface};
use crate::math::{mat3, Aabb, Ray, Vec3};

/// Primitives in their own space that rays can be asked about: what a placement
/// places (the acceleration structure built over a prototype's primitives).
pub trait Prototype: Send + Sync + std::fmt::Debug {
    /// The nearest hit with `0 < t < t_max`, and the index of the primitive met.
    fn closest_hit(&self, ray: &Ray, t_max: f32) -> Option<(Hit, u32)>;
    /// True if anything lies along `ray` with `0 < t < t_max`.
    fn occluded(&self, ray: &Ray, t_max: f32) -> bool;
    /// Phase two of a hit on primitive `index` (see [`super::Primitive::surface`]).
    fn surface(&self, index: u32, ray: &Ray, hit: &Hit) -> Surface;
    /// The texture coordinates of a hit on primitive `index`, if it has them.
    fn texcoords(&self, index: u32, hit: &Hit) -> Option<[f32; 2]>;
    /// A box around its primitives placed by `m` (rows of the linear part with the
    /// translation as a fourth column), holding them however f32 arithmetic rounds
    /// (see [`Aabb::placed`]); `None` when it has an unbounded primitive.
    fn placed_bounds(&self, m: &[[f64; 4]; 3]) -> Option<Aabb>;
}

/// A prototype placed by an affine transform.
#[derive(Clone, Debug)]
pub struct Placement {
    /// What is placed.
    pub prototype: Arc<dyn Prototype>,
    /// The transform into the prototype's space: rows of the linear part with the
    /// translation as a fourth column.
    to_local: [[f32; 4]; 3],
    /// The transform out of it, the same way.
    to_world: [[f32; 4]; 3],
    /// The cofactor matrix of `to_world`'s linear part, scaled to keep it in range:
    /// normals out of the prototype's space, the geometric normal's side following
    /// the placed vertices' winding as a flattened copy's would.
    normals: [[f32; 3]; 3],
    /// The placed prototype's box.
    bounds: Aabb,
}

impl Placement {
    /// `prototype` placed by `to_world` (rows of the linear part with the
    /// translation as a fourth column); `None` if the transform cannot be inverted
    /// or takes the prototype out of f32's range, or the prototype is unbounded.
    pub fn new(prototype: Arc<dyn Prototype>, to_world: [[f64; 4]; 3]) -> Option<Placement> {
        let m = to_world.map(|r| [r[0], r[1], r[2]]);
        let cof = mat3::cofactors(m);
        let det = mat3::determinant(m, cof);
        if !(det.is_finite() && det != 0.0) {
            return None;
        }
        // The inverse's linear part is the cofactors' transpose over the determinant.
        let mut to_local = [[0.0f64; 4]; 3];
        for (i, row) in to_local.iter_mut().enumerate() {
            for j in 0..3 {
                row[j] = cof[j][i] / det;
            }
            row[3] = -(0..3).map(|j| row[j] * to_world[j][3]).sum::<f64>();
        }
        let largest = cof.iter().flatten().fold(0.0f64, |a, &b| a.max(b.abs()));
        let bounds = prototype.placed_bounds(&to_world)?;
        if !(bounds.min.is_finite() && bounds.max.is_finite()) {
            return None;
        }
        let narrow = |rows: [[f64; 4]; 3]| rows.map(|r| r.map(|v| v as f32));
        let placement = Placement {
            prototype,
            to_local: narrow(to_local),
            to_world: narrow(to_world),
            normals: cof.map(|r| r.map(|v| (v / largest) as f32)),
            bounds,
        };
        let finite = placement.to_local.iter().flatten().all(|v| v.is_finite())
            && placement.to_world.iter().flatten().all(|v| v.is_finite());
        finite.then_some(placement)
    }

    /// The placed prototype's box.
    #[inline]
    pub fn bounds(&self) -> Aabb {
        self.bounds
    }

    /// `ray` in the prototype's space, with the same parameter `t` along it.
    #[inline]
    fn local_ray(&self, ray: &Ray) -> Ray {
        let m = &self.to_local;
        let point =
            |p: Vec3, w: f32| Vec3::from_array(m.map(|r| r[0] * p.x + r[1] * p.y + r[2] * p.z + r[3] * w));
        Ray::with_time(point(ray.origin, 1.0), point(ray.dir, 0.0), ray.time)
    }

    /// Phase one: the nearest hit with `0 < t < t_max`, the prototype's primitive met
    /// in [`Hit::part`]. A ray that misses the placed box (a leaf holds several
    /// instances) is turned away before it is carried anywhere.
    #[inline(never)]
    pub fn intersect(&self, ray: &Ray, t_max: f32) -> Option<Hit> {
        if !self.bounds.may_hit(ray, t_max) {
            return None;
        }
        let (hit, part) = self.prototype.closest_hit(&self.local_ray(ray), t_max)?;
        Some(Hit { part, ..hit })
    }

    /// True if the placed prototype lies along `ray` with `0 < t < t_max`.
    #[inline(never)]
    pub fn occludes(&self, ray: &Ray, t_max: f32) -> bool {
        self.bounds.may_hit(ray, t_max) && self.prototype.occluded(&self.local_ray(ray), t_max)
    }

    /// Phase two of a hit returned by [`Placement::intersect`]: the prototype's
    /// surface carried out of its space.
    pub fn surface(&self, ray: &Ray, hit: &Hit) -> Surface {
        let local = self.prototype.surface(hit.part, &self.local_ray(ray), hit);
        let m = &self.to_world;
        let p = local.point;
        let point = Vec3::from_array(m.map(|r| r[0] * p.x + r[1] * p.y + r[2] * p.z + r[3]));
        let normal = self.normal(local.normal);
        let shading = self.normal(local.shading_normal);
        let shading_normal = if shading.dot(normal) < 0.0 {
            -shading
        } else {
            shading
        };
        Surface {
            point,
            normal,
            shading_normal,
        }
    }

    /// The texture coordinates of a hit returned by [`Placement::intersect`].
    pub fn texcoords(&self, hit: &Hit) -> Option<[f32; 2]> {
        self.prototype.texcoords(hit.part, hit)
    }

    /// Normal `n` out of the prototype's space, of unit length.
    #[inline]
    fn normal(&self, n: Vec3) -> Vec3 {
        let image = Vec3::from_array(self.normals.map(|r| r[0] * n.x + r[1] * n.y + r[2] * n.z));
        image.normalize()
    }
}
