//! Render-time geometry: every NFF primitive converted into a form that is quick to
//! intersect, plus the two-phase query used by the acceleration structure.
//!
//! Phase one, in the traversal loop: [`Primitive::intersect`] returns only the hit
//! distance and two surface parameters ([`Hit`]). Phase two, once for the winner:
//! [`Primitive::surface`] computes the point and normals ([`Surface`]).
//!
//! A moving sphere is intersected where it is at the ray's time ([`Ray::time`]); the
//! other shapes stand still.
//!
//! Conventions shared by every shape:
//! - surfaces are two-sided (a hit from either side counts), except spheres and cones
//!   marked inside-only (negative radii), which report only hits where the ray travels
//!   from the inside outwards (`dot(dir, outward normal) > 0`);
//! - `intersect` returns the nearest hit with `0 < t < t_max`, never a NaN `t`;
//! - `Surface::normal` is the primitive's own unit normal (outward for spheres and
//!   cones, inward for inside-only ones; from the vertex winding for polygons); the
//!   shader flips it to face the ray. `shading_normal` is the interpolated normal for
//!   patches (unit, on the same side as `normal`) and equals `normal` otherwise.

pub mod aabb_box;
pub mod cone;
mod convert;
pub mod instance;
pub mod moving_sphere;
pub mod plane;
pub mod polygon;
#[cfg(test)]
mod proptests;
pub mod sphere;
pub mod triangle;
pub mod triangulate;
pub mod watertight;

use crate::math::{Aabb, Ray, Vec3};

pub use aabb_box::BoxShape;
pub use cone::ConeShape;
pub use convert::{build_geometry, build_geometry_for_shutter, place_instances};
pub use instance::{Placement, Prototype};
pub use moving_sphere::MovingSphereShape;
pub use plane::PlaneShape;
pub use polygon::PolygonShape;
pub use sphere::SphereShape;
pub use triangle::Triangle;

/// The result of phase one: where along the ray, and surface parameters
/// (barycentric `u`, `v` for triangles; unused by other shapes).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Hit {
    /// Ray parameter of the hit, `0 < t < t_max`.
    pub t: f32,
    /// First surface parameter (barycentric weight of vertex 1 for triangles).
    pub u: f32,
    /// Second surface parameter (barycentric weight of vertex 2 for triangles).
    pub v: f32,
    /// On an instance, the index of the prototype's primitive met (see
    /// [`instance`]); 0 elsewhere.
    pub part: u32,
}

/// The result of phase two: the hit point and its normals (world space, unit length).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Surface {
    /// The hit point.
    pub point: Vec3,
    /// The primitive's geometric normal (see the module docs for its side).
    pub normal: Vec3,
    /// The normal to shade with (interpolated on patches).
    pub shading_normal: Vec3,
}

/// Shared arrays that some shapes index into instead of owning heap data.
#[derive(Clone, Debug, Default)]
pub struct GeometryData {
    /// Polygon vertices projected onto each polygon's dominant plane (see [`PolygonShape`]).
    pub polygon_points_2d: Vec<[f32; 2]>,
    /// Vertex normals of patch triangles, three consecutive entries per triangle.
    pub patch_normals: Vec<Vec3>,
    /// Texture coordinates of patch triangles' vertices: empty (a scene without
    /// textures), or parallel to `patch_normals`.
    pub patch_uvs: Vec<[f32; 2]>,
    /// The placements that [`Shape::Instance`] refers to.
    pub instances: Vec<Placement>,
}

/// The shape of one render-time primitive.
#[derive(Clone, Copy, Debug)]
pub enum Shape {
    /// A sphere.
    Sphere(SphereShape),
    /// A sphere moving in a straight line, intersected at the ray's time.
    MovingSphere(MovingSphereShape),
    /// A triangle (from a `p 3`, a convex polygon's fan, or a patch).
    Triangle(Triangle),
    /// A general (concave) polygon tested by crossings in its dominant plane.
    Polygon(PolygonShape),
    /// An open cone or cylinder.
    Cone(ConeShape),
    /// An infinite plane (unbounded: kept outside the BVH).
    Plane(PlaneShape),
    /// A solid axis-aligned box.
    Box(BoxShape),
    /// A placed prototype: index into [`GeometryData::instances`].
    Instance(u32),
}

/// Which NFF entity a primitive came from.
#[derive(Clone, Copy, Debug, PartialEq, Eq, serde::Serialize)]
pub enum SourceKind {
    /// `s`
    Sphere,
    /// P3F `sm`
    MovingSphere,
    /// `p`
    Polygon,
    /// `pp`
    Patch,
    /// `c`
    Cone,
    /// `pl`
    Plane,
    /// `aabb` (P3F `box`)
    Box,
    /// a triangle of a P3F `mesh`
    Mesh,
}

impl SourceKind {
    /// Every kind, in the order [`build_geometry`] emits them.
    pub const ALL: [SourceKind; 8] = [
        SourceKind::Sphere,
        SourceKind::MovingSphere,
        SourceKind::Cone,
        SourceKind::Polygon,
        SourceKind::Patch,
        SourceKind::Plane,
        SourceKind::Box,
        SourceKind::Mesh,
    ];
}

