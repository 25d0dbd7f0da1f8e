//! Triangles: `p 3` polygons, the fans of convex polygons, and the fans of patches
//! (`pp`), which add per-vertex normals for smooth shading.
//!
//! Intersection is the watertight test of Woop, Benthin and Wald (JCGT 2013; see
//! [`super::watertight`]), two-sided (no culling), edges and vertices included. A ray
//! through an edge or a vertex shared by several triangles (with the same floats for
//! the shared vertices, as a mesh's or a fan's have) hits at least one of them, in
//! floating point and not only in exact arithmetic: closed meshes have no cracks.

use super::watertight::{watertight, watertight_exact, Sheared};
use super::{GeometryData, Hit, Surface};
use crate::math::{Aabb, Ray, Vec3};

/// A triangle ready for intersection: its three vertices (not one vertex and two
/// edges: `v0 + (v1 − v0)` need not round to `v1`, and a shared edge must be the same
/// floats in both triangles for the test to be watertight).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Triangle {
    /// First vertex `v0`.
    pub v0: Vec3,
    /// Second vertex `v1`.
    pub v1: Vec3,
    /// Third vertex `v2`.
    pub v2: Vec3,
    /// Index of the first of three consecutive vertex normals (for `v0`, `v1`, `v2`)
    /// in [`GeometryData::patch_normals`]; [`Triangle::FLAT`] for none.
    pub normals: u32,
}

impl Triangle {
    /// The `normals` value of a triangle without vertex normals.
    pub const FLAT: u32 = u32::MAX;

    /// Builds a triangle; its front is the side from which `v0, v1, v2` run
    /// counter-clockwise. `normals` indexes [`GeometryData::patch_normals`] or is
    /// [`Triangle::FLAT`].
    pub fn new(v0: Vec3, v1: Vec3, v2: Vec3, normals: u32) -> Triangle {
        Triangle { v0, v1, v2, normals }
    }

    /// The edges `(v1 − v0, v2 − v0)`.
    #[inline]
    pub fn edges(&self) -> (Vec3, Vec3) {
        (self.v1 - self.v0, self.v2 - self.v0)
    }

    /// Bounding box of the three vertices.
    #[inline]
    pub fn bounds(&self) -> Aabb {
        Aabb::from_points(self.v0, self.v1).grow(self.v2)
    }

    /// The unit geometric normal `normalize((v1 − v0) × (v2 − v0))` (zero for a
    /// degenerate triangle).
    #[inline]
    pub fn geometric_normal(&self) -> Vec3 {
        let (e1, e2) = self.edges();
        e1.cross(e2).normalize()
    }

    /// Phase one: the hit with `0 < t < t_max`, with barycentrics `u` (weight of `v1`)
    /// and `v` (weight of `v2`).
    #[inline]
    pub fn intersect(&self, ray: &Ray, t_max: f32) -> Option<Hit> {
        self.intersect_sheared(&Sheared::new(ray), t_max)
    }

    /// [`Triangle::intersect`] for a ray already prepared: the very arithmetic of the
    /// leaf blocks' lanes (see [`super::watertight`]).
    #[inline]
    pub fn intersect_sheared(&self, ray: &Sheared, t_max: f32) -> Option<Hit> {
        let [v0, v1, v2] = self.in_frame(ray);
        let (t, u, v, hit) = match watertight(&ray.origin, &ray.shear, &v0, &v1, &v2, t_max) {
            Some(found) => found,
            None => self.intersect_exact(ray, t_max),
        };
        (hit != 0).then_some(Hit { t, u, v, part: 0 })
    }

    /// [`Triangle::intersect_sheared`] when an edge function came out zero.
    #[cold]
    #[inline(never)]
    fn intersect_exact(&self, ray: &Sheared, t_max: f32) -> (f32, f32, f32, u32) {
        let [v0, v1, v2] = self.in_frame(ray);
        watertight_exact(&ray.origin, &ray.shear, &v0, &v1, &v2, t_max)
    }

    /// The vertices' coordinates in the order of the ray's frame ([`Sheared::axes`]).
    #[inline(always)]
    fn in_frame(&self, ray: &Sheared) -> [[f32; 3]; 3] {
        [self.v0, self.v1, self.v2].map(|p| ray.permute(&p.to_array()))
    }

