//! General planar polygons (`p n`), convex or concave, tested by crossings.
//!
//! A concave polygon (the SPD gears have 144-vertex concave faces) cannot be a
//! triangle fan. Instead the ray meets the polygon's plane and the hit point is
//! tested against the outline with the crossings (even–odd) test of Haines,
//! "Point in Polygon Strategies" (Graphics Gems IV), in the coordinate plane the
//! polygon projects onto with the largest area (its dominant axis dropped). The
//! projected outline lives in [`GeometryData::polygon_points_2d`], so the shape
//! itself stays small.

use super::{GeometryData, Hit, Surface};
use crate::math::{Aabb, Ray, Vec3};

/// Bits of [`PolygonShape`]'s packed `count_axis` that hold the vertex count.
const COUNT_MASK: u32 = (1 << 30) - 1;

/// A planar polygon ready for intersection.
///
/// Invariants: `normal` is unit length (zero only for a polygon with no area, which
/// is never hit); `offset = normal · p` for the points `p` of the plane; the outline
/// is `data.polygon_points_2d[first .. first + count]`, the vertices' coordinates on
/// the two axes other than the dominant one, in the order `(a + 1) % 3, (a + 2) % 3`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PolygonShape {
    /// Unit plane normal, oriented like the winding of the first three vertices.
    pub normal: Vec3,
    /// Plane offset: `normal · p` for every point `p` of the plane.
    pub offset: f32,
    /// Index of the first projected vertex in [`GeometryData::polygon_points_2d`].
    pub first: u32,
    /// Vertex count (low 30 bits) and dominant axis (high 2 bits), packed to keep
    /// [`super::Primitive`] within 64 bytes.
    count_axis: u32,
    /// Bounding box of the vertices.
    pub bounds: Aabb,
}

impl PolygonShape {
    /// The largest vertex count a `PolygonShape` can hold.
    pub const MAX_VERTICES: usize = COUNT_MASK as usize;

    /// Builds a polygon from its vertices (at least 3, counter-clockwise seen from the
    /// front; at most [`PolygonShape::MAX_VERTICES`], the rest being ignored) and
    /// appends its projected outline to `data.polygon_points_2d`.
    ///
    /// The normal comes from Newell's method, which is robust for concave and nearly
    /// degenerate outlines, turned if needed to agree with the winding of the first
    /// three vertices (the side NFF names as the front).
    pub fn new(points: &[Vec3], data: &mut GeometryData) -> PolygonShape {
        let points = &points[..points.len().min(Self::MAX_VERTICES)];
        let normal = plane_normal(points);
        let axis = normal.dominant_axis();
        let (a1, a2) = ((axis + 1) % 3, (axis + 2) % 3);
        // Mean of the vertices' offsets: the least-squares plane for this normal,
        // which spreads the error of a slightly non-planar polygon evenly.
        let offset = if points.is_empty() {
            0.0
        } else {
            points.iter().map(|p| normal.dot(*p)).sum::<f32>() / points.len() as f32
        };
        // The scene indexes all polygon vertices with u32 and these are a subset.
        let first = data.polygon_points_2d.len() as u32;
        data.polygon_points_2d
            .extend(points.iter().map(|p| [p[a1], p[a2]]));
        // The hits lie on the fitted plane, inside the outline: the vertices lifted onto
        // the plane along the dropped axis. For a non-planar polygon these leave the
        // vertices' own box, which the BVH would then cull (found by tests/bvh_prop.rs).
        let lift = |p: &Vec3| {
            let mut q = p.to_array();
            q[axis] = (offset - normal[a1] * p[a1] - normal[a2] * p[a2]) / normal[axis];
            Vec3::from_array(q)
        };
        let bounds = points.iter().fold(Aabb::EMPTY, |b, p| b.grow(*p).grow(lift(p)));
        PolygonShape {
            normal,
            offset,
            first,
            count_axis: points.len() as u32 | (axis as u32) << 30,
            bounds,
        }
    }

    /// Number of vertices.
    #[inline]
    pub fn count(&self) -> usize {
        (self.count_axis & COUNT_MASK) as usize
    }

