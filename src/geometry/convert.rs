//! Conversion of a parsed [`Scene`] into render-time [`Geometry`].
//!
//! | NFF | becomes |
//! |---|---|
//! | `s` | one [`SphereShape`] |
//! | P3F `sm` | one [`MovingSphereShape`], for the shutter interval given |
//! | `c` | one [`ConeShape`] |
//! | `p 3` | one flat [`Triangle`] |
//! | `p n`, convex | a fan of flat [`Triangle`]s from the first vertex |
//! | `p n`, concave and simple | [`Triangle`]s by ear clipping ([`super::triangulate`]) |
//! | `p n`, self-intersecting | one [`PolygonShape`] (crossings test, even-odd rule) |
//! | `pp n` | a fan of [`Triangle`]s with vertex normals in [`GeometryData::patch_normals`] |
//! | `pl` | one [`PlaneShape`] |
//! | `aabb`, P3F `box` | one [`BoxShape`] |
//! | P3F `mesh` | one flat [`Triangle`] per triangle, with the line of its indices |
//! | an instance (AFF's meshes) | one [`Shape::Instance`] ([`place_instances`]) |
//!
//! Patches always become fans: the SPD's patches are triangles and a patch is meant
//! to be a small convex piece of a smooth surface. A concave patch is therefore
//! covered by its fan as well, which is wrong in its notches; this is accepted.
//!
//! Primitives come out kind by kind (spheres, moving spheres, cones, polygons,
//! patches, planes, boxes, mesh triangles: [`SourceKind::ALL`]), each kind in file
//! order, so the result is deterministic.

use super::{
    BoxShape, ConeShape, Geometry, GeometryData, MovingSphereShape, Placement, PlaneShape, PolygonShape,
    Primitive, Prototype, Shape, SourceKind, SphereShape, Triangle,
};
use crate::math::Vec3;
use crate::pages::huge_vec;
use crate::scene::{Polygon, Scene};
use rayon::prelude::*;
use std::sync::Arc;

/// Adds `scene`'s instances ([`Scene::instances`]) to `g`, after its other
/// primitives: each one [`Shape::Instance`] placing `built[i]`, the structure built
/// over prototype `i`. An instance whose transform cannot be inverted (a zero scale
/// leaves nothing to see) or takes its prototype past f32's range is left out, as
/// a flattened copy's triangles without area would be.
pub fn place_instances(scene: &Scene, built: &[Arc<dyn Prototype>], g: &mut Geometry) {
    for x in &scene.instances {
        let Some(placement) = Placement::new(built[x.prototype as usize].clone(), x.to_world) else {
            continue;
        };
        g.primitives.push(Primitive {
            shape: Shape::Instance(g.data.instances.len() as u32),
            material: x.material,
            line: x.line,
            kind: SourceKind::Mesh,
        });
        g.data.instances.push(placement);
    }
}

/// Converts every primitive of `scene` (see the module docs for the mapping), its
/// moving spheres for the scene's own shutter ([`Scene::shutter_interval`]).
pub fn build_geometry(scene: &Scene) -> Geometry {
    build_geometry_for_shutter(scene, scene.shutter_interval())
}