    /// Phase two: the point (from the barycentrics, so it lies in the plane), the
    /// geometric normal, and for patches the interpolated vertex normal.
    #[inline]
    pub fn surface(&self, _ray: &Ray, hit: &Hit, data: &GeometryData) -> Surface {
        let (e1, e2) = self.edges();
        let point = self.v0 + e1 * hit.u + e2 * hit.v;
        let normal = self.geometric_normal();
        let shading_normal = self.shading_normal(hit.u, hit.v, normal, data);
        Surface {
            point,
            normal,
            shading_normal,
        }
    }

    /// The texture coordinates at `hit`: its barycentric mix of the vertices'
    /// ([`GeometryData::patch_uvs`]), if the triangle has vertex data and the scene
    /// texture coordinates.
    #[inline]
    pub fn texcoords(&self, hit: &Hit, data: &GeometryData) -> Option<[f32; 2]> {
        let i = self.normals as usize;
        let uvs = data.patch_uvs.get(i..i.checked_add(3)?)?;
        let w = 1.0 - hit.u - hit.v;
        let mix = |k: usize| uvs[0][k] * w + uvs[1][k] * hit.u + uvs[2][k] * hit.v;
        Some([mix(0), mix(1)])
    }

    /// The interpolated vertex normal at barycentrics `(u, v)`, unit length and on the
    /// side of `geometric`; `geometric` itself for flat triangles and whenever the
    /// vertex normals interpolate to nothing usable (zero, NaN, missing).
    fn shading_normal(&self, u: f32, v: f32, geometric: Vec3, data: &GeometryData) -> Vec3 {
        if self.normals == Self::FLAT {
            return geometric;
        }
        let i = self.normals as usize;
        let Some(ns) = data.patch_normals.get(i..i + 3) else {
            return geometric;
        };
        let n = ns[0] * (1.0 - u - v) + ns[1] * u + ns[2] * v;
        let l2 = n.length_squared();
        if !(l2 > 0.0 && l2.is_finite()) {
            return geometric;
        }
        let n = n * (1.0 / l2.sqrt());
        if n.dot(geometric) < 0.0 {
            -n
        } else {
            n
        }
    }
}

#[cfg(test)]
pub(crate) mod tests {
    use super::*;

    const INF: f32 = f32::INFINITY;

    fn close(a: f32, b: f32) -> bool {
        (a - b).abs() <= 1e-6 * (1.0 + b.abs())
    }

    fn close_v(a: Vec3, b: Vec3) -> bool {
        close(a.x, b.x) && close(a.y, b.y) && close(a.z, b.z)
    }

    /// The right triangle (0,0,0), (1,0,0), (0,1,0) in the z = 0 plane, front +z.
    fn tri() -> Triangle {
        Triangle::new(
            Vec3::ZERO,
            Vec3::new(1.0, 0.0, 0.0),
            Vec3::new(0.0, 1.0, 0.0),
            Triangle::FLAT,
        )
    }

    fn down_at(x: f32, y: f32) -> Ray {
        Ray::new(Vec3::new(x, y, 2.0), Vec3::new(0.0, 0.0, -1.0))
    }

    #[test]
    fn hit_from_front_gives_t_barycentrics_point_normal() {
        let t = tri();
        let ray = down_at(0.25, 0.5);
        let h = t.intersect(&ray, INF).unwrap();
        assert!(close(h.t, 2.0) && close(h.u, 0.25) && close(h.v, 0.5));
        let sf = t.surface(&ray, &h, &GeometryData::default());
        assert!(close_v(sf.point, Vec3::new(0.25, 0.5, 0.0)));
        assert_eq!(sf.normal, Vec3::new(0.0, 0.0, 1.0));
        assert_eq!(sf.shading_normal, sf.normal);
    }

    #[test]
    fn back_side_hit_counts_and_keeps_winding_normal() {
        let t = tri();
        let ray = Ray::new(Vec3::new(0.2, 0.2, -3.0), Vec3::new(0.0, 0.0, 2.0));
        let h = t.intersect(&ray, INF).unwrap();
        assert!(close(h.t, 1.5));
        let sf = t.surface(&ray, &h, &GeometryData::default());
        assert_eq!(sf.normal, Vec3::new(0.0, 0.0, 1.0));
    }