    /// The dominant axis of the normal (0, 1 or 2): the one dropped by the projection.
    #[inline]
    pub fn axis(&self) -> usize {
        (self.count_axis >> 30) as usize
    }

    /// Bounding box.
    #[inline]
    pub fn bounds(&self, _data: &GeometryData) -> Aabb {
        self.bounds
    }

    /// Phase one: the hit with `0 < t < t_max` (`u`, `v` unused).
    #[inline]
    pub fn intersect(&self, ray: &Ray, t_max: f32, data: &GeometryData) -> Option<Hit> {
        let denom = self.normal.dot(ray.dir);
        // Parallel rays (and polygons without area) never hit.
        if denom == 0.0 {
            return None;
        }
        let t = (self.offset - self.normal.dot(ray.origin)) / denom;
        if !(t > 0.0 && t < t_max) {
            return None;
        }
        let p = ray.at(t);
        let axis = self.axis();
        let (a1, a2) = ((axis + 1) % 3, (axis + 2) % 3);
        let (x, y) = (p[a1], p[a2]);
        // The projected outline has exactly the vertices' coordinates on these axes,
        // so its box rejects early without changing the answer.
        let b = &self.bounds;
        if !(x >= b.min[a1] && x <= b.max[a1] && y >= b.min[a2] && y <= b.max[a2]) {
            return None;
        }
        let first = self.first as usize;
        let outline = data.polygon_points_2d.get(first..first + self.count())?;
        crossings_inside(outline, x, y).then_some(Hit {
            t,
            u: 0.0,
            v: 0.0,
            part: 0,
        })
    }

    /// Phase two: the hit point and the plane normal.
    #[inline]
    pub fn surface(&self, ray: &Ray, hit: &Hit) -> Surface {
        Surface {
            point: ray.at(hit.t),
            normal: self.normal,
            shading_normal: self.normal,
        }
    }
}

/// Newell's normal of `points`, unit length, turned to agree with the winding of the
/// first three vertices when those are not collinear. Zero for a polygon with no area.
pub(crate) fn plane_normal(points: &[Vec3]) -> Vec3 {
    let Some(&p0) = points.first() else {
        return Vec3::ZERO;
    };
    // Newell's method, with vertices taken relative to p0 for precision away from the
    // origin: the sum of (a − p0) × (b − p0) over the edges is twice the vector area.
    let mut n = Vec3::ZERO;
    for (i, a) in points.iter().enumerate() {
        let b = points[(i + 1) % points.len()];
        n += (*a - p0).cross(b - p0);
    }
    let n = n.normalize();
    if points.len() >= 3 && (points[1] - p0).cross(points[2] - p0).dot(n) < 0.0 {
        -n
    } else {
        n
    }
}

/// The crossings test: is `(x, y)` inside the closed outline by the even–odd rule?
///
/// Each edge counts when it straddles the horizontal line through the point (one end
/// strictly above, the other not) and crosses it to the right of the point. Every
/// edge is evaluated from its lower end, so two polygons sharing an edge compute the
/// same crossing and leave no crack between them.
pub(crate) fn crossings_inside(outline: &[[f32; 2]], x: f32, y: f32) -> bool {
    let Some(&last) = outline.last() else {
        return false;
    };
    let mut inside = false;
    let mut prev = last;
    for &cur in outline {
        let (lo, hi) = if prev[1] <= cur[1] {
            (prev, cur)
        } else {
            (cur, prev)
        };
        if lo[1] <= y && y < hi[1] {
            // x < lo.x + (hi.x − lo.x)(y − lo.y)/(hi.y − lo.y), multiplied out by
            // hi.y − lo.y > 0 to avoid the division.
            if (x - lo[0]) * (hi[1] - lo[1]) < (hi[0] - lo[0]) * (y - lo[1]) {
                inside = !inside;
            }
        }
        prev = cur;
    }
    inside
}

#[cfg(test)]
mod tests {
    use super::*;

    const INF: f32 = f32::INFINITY;

    fn close(a: f32, b: f32) -> bool {
        (a - b).abs() <= 1e-6 * (1.0 + b.abs())
    }