/// [`build_geometry`] for a camera whose shutter is open over `shutter`
/// (`[open, close]`, `open <= close`), which bounds the moving spheres and clamps
/// the times they are seen at (see [`MovingSphereShape`]): for a caller that
/// renders the scene with another shutter than its file's.
pub fn build_geometry_for_shutter(scene: &Scene, shutter: [f32; 2]) -> Geometry {
    // Polygons first: their pieces tell how many primitives there are.
    let polygons = polygon_chunks(scene);
    let pieces: usize = polygons
        .iter()
        .map(|c| c.triangles.len() + c.crossings.len())
        .sum();
    let patch_pieces: usize = scene.patches.iter().map(|p| p.count as usize - 2).sum();
    let count = scene.primitive_count() - scene.polygons.len() - scene.patches.len();
    let mut g = Geometry {
        primitives: huge_vec(count + pieces + patch_pieces),
        ..Geometry::default()
    };
    // Spheres and cones (hundreds of thousands in generated scenes) are converted in
    // parallel, straight into place.
    g.primitives
        .par_extend(scene.spheres.par_iter().map(|s| Primitive {
            shape: Shape::Sphere(SphereShape::new(s.center, s.radius)),
            material: s.material,
            line: s.line,
            kind: SourceKind::Sphere,
        }));
    g.primitives
        .extend(scene.moving_spheres.iter().map(|m| Primitive {
            shape: Shape::MovingSphere(MovingSphereShape::new(m, shutter)),
            material: m.material,
            line: m.line,
            kind: SourceKind::MovingSphere,
        }));
    g.primitives.par_extend(scene.cones.par_iter().map(|c| Primitive {
        shape: Shape::Cone(ConeShape::new(c.base, c.base_radius, c.apex, c.apex_radius)),
        material: c.material,
        line: c.line,
        kind: SourceKind::Cone,
    }));
    let prims = &mut g.primitives;
    let data = &mut g.data;
    // The polygons' triangles copied in input order, and those that keep the
    // crossings test (whose vertices go to `data`) converted in between.
    for chunk in polygons {
        let mut from = 0;
        for (at, p) in chunk.crossings {
            prims.extend_from_slice(&chunk.triangles[from..at]);
            prims.push(Primitive {
                shape: Shape::Polygon(PolygonShape::new(scene.polygon_points(p), data)),
                material: p.material,
                line: p.line,
                kind: SourceKind::Polygon,
            });
            from = at;
        }
        prims.extend_from_slice(&chunk.triangles[from..]);
    }
    let mut push = |shape, material, line, kind| {
        prims.push(Primitive {
            shape,
            material,
            line,
            kind,
        })
    };

    for p in &scene.patches {
        let (pts, normals) = scene.patch_points(p);
        let range = p.first as usize..(p.first + p.count) as usize;
        let uvs = scene.patch_uvs.get(range).unwrap_or_default();
        for (a, b, c) in fan(pts) {
            let index = push_normals(data, [normals[a], normals[b], normals[c]]);
            if index != Triangle::FLAT && !uvs.is_empty() {
                // Parallel to the normals from the first textured patch on.
                data.patch_uvs.resize(index as usize, [0.0; 2]);
                data.patch_uvs.extend([uvs[a], uvs[b], uvs[c]]);
            }
            let tri = Triangle::new(pts[a], pts[b], pts[c], index);
            push(Shape::Triangle(tri), p.material, p.line, SourceKind::Patch);
        }
    }
    for p in &scene.planes {
        let shape = Shape::Plane(PlaneShape::new(p.points));
        push(shape, p.material, p.line, SourceKind::Plane);
    }
    for b in &scene.boxes {
        let shape = Shape::Box(BoxShape::new(b.min, b.max));
        push(shape, b.material, b.line, SourceKind::Box);
    }
    for m in &scene.meshes {
        for t in scene.mesh_triangles_of(m) {
            let [a, b, c] = t.vertices.map(|i| scene.mesh_vertices[i as usize]);
            let tri = Triangle::new(a, b, c, Triangle::FLAT);
            push(Shape::Triangle(tri), m.material, t.line, SourceKind::Mesh);
        }
    }
    g
}

/// Polygons per parallel triangulation task.
const POLYGON_CHUNK: usize = 128;

/// The primitives of one chunk of polygons: the triangles covering them, in input
/// order, and the polygons that keep the crossings test, each with the number of
/// triangles before it.
struct PolygonChunk<'a> {
    triangles: Vec<Primitive>,
    crossings: Vec<(usize, &'a Polygon)>,
}

/// The scene's polygons triangulated, [`POLYGON_CHUNK`] of them per parallel task.
fn polygon_chunks(scene: &Scene) -> Vec<PolygonChunk<'_>> {
    scene
        .polygons
        .par_chunks(POLYGON_CHUNK)
        .map(|chunk| {
            let mut out = PolygonChunk {
                triangles: Vec::with_capacity(chunk.len()),
                crossings: Vec::new(),
            };
            for p in chunk {
                polygon_pieces(scene.polygon_points(p), |piece| match piece {
                    Some(tri) => out.triangles.push(Primitive {
                        shape: Shape::Triangle(tri),
                        material: p.material,
                        line: p.line,
                        kind: SourceKind::Polygon,
                    }),
                    None => out.crossings.push((out.triangles.len(), p)),
                });
            }
            out
        })
        .collect()
}