    #[test]
    fn edges_and_vertices_are_inclusive() {
        let t = tri();
        for (x, y) in [
            (0.0, 0.0),
            (1.0, 0.0),
            (0.0, 1.0),
            (0.5, 0.0),
            (0.0, 0.5),
            (0.5, 0.5),
        ] {
            assert!(t.intersect(&down_at(x, y), INF).is_some(), "({x}, {y})");
        }
    }

    /// Two triangles on either side of an edge that passes 2^-46 / √8 beside the ray
    /// (along +z from the origin): the edge function rounds to zero in `f32` (where
    /// both triangles would be hit), while its exact value, recomputed in `f64`, puts
    /// the ray on the first triangle's side only. The ray, the triangle hit and the
    /// one missed.
    pub(crate) fn split_by_a_near_edge() -> (Ray, Triangle, Triangle) {
        let e = f32::EPSILON;
        let b = Vec3::new(-1.0, -(1.0 + e), 1.0);
        let c = Vec3::new(1.0 + e, 1.0 + 2.0 * e, 1.0);
        let ray = Ray::new(Vec3::ZERO, Vec3::new(0.0, 0.0, 1.0));
        let hit = Triangle::new(Vec3::new(-1.0, 1.0, 1.0), b, c, Triangle::FLAT);
        let missed = Triangle::new(Vec3::new(1.0, -1.0, 1.0), c, b, Triangle::FLAT);
        (ray, hit, missed)
    }

    #[test]
    fn an_edge_function_rounded_to_zero_gets_its_exact_sign() {
        let (ray, hit, missed) = split_by_a_near_edge();
        // In f32 the edge function of b, c is zero: cx·by and cy·bx both round to
        // −(1 + 2ε).
        let (b, c) = (hit.v1, hit.v2);
        assert_eq!(c.x * b.y - c.y * b.x, 0.0);
        let h = hit.intersect(&ray, INF).unwrap();
        assert_eq!(h.t, 1.0);
        assert_eq!(missed.intersect(&ray, INF), None);
    }

    #[test]
    fn shared_edge_has_no_crack() {
        // The unit square split along its diagonal; rays along the diagonal hit one.
        let a = tri();
        let b = Triangle::new(
            Vec3::new(1.0, 0.0, 0.0),
            Vec3::new(1.0, 1.0, 0.0),
            Vec3::new(0.0, 1.0, 0.0),
            Triangle::FLAT,
        );
        for i in 0..=64 {
            let x = i as f32 / 64.0;
            let ray = down_at(x, 1.0 - x);
            assert!(
                a.intersect(&ray, INF).is_some() || b.intersect(&ray, INF).is_some(),
                "crack at x = {x}"
            );
        }
    }

    #[test]
    fn misses_outside_parallel_and_grazing_in_plane() {
        let t = tri();
        assert_eq!(t.intersect(&down_at(0.6, 0.6), INF), None);
        assert_eq!(t.intersect(&down_at(-0.01, 0.5), INF), None);
        // In the plane of the triangle: parallel, no hit.
        let ray = Ray::new(Vec3::new(-1.0, 0.2, 0.0), Vec3::new(1.0, 0.0, 0.0));
        assert_eq!(t.intersect(&ray, INF), None);
    }

    #[test]
    fn behind_origin_and_t_max() {
        let t = tri();
        let ray = Ray::new(Vec3::new(0.2, 0.2, -1.0), Vec3::new(0.0, 0.0, -1.0));
        assert_eq!(t.intersect(&ray, INF), None);
        let ray = down_at(0.2, 0.2);
        assert_eq!(t.intersect(&ray, 2.0), None);
        assert!(t.intersect(&ray, 2.001).is_some());
    }

    #[test]
    fn axis_aligned_ray_with_infinite_inv_dir() {
        let t = Triangle::new(
            Vec3::new(0.0, -1.0, -1.0),
            Vec3::new(0.0, 1.0, -1.0),
            Vec3::new(0.0, 0.0, 1.0),
            Triangle::FLAT,
        );
        let ray = Ray::new(Vec3::new(-4.0, 0.0, 0.0), Vec3::new(1.0, 0.0, 0.0));
        let h = t.intersect(&ray, INF).unwrap();
        assert!(close(h.t, 4.0));
        // (0,0,0) = 0.25 v0 + 0.25 v1 + 0.5 v2.
        assert!(close(h.u, 0.25) && close(h.v, 0.5));
    }