    /// An L in the z = 1 plane, counter-clockwise seen from +z: the 2×2 square
    /// [0,2]² minus the notch [1,2]×[1,2].
    fn ell() -> (PolygonShape, GeometryData) {
        let pts = [
            (0.0, 0.0),
            (2.0, 0.0),
            (2.0, 1.0),
            (1.0, 1.0),
            (1.0, 2.0),
            (0.0, 2.0),
        ]
        .map(|(x, y)| Vec3::new(x, y, 1.0));
        let mut data = GeometryData::default();
        let p = PolygonShape::new(&pts, &mut data);
        (p, data)
    }

    fn down_at(x: f32, y: f32) -> Ray {
        Ray::new(Vec3::new(x, y, 5.0), Vec3::new(0.0, 0.0, -1.0))
    }

    #[test]
    fn plane_and_projection_of_the_l() {
        let (p, data) = ell();
        assert_eq!(p.normal, Vec3::new(0.0, 0.0, 1.0));
        assert!(close(p.offset, 1.0));
        assert_eq!((p.axis(), p.count(), p.first), (2, 6, 0));
        // z dropped: coordinates are (x, y).
        assert_eq!(data.polygon_points_2d[3], [1.0, 1.0]);
        assert_eq!(
            p.bounds(&data),
            Aabb::new(Vec3::new(0.0, 0.0, 1.0), Vec3::new(2.0, 2.0, 1.0))
        );
    }

    #[test]
    fn ray_through_an_arm_hits_and_through_the_notch_misses() {
        let (p, data) = ell();
        let ray = down_at(1.5, 0.5);
        let h = p.intersect(&ray, INF, &data).unwrap();
        assert!(close(h.t, 4.0));
        let sf = p.surface(&ray, &h);
        assert_eq!(sf.point, Vec3::new(1.5, 0.5, 1.0));
        assert_eq!(sf.normal, Vec3::new(0.0, 0.0, 1.0));
        assert!(p.intersect(&down_at(0.5, 1.5), INF, &data).is_some());
        // The notch is inside the bounds and inside a fan from vertex 0.
        assert_eq!(p.intersect(&down_at(1.5, 1.5), INF, &data), None);
        assert_eq!(p.intersect(&down_at(2.5, 0.5), INF, &data), None);
    }

    #[test]
    fn hit_from_behind_counts_and_behind_origin_does_not() {
        let (p, data) = ell();
        let ray = Ray::new(Vec3::new(0.5, 0.5, -1.0), Vec3::new(0.0, 0.0, 0.5));
        assert!(close(p.intersect(&ray, INF, &data).unwrap().t, 4.0));
        let away = Ray::new(Vec3::new(0.5, 0.5, 2.0), Vec3::new(0.0, 0.0, 1.0));
        assert_eq!(p.intersect(&away, INF, &data), None);
    }

    #[test]
    fn t_max_and_parallel_rays() {
        let (p, data) = ell();
        assert_eq!(p.intersect(&down_at(0.5, 0.5), 4.0, &data), None);
        assert!(p.intersect(&down_at(0.5, 0.5), 4.01, &data).is_some());
        // Grazing: in the plane itself, parallel to it.
        let graze = Ray::new(Vec3::new(-1.0, 0.5, 1.0), Vec3::new(1.0, 0.0, 0.0));
        assert_eq!(p.intersect(&graze, INF, &data), None);
    }

    #[test]
    fn oblique_ray_on_a_tilted_polygon_uses_the_dominant_plane() {
        // The square x + z = 1 for y, z in [0, 1], seen from +x+z; dominant axis x
        // (ties go to x). Winding chosen counter-clockwise about (1, 0, 1).
        let pts = [
            Vec3::new(1.0, 0.0, 0.0),
            Vec3::new(1.0, 1.0, 0.0),
            Vec3::new(0.0, 1.0, 1.0),
            Vec3::new(0.0, 0.0, 1.0),
        ];
        let mut data = GeometryData::default();
        let p = PolygonShape::new(&pts, &mut data);
        let k = 0.5f32.sqrt();
        assert!(close(p.normal.x, k) && close(p.normal.y, 0.0) && close(p.normal.z, k));
        let ray = Ray::new(Vec3::new(2.0, 0.5, 2.0), Vec3::new(-1.0, 0.0, -1.0));
        // Meets x + z = 1 at x = z = 0.5: t = 1.5.
        assert!(close(p.intersect(&ray, INF, &data).unwrap().t, 1.5));
        let miss = Ray::new(Vec3::new(2.0, 1.5, 2.0), Vec3::new(-1.0, 0.0, -1.0));
        assert_eq!(p.intersect(&miss, INF, &data), None);
    }