/// Emits the triangles covering polygon `pts` (see the module docs), or one `None`
/// for a polygon that keeps the crossings test.
fn polygon_pieces(pts: &[Vec3], mut emit: impl FnMut(Option<Triangle>)) {
    let mut tri = |a: usize, b: usize, c: usize| {
        emit(Some(Triangle::new(pts[a], pts[b], pts[c], Triangle::FLAT)));
    };
    if pts.len() == 3 {
        tri(0, 1, 2);
    } else if !is_convex(pts) {
        let axis = super::polygon::plane_normal(pts).dominant_axis();
        match super::triangulate::ear_clip(pts, axis) {
            Some(tris) => tris.into_iter().for_each(|[a, b, c]| tri(a, b, c)),
            None if pts.len() <= PolygonShape::MAX_VERTICES => emit(None),
            None => fan(pts).for_each(|(a, b, c)| tri(a, b, c)),
        }
    } else {
        fan(pts).for_each(|(a, b, c)| tri(a, b, c));
    }
}

/// Appends three vertex normals and returns the index of the first, or
/// [`Triangle::FLAT`] (pushing nothing) if the index would not fit in a `u32`.
fn push_normals(data: &mut GeometryData, normals: [Vec3; 3]) -> u32 {
    match u32::try_from(data.patch_normals.len()) {
        Ok(i) if i <= u32::MAX - 3 => {
            data.patch_normals.extend_from_slice(&normals);
            i
        }
        _ => Triangle::FLAT,
    }
}

/// The fan triangles `(0, i, i + 1)` of a polygon, leaving out those with exactly
/// zero area (from collinear vertices), which could never be hit anyway.
fn fan(pts: &[Vec3]) -> impl Iterator<Item = (usize, usize, usize)> + '_ {
    (1..pts.len().saturating_sub(1))
        .filter(move |&i| (pts[i] - pts[0]).cross(pts[i + 1] - pts[0]) != Vec3::ZERO)
        .map(|i| (0, i, i + 1))
}