    fn patch(normals: [Vec3; 3]) -> (Triangle, GeometryData) {
        let data = GeometryData {
            patch_normals: normals.to_vec(),
            ..Default::default()
        };
        let t = Triangle::new(Vec3::ZERO, Vec3::new(1.0, 0.0, 0.0), Vec3::new(0.0, 1.0, 0.0), 0);
        (t, data)
    }

    #[test]
    fn patch_normal_is_vertex_normal_at_vertex_and_mean_at_centroid() {
        let n0 = Vec3::new(0.0, 0.0, 1.0);
        let n1 = Vec3::new(1.0, 0.0, 0.0);
        let n2 = Vec3::new(0.0, 1.0, 0.0);
        let (t, data) = patch([n0, n1, n2]);
        let ray = down_at(1.0, 0.0);
        let h = t.intersect(&ray, INF).unwrap();
        let sf = t.surface(&ray, &h, &data);
        assert!(close_v(sf.shading_normal, n1));
        assert_eq!(sf.normal, Vec3::new(0.0, 0.0, 1.0));
        let ray = down_at(1.0 / 3.0, 1.0 / 3.0);
        let h = t.intersect(&ray, INF).unwrap();
        let sf = t.surface(&ray, &h, &data);
        let k = 1.0 / 3.0f32.sqrt();
        assert!(close_v(sf.shading_normal, Vec3::new(k, k, k)));
    }

    #[test]
    fn patch_normal_is_flipped_to_the_geometric_side() {
        let n = Vec3::new(0.0, 0.6, -0.8);
        let (t, data) = patch([n, n, n]);
        let ray = down_at(0.2, 0.2);
        let h = t.intersect(&ray, INF).unwrap();
        let sf = t.surface(&ray, &h, &data);
        assert!(close_v(sf.shading_normal, Vec3::new(0.0, -0.6, 0.8)));
    }

    #[test]
    fn zero_or_missing_patch_normals_fall_back_to_geometric() {
        let (t, data) = patch([Vec3::ZERO; 3]);
        let ray = down_at(0.2, 0.2);
        let h = t.intersect(&ray, INF).unwrap();
        assert_eq!(
            t.surface(&ray, &h, &data).shading_normal,
            Vec3::new(0.0, 0.0, 1.0)
        );
        // Normals that cancel at this point.
        let a = Vec3::new(1.0, 0.0, 0.0);
        let (t, data) = patch([a, -a, Vec3::ZERO]);
        let ray = down_at(0.5, 0.0);
        let h = t.intersect(&ray, INF).unwrap();
        assert_eq!(
            t.surface(&ray, &h, &data).shading_normal,
            Vec3::new(0.0, 0.0, 1.0)
        );
        // An index past the end of the table.
        let (t, _) = patch([a; 3]);
        let h = t.intersect(&ray, INF).unwrap();
        let sf = t.surface(&ray, &h, &GeometryData::default());
        assert_eq!(sf.shading_normal, Vec3::new(0.0, 0.0, 1.0));
    }

    #[test]
    fn degenerate_triangle_never_hits() {
        let t = Triangle::new(
            Vec3::ZERO,
            Vec3::new(1.0, 0.0, 0.0),
            Vec3::new(2.0, 0.0, 0.0),
            Triangle::FLAT,
        );
        assert_eq!(t.intersect(&down_at(0.5, 0.0), INF), None);
    }

    #[test]
    fn bounds_hold_the_vertices() {
        let t = Triangle::new(
            Vec3::new(1.0, -2.0, 0.5),
            Vec3::new(-1.0, 3.0, 0.0),
            Vec3::new(0.0, 0.0, 4.0),
            Triangle::FLAT,
        );
        assert_eq!(
            t.bounds(),
            Aabb::new(Vec3::new(-1.0, -2.0, 0.0), Vec3::new(1.0, 3.0, 4.0))
        );
    }
}