/// One render-time primitive: its shape, material and provenance.
#[derive(Clone, Copy, Debug)]
pub struct Primitive {
    /// The geometry.
    pub shape: Shape,
    /// Index into the scene's material table.
    pub material: u32,
    /// Line of the NFF entity it came from.
    pub line: u32,
    /// Kind of the NFF entity it came from.
    pub kind: SourceKind,
}

const _: () = assert!(std::mem::size_of::<Primitive>() <= 64);

/// Relative error bound of a hit point `p = o + t d` as the intersectors compute it
/// (the rounding of the point's arithmetic and of `t` itself), see [`point_error`].
const POINT_ERROR_REL: f32 = 4e-6;

/// A bound on the floating-point error of each coordinate of the hit point `p` of
/// `ray` at distance `t`: proportional to the magnitudes involved in computing it,
/// so it holds for tiny and huge scenes alike (no global epsilon).
#[inline]
pub fn point_error(p: Vec3, ray: &Ray, t: f32) -> f32 {
    POINT_ERROR_REL * (p.abs().max_elem() + ray.origin.abs().max_elem() + t) + f32::MIN_POSITIVE
}

impl Primitive {
    /// Bounding box; `None` for unbounded shapes (planes).
    #[inline]
    pub fn bounds(&self, data: &GeometryData) -> Option<Aabb> {
        match &self.shape {
            Shape::Sphere(s) => Some(s.bounds()),
            Shape::MovingSphere(s) => Some(s.bounds()),
            Shape::Triangle(s) => Some(s.bounds()),
            Shape::Polygon(s) => Some(s.bounds(data)),
            Shape::Cone(s) => Some(s.bounds()),
            Shape::Plane(_) => None,
            Shape::Box(s) => Some(s.bounds()),
            Shape::Instance(i) => Some(data.instances[*i as usize].bounds()),
        }
    }

    /// Phase one: the nearest hit with `0 < t < t_max`.
    #[inline(always)]
    pub fn intersect(&self, ray: &Ray, t_max: f32, data: &GeometryData) -> Option<Hit> {
        match &self.shape {
            Shape::Sphere(s) => s.intersect(ray, t_max),
            Shape::MovingSphere(s) => s.intersect(ray, t_max),
            Shape::Triangle(s) => s.intersect(ray, t_max),
            Shape::Polygon(s) => s.intersect(ray, t_max, data),
            Shape::Cone(s) => s.intersect(ray, t_max),
            Shape::Plane(s) => s.intersect(ray, t_max),
            Shape::Box(s) => s.intersect(ray, t_max),
            Shape::Instance(i) => data.instances[*i as usize].intersect(ray, t_max),
        }
    }

    /// True if the primitive lies along `ray` with `0 < t < t_max`: an instance asks
    /// its prototype for any hit, the rest for their hit.
    #[inline(always)]
    pub fn occludes(&self, ray: &Ray, t_max: f32, data: &GeometryData) -> bool {
        match &self.shape {
            Shape::Instance(i) => data.instances[*i as usize].occludes(ray, t_max),
            _ => self.intersect(ray, t_max, data).is_some(),
        }
    }

    /// The displacement that moves a secondary ray's origin off the surface at
    /// `s.point`, to the side `s.normal` points to, by `error`, the point's
    /// floating-point error bound ([`point_error`]): along the normal, as pbrt-v4's
    /// `OffsetRayOrigin` does; for a box also off every other face the bound cannot
    /// rule out (at an edge or a corner the point may lie on two or three faces, and
    /// a ray leaving from one must not start on another).
    #[inline(always)]
    pub fn origin_offset(&self, s: &Surface, error: f32) -> Vec3 {
        match &self.shape {
            Shape::Box(b) => b.origin_offset(s.point, s.normal, error),
            _ => s.normal * error,
        }
    }

    /// The texture coordinates at a hit returned by [`Primitive::intersect`]:
    /// interpolated on a patch triangle that has them, else `None`. Asked only of
    /// hits on a textured material.
    #[inline]
    pub fn texcoords(&self, hit: &Hit, data: &GeometryData) -> Option<[f32; 2]> {
        match &self.shape {
            Shape::Triangle(s) => s.texcoords(hit, data),
            Shape::Instance(i) => data.instances[*i as usize].texcoords(hit),
            _ => None,
        }
    }

    /// Phase two: point and normals of a hit returned by [`Primitive::intersect`].
    #[inline]
    pub fn surface(&self, ray: &Ray, hit: &Hit, data: &GeometryData) -> Surface {
        match &self.shape {
            Shape::Sphere(s) => s.surface(ray, hit),
            Shape::MovingSphere(s) => s.surface(ray, hit),
            Shape::Triangle(s) => s.surface(ray, hit, data),
            Shape::Polygon(s) => s.surface(ray, hit),
            Shape::Cone(s) => s.surface(ray, hit),
            Shape::Plane(s) => s.surface(ray, hit),
            Shape::Box(s) => s.surface(ray, hit),
            Shape::Instance(i) => data.instances[*i as usize].surface(ray, hit),
        }
    }
}

/// A scene's render-time geometry.
#[derive(Clone, Debug, Default)]
pub struct Geometry {
    /// All primitives (bounded and unbounded).
    pub primitives: Vec<Primitive>,
    /// Shared arrays the primitives index into.
    pub data: GeometryData,
}