/// Is the polygon convex, so that a fan from its first vertex covers exactly it?
///
/// Tested in the plane the polygon projects onto with the largest area: every turn
/// must go the same way (collinear consecutive vertices and repeated vertices are
/// fine; a reversal, i.e. a spike, is not), and the turns must add up to a single
/// revolution (a pentagram turns one way throughout but twice around).
pub(crate) fn is_convex(pts: &[Vec3]) -> bool {
    let axis = super::polygon::plane_normal(pts).dominant_axis();
    let (a1, a2) = ((axis + 1) % 3, (axis + 2) % 3);
    // Projected vertices without consecutive repeats (which have no direction).
    let mut v: Vec<[f32; 2]> = Vec::with_capacity(pts.len());
    for p in pts {
        let q = [p[a1], p[a2]];
        if v.last() != Some(&q) {
            v.push(q);
        }
    }
    while v.len() > 1 && v.first() == v.last() {
        v.pop();
    }
    if v.len() < 3 {
        return false;
    }
    let n = v.len();
    let mut sign = 0.0f32;
    let mut turning = 0.0f32;
    for i in 0..n {
        let (p0, p1, p2) = (v[(i + n - 1) % n], v[i], v[(i + 1) % n]);
        let e_in = [p1[0] - p0[0], p1[1] - p0[1]];
        let e_out = [p2[0] - p1[0], p2[1] - p1[1]];
        let cross = e_in[0] * e_out[1] - e_in[1] * e_out[0];
        let dot = e_in[0] * e_out[0] + e_in[1] * e_out[1];
        // Collinear within f32 rounding of the edge lengths.
        let tol = 1e-6 * e_in[0].hypot(e_in[1]) * e_out[0].hypot(e_out[1]);
        if cross.abs() <= tol {
            if dot < 0.0 {
                return false;
            }
            continue;
        }
        if sign == 0.0 {
            sign = cross.signum();
        } else if cross.signum() != sign {
            return false;
        }
        turning += cross.atan2(dot);
    }
    // One revolution is 2π; a doubly wound outline turns 4π.
    sign != 0.0 && turning.abs() < 3.0 * std::f32::consts::PI
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geometry::Hit;
    use crate::math::Ray;
    use crate::nff::parse;

    const INF: f32 = f32::INFINITY;

    fn poly(xy: &[(f32, f32)]) -> Vec<Vec3> {
        xy.iter().map(|&(x, y)| Vec3::new(x, y, 0.0)).collect()
    }

    #[test]
    fn convexity_in_the_dominant_plane() {
        let square = [(0.0, 0.0), (1.0, 0.0), (1.0, 1.0), (0.0, 1.0)];
        assert!(is_convex(&poly(&square)));
        // Clockwise is just as convex.
        let cw: Vec<_> = square.iter().rev().copied().collect();
        assert!(is_convex(&poly(&cw)));
        // Collinear midpoints and a repeated vertex.
        let with_mid = [
            (0.0, 0.0),
            (0.5, 0.0),
            (1.0, 0.0),
            (1.0, 1.0),
            (1.0, 1.0),
            (0.0, 1.0),
        ];
        assert!(is_convex(&poly(&with_mid)));
        let ell = [
            (0.0, 0.0),
            (2.0, 0.0),
            (2.0, 1.0),
            (1.0, 1.0),
            (1.0, 2.0),
            (0.0, 2.0),
        ];
        assert!(!is_convex(&poly(&ell)));
        // A spike: goes out to (2, 0) and straight back.
        let spike = [(0.0, 0.0), (2.0, 0.0), (1.0, 0.0), (1.0, 1.0), (0.0, 1.0)];
        assert!(!is_convex(&poly(&spike)));
        let star: Vec<_> = (0..5)
            .map(|i| {
                let a = i as f32 * 4.0 * std::f32::consts::PI / 5.0;
                (a.cos(), a.sin())
            })
            .collect();
        assert!(!is_convex(&poly(&star)));
        // A square standing in the x = 3 plane (dominant axis x).
        let upright: Vec<_> = square.iter().map(|&(y, z)| Vec3::new(3.0, y, z)).collect();
        assert!(is_convex(&upright));
    }

    const SCENE: &str = "v from 0 0 10 at 0 0 0 up 0 1 0 angle 40 hither 1 resolution 8 8\n\
        f 1 0 0 1 0 1 0 1\n\
        s 0 0 0 1\n\
        s 5 0 0 -2\n\
        c 0 0 0 1 0 0 2 1\n\
        p 3 0 0 0 1 0 0 0 1 0\n\
        f 0 1 0 1 0 1 0 1\n\
        p 4 0 0 1 2 0 1 2 2 1 0 2 1\n\
        p 6 0 0 3 2 0 3 2 1 3 1 1 3 1 2 3 0 2 3\n\
        pp 3 0 0 0 0 0 1 1 0 0 0 0 1 0 1 0 0 0 1\n\
        pp 4 0 0 5 0 0 1 1 0 5 1 0 1 1 1 5 1 1 1 0 1 5 0 1 1\n\
        pl 0 -1 0 0 -1 1 1 -1 0\n\
        aabb -1 1 -2 2 -3 3\n";

    fn count(g: &Geometry, f: fn(&Shape) -> bool) -> usize {
        g.primitives.iter().filter(|p| f(&p.shape)).count()
    }

    #[test]
    fn builds_every_kind_with_counts_and_provenance() {
        let scene = parse(SCENE).unwrap();
        let g = build_geometry(&scene);
        assert_eq!(count(&g, |s| matches!(s, Shape::Sphere(_))), 2);
        assert_eq!(count(&g, |s| matches!(s, Shape::Cone(_))), 1);
        // p 3 → 1, p 4 → 2, the L-shaped p 6 → 4 by ear clipping, pp 3 → 1, pp 4 → 2.
        assert_eq!(count(&g, |s| matches!(s, Shape::Triangle(_))), 10);
        assert_eq!(count(&g, |s| matches!(s, Shape::Polygon(_))), 0);
        assert_eq!(count(&g, |s| matches!(s, Shape::Plane(_))), 1);
        assert_eq!(count(&g, |s| matches!(s, Shape::Box(_))), 1);
        assert_eq!(g.primitives.len(), 15);
        assert_eq!(g.data.polygon_points_2d.len(), 0);
        assert_eq!(g.data.patch_normals.len(), 9);
        let kinds: Vec<_> = g.primitives.iter().map(|p| p.kind).collect();
        use SourceKind::*;
        let expected = [
            Sphere, Sphere, Cone, Polygon, Polygon, Polygon, Polygon, Polygon, Polygon, Polygon, Patch,
            Patch, Patch, Plane, Box,
        ];
        assert_eq!(kinds, expected);
        let lines: Vec<_> = g.primitives.iter().map(|p| p.line).collect();
        assert_eq!(lines, [3, 4, 5, 6, 8, 8, 9, 9, 9, 9, 10, 11, 11, 12, 13]);
        let materials: Vec<_> = g.primitives.iter().map(|p| p.material).collect();
        assert_eq!(materials, [0, 0, 0, 0, 1, 1, 1, 1, 1, 1, 1, 1, 1, 1, 1]);
        assert!(matches!(g.primitives[1].shape, Shape::Sphere(s) if s.inside));
        assert!(g
            .primitives
            .iter()
            .all(|p| p.bounds(&g.data).is_some() != (p.kind == Plane)));
    }

    #[test]
    fn moving_spheres_follow_the_spheres_and_are_bounded_over_the_shutter_asked_for() {
        let src = "camera eye 0 0 10 at 0 0 0 up 0 1 0 angle 40\nshutter 0 0.5\n\
                   mat 1 1 1 1 1 1 1 0 9 0 1\nc 0 0 0 1 0 0 2 1\nsm 0 0 0 4 0 0 1 0 1\ns 9 9 9 1\n";
        let scene =
            crate::nff::parse_format(src.as_bytes(), crate::nff::Format::P3f, &Default::default()).unwrap();
        let g = build_geometry(&scene);
        let kinds: Vec<_> = g.primitives.iter().map(|p| p.kind).collect();
        use SourceKind::*;
        assert_eq!(kinds, [Sphere, MovingSphere, Cone]);
        assert_eq!(g.primitives[1].line, 5);
        // The file's shutter, [0, 0.5]: centres 0 to 2 along x.
        let b = g.primitives[1].bounds(&g.data).unwrap();
        assert_eq!((b.min.x, b.max.x), (-1.0, 3.0));
        // Another shutter, [0.5, 1]: centres 2 to 4.
        let g = build_geometry_for_shutter(&scene, [0.5, 1.0]);
        let b = g.primitives[1].bounds(&g.data).unwrap();
        assert_eq!((b.min.x, b.max.x), (1.0, 5.0));
        // Seen at the ray's time: along -z at x = 4 from z = 5, hit at time 1 (centre
        // x = 4: the top at z = 1) and missed at time 0.5 (centre x = 2, two away).
        let down = |time| Ray::with_time(Vec3::new(4.0, 0.0, 5.0), Vec3::new(0.0, 0.0, -1.0), time);
        let h = g.primitives[1].intersect(&down(1.0), INF, &g.data).unwrap();
        assert_eq!(h.t, 4.0);
        assert_eq!(g.primitives[1].intersect(&down(0.5), INF, &g.data), None);
    }

    /// Brute-force closest hit: the primitive's index and the hit.
    fn first_hit(g: &Geometry, ray: &Ray) -> Option<(usize, Hit)> {
        let mut best: Option<(usize, Hit)> = None;
        for (i, p) in g.primitives.iter().enumerate() {
            let t_max = best.map_or(INF, |b| b.1.t);
            if let Some(h) = p.intersect(ray, t_max, &g.data) {
                best = Some((i, h));
            }
        }
        best
    }

    #[test]
    fn convex_quad_fan_covers_the_quad_exactly() {
        let g = build_geometry(&parse("p 4 0 0 0 2 0 0 2 1 0 0 1 0\n").unwrap());
        assert_eq!(g.primitives.len(), 2);
        let down = Vec3::new(0.0, 0.0, -1.0);
        for (x, y) in [(0.1, 0.1), (1.9, 0.1), (1.9, 0.9), (0.1, 0.9), (1.0, 0.5)] {
            let ray = Ray::new(Vec3::new(x, y, 3.0), down);
            let (i, h) = first_hit(&g, &ray).unwrap_or_else(|| panic!("({x}, {y})"));
            assert_eq!(h.t, 3.0);
            let sf = g.primitives[i].surface(&ray, &h, &g.data);
            assert_eq!(sf.normal, Vec3::new(0.0, 0.0, 1.0));
            assert!((sf.point - Vec3::new(x, y, 0.0)).length() < 1e-6);
        }
        for (x, y) in [(2.1, 0.5), (1.0, 1.1), (-0.1, 0.5)] {
            assert_eq!(first_hit(&g, &Ray::new(Vec3::new(x, y, 3.0), down)), None);
        }
    }

    #[test]
    fn concave_polygon_is_ear_clipped_and_misses_in_its_notch() {
        let g = build_geometry(&parse("p 6 0 0 3 2 0 3 2 1 3 1 1 3 1 2 3 0 2 3\n").unwrap());
        assert_eq!(g.primitives.len(), 4);
        assert!(g.primitives.iter().all(|p| matches!(p.shape, Shape::Triangle(_))));
        let down = Vec3::new(0.0, 0.0, -1.0);
        let hit = first_hit(&g, &Ray::new(Vec3::new(1.5, 0.5, 5.0), down)).unwrap();
        assert_eq!(hit.1.t, 2.0);
        assert_eq!(first_hit(&g, &Ray::new(Vec3::new(1.5, 1.5, 5.0), down)), None);
    }

    #[test]
    fn self_intersecting_polygon_keeps_the_crossings_test() {
        // A pentagram: its even-odd interior excludes the central pentagon.
        let g = build_geometry(
            &parse("p 5 1 0 0 -0.809 0.588 0 0.309 -0.951 0 0.309 0.951 0 -0.809 -0.588 0\n").unwrap(),
        );
        assert_eq!(g.primitives.len(), 1);
        assert!(matches!(g.primitives[0].shape, Shape::Polygon(_)));
        let down = Vec3::new(0.0, 0.0, -1.0);
        assert_eq!(first_hit(&g, &Ray::new(Vec3::new(0.0, 0.0, 1.0), down)), None);
        assert!(first_hit(&g, &Ray::new(Vec3::new(0.6, 0.0, 1.0), down)).is_some());
    }

    /// Polygons triangulated chunk by chunk on several threads come out in input
    /// order, those that keep the crossings test in their places among the
    /// triangles, each with its own vertices.
    #[test]
    fn polygons_come_out_in_input_order_across_chunks() {
        // Three kinds in turn, over more than two chunks: a triangle (one piece), a
        // pentagram (one crossings-test polygon), a convex quad (two triangles); each
        // polygon on its own line, at its own height.
        let n = 2 * POLYGON_CHUNK + 50;
        let mut text = String::new();
        let mut expected = Vec::new();
        for i in 0..n {
            let z = i as f32;
            let line = i as u32 + 1;
            match i % 3 {
                0 => {
                    text += &format!("p 3 0 0 {z} 1 0 {z} 0 1 {z}\n");
                    expected.push((line, false));
                }
                1 => {
                    text += &format!(
                        "p 5 1 0 {z} -0.809 0.588 {z} 0.309 -0.951 {z} 0.309 0.951 {z} -0.809 -0.588 {z}\n"
                    );
                    expected.push((line, true));
                }
                _ => {
                    text += &format!("p 4 0 0 {z} 2 0 {z} 2 1 {z} 0 1 {z}\n");
                    expected.extend([(line, false), (line, false)]);
                }
            }
        }
        let g = build_geometry(&parse(&text).unwrap());
        let got: Vec<(u32, bool)> = g
            .primitives
            .iter()
            .map(|p| (p.line, matches!(p.shape, Shape::Polygon(_))))
            .collect();
        assert_eq!(got, expected);
        // Each pentagram answers at its own height: its vertices are its own.
        let down = Vec3::new(0.0, 0.0, -1.0);
        for (index, p) in g.primitives.iter().enumerate() {
            if let Shape::Polygon(_) = p.shape {
                let z = (p.line - 1) as f32;
                let ray = Ray::new(Vec3::new(0.6, 0.0, z + 0.5), down);
                let hit = p.intersect(&ray, 0.75, &g.data);
                assert_eq!(hit.map(|h| h.t), Some(0.5), "polygon {index}, line {}", p.line);
            }
        }
    }

    #[test]
    fn patch_fan_carries_its_vertex_normals() {
        let src = "pp 4 0 0 0 0 0 1  1 0 0 1 0 0  1 1 0 0 1 0  0 1 0 1 1 1\n";
        let g = build_geometry(&parse(src).unwrap());
        assert_eq!(g.primitives.len(), 2);
        let n = &g.data.patch_normals;
        // Second fan triangle (v0, v2, v3).
        assert_eq!(
            n[3..6],
            [Vec3::new(0.0, 0.0, 1.0), Vec3::new(0.0, 1.0, 0.0), Vec3::ONE]
        );
        // At vertex v2 = (1, 1, 0), the shading normal is v2's normal.
        let ray = Ray::new(Vec3::new(1.0, 1.0, 2.0), Vec3::new(0.0, 0.0, -1.0));
        let p = &g.primitives[1];
        let h = p.intersect(&ray, INF, &g.data).unwrap();
        let sf = p.surface(&ray, &h, &g.data);
        assert_eq!(sf.shading_normal, Vec3::new(0.0, 1.0, 0.0));
        assert_eq!(sf.normal, Vec3::new(0.0, 0.0, 1.0));
    }
}