    #[test]
    fn normal_follows_first_three_vertices_even_at_a_reflex_corner() {
        // The L, counter-clockwise seen from +z (Newell: +z), listed from the vertex
        // before the notch corner so that the first three vertices turn clockwise:
        // (v1 − v0) × (v2 − v0) = (−1,0,0) × (−1,1,0) = (0,0,−1). NFF takes the normal
        // from the first three vertices, so −z wins.
        let pts = [
            (2.0, 1.0),
            (1.0, 1.0),
            (1.0, 2.0),
            (0.0, 2.0),
            (0.0, 0.0),
            (2.0, 0.0),
        ]
        .map(|(x, y)| Vec3::new(x, y, 0.0));
        assert_eq!(plane_normal(&pts), Vec3::new(0.0, 0.0, -1.0));
        // Listed from (0,0): the first three turn counter-clockwise, as does Newell.
        let pts = [
            (0.0, 0.0),
            (2.0, 0.0),
            (2.0, 1.0),
            (1.0, 1.0),
            (1.0, 2.0),
            (0.0, 2.0),
        ]
        .map(|(x, y)| Vec3::new(x, y, 0.0));
        assert_eq!(plane_normal(&pts), Vec3::new(0.0, 0.0, 1.0));
        // First three collinear: Newell's orientation stands.
        let pts =
            [(0.0, 0.0), (1.0, 0.0), (2.0, 0.0), (2.0, 1.0), (0.0, 1.0)].map(|(x, y)| Vec3::new(x, y, 0.0));
        assert_eq!(plane_normal(&pts), Vec3::new(0.0, 0.0, 1.0));
        // The shape's own normal is the same, and the notch still misses.
        let pts = [
            (2.0, 1.0),
            (1.0, 1.0),
            (1.0, 2.0),
            (0.0, 2.0),
            (0.0, 0.0),
            (2.0, 0.0),
        ]
        .map(|(x, y)| Vec3::new(x, y, 1.0));
        let mut data = GeometryData::default();
        let p = PolygonShape::new(&pts, &mut data);
        assert_eq!(p.normal, Vec3::new(0.0, 0.0, -1.0));
        assert!(close(p.offset, -1.0));
        assert!(close(p.intersect(&down_at(0.5, 0.5), INF, &data).unwrap().t, 4.0));
        assert_eq!(p.intersect(&down_at(1.5, 1.5), INF, &data), None);
    }

    #[test]
    fn star_has_a_hollow_centre_only_under_even_odd() {
        // A pentagram drawn as one self-intersecting outline: its centre is crossed
        // twice (even), its points once.
        let pts: Vec<[f32; 2]> = (0..5)
            .map(|i| {
                let a = std::f32::consts::FRAC_PI_2 + (i * 2) as f32 * 2.0 * std::f32::consts::PI / 5.0;
                [a.cos(), a.sin()]
            })
            .collect();
        assert!(!crossings_inside(&pts, 0.0, 0.0));
        assert!(crossings_inside(&pts, 0.0, 0.8));
        assert!(!crossings_inside(&pts, 0.0, 1.1));
    }

    #[test]
    fn shared_edge_is_covered_once() {
        // Two unit squares side by side share the edge x = 1: a point on it is in
        // exactly one of them.
        let a = [[0.0, 0.0], [1.0, 0.0], [1.0, 1.0], [0.0, 1.0]];
        let b = [[1.0, 0.0], [2.0, 0.0], [2.0, 1.0], [1.0, 1.0]];
        for y in [0.0, 0.25, 0.5, 0.999] {
            assert!(
                crossings_inside(&a, 1.0, y) != crossings_inside(&b, 1.0, y),
                "y = {y}"
            );
        }
    }
}
