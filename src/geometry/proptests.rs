//! Property tests shared by all shapes: hit points lie on the surface (checked in
//! `f64`), clear hits are not missed, and no finite input yields a NaN or an
//! out-of-range `t`.

use super::*;
use proptest::prelude::*;

const INF: f32 = f32::INFINITY;

fn coord() -> impl Strategy<Value = f32> {
    -50.0f32..50.0
}

fn point() -> impl Strategy<Value = Vec3> {
    (coord(), coord(), coord()).prop_map(|(x, y, z)| Vec3::new(x, y, z))
}

/// Directions with a fair share of exactly-zero components (infinite `inv_dir`).
fn direction() -> impl Strategy<Value = Vec3> {
    let c = || prop_oneof![1 => Just(0.0f32), 3 => -1.0f32..1.0];
    (c(), c(), c())
        .prop_map(|(x, y, z)| Vec3::new(x, y, z))
        .prop_filter("non-zero direction", |d| d.length_squared() > 1e-6)
}

fn f64v(v: Vec3) -> [f64; 3] {
    [v.x as f64, v.y as f64, v.z as f64]
}

fn dot64(a: [f64; 3], b: [f64; 3]) -> f64 {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}

fn sub64(a: [f64; 3], b: [f64; 3]) -> [f64; 3] {
    [a[0] - b[0], a[1] - b[1], a[2] - b[2]]
}

/// The hit point `o + t d` computed in `f64`.
fn at64(ray: &Ray, t: f32) -> [f64; 3] {
    let (o, d) = (f64v(ray.origin), f64v(ray.dir));
    [0, 1, 2].map(|i| o[i] + t as f64 * d[i])
}

proptest! {
    #[test]
    fn sphere_hits_lie_on_the_sphere_and_clear_hits_are_found(
        c in point(), r in 0.001f32..20.0, o in point(), aim in point(), inside in any::<bool>(),
    ) {
        // Aim at a point near the sphere so that about half the rays hit.
        let target = c + aim * (r / 40.0);
        prop_assume!((target - o).length_squared() > 1e-6);
        let ray = Ray::new(o, target - o);
        let s = SphereShape::new(c, if inside { -r } else { r });
        let dist_oc = (o - c).length() as f64;
        let tol = 1e-5 * (dist_oc + r as f64);
        // Exact (f64) solution: distance from the centre to the line, and the roots.
        let (f, d) = (sub64(f64v(o), f64v(c)), f64v(ray.dir));
        let a = dot64(d, d);
        let b = -dot64(f, d);
        let l2 = dot64(f, f) - b * b / a;
        let rr = r as f64;
        match s.intersect(&ray, INF) {
            Some(h) => {
                prop_assert!(h.t > 0.0 && h.t.is_finite());
                let p = at64(&ray, h.t);
                let dist = dot64(sub64(p, f64v(c)), sub64(p, f64v(c))).sqrt();
                prop_assert!((dist - rr).abs() <= tol, "|p − c| = {dist}, r = {r}");
                let sf = s.surface(&ray, &h);
                prop_assert!((sf.normal.length() - 1.0).abs() < 1e-4);
            }
            None => {
                // A miss is only allowed if the line misses, grazes, or the sphere
                // (for inside-only: its exit) is behind the origin.
                let clear_line = l2 < (rr * rr) * 0.99 - tol * rr;
                let far = (b + (a * (rr * rr - l2)).max(0.0).sqrt()) / a;
                let near = (b - (a * (rr * rr - l2)).max(0.0).sqrt()) / a;
                let ahead = if inside { far } else { far.max(near) };
                prop_assert!(!(clear_line && ahead > tol), "missed: far {far}");
            }
        }
    }

    #[test]
    fn cone_hits_lie_on_the_cone(
        b in point(), axis in point(), rb in 0.0f32..5.0, ra in 0.0f32..5.0,
        o in point(), aim in point(),
    ) {
        prop_assume!(axis.length() > 0.5 && (rb > 0.01 || ra > 0.01));
        let apex = b + axis * 0.2;
        let cone = ConeShape::new(b, rb, apex, ra);
        let target = b + axis * 0.1 + aim * ((rb + ra) / 50.0);
        prop_assume!((target - o).length_squared() > 1e-6);
        let ray = Ray::new(o, target - o);
        if let Some(h) = cone.intersect(&ray, INF) {
            prop_assert!(h.t > 0.0 && h.t.is_finite());
            let p = at64(&ray, h.t);
            let (w, len) = (f64v(cone.axis), cone.length as f64);
            let f = sub64(p, f64v(b));
            let ax = dot64(f, w);
            let radial = (dot64(f, f) - ax * ax).max(0.0).sqrt();
            let tol = 1e-4 * (1.0 + (o - b).length() as f64);
            prop_assert!(ax >= -tol && ax <= len + tol, "axial {ax} of {len}");
            let r = rb as f64 + (ra as f64 - rb as f64) * ax / len;
            prop_assert!((radial - r).abs() <= tol, "radial {radial} vs {r}");
            let n = cone.surface(&ray, &h).normal;
            prop_assert!((n.length() - 1.0).abs() < 1e-4);
        }
    }

    #[test]
    fn convex_polygon_crossings_agree_with_half_planes(
        mut angles in prop::collection::vec(0.0f32..std::f32::consts::TAU, 3..12),
        x in -1.2f32..1.2, y in -1.2f32..1.2,
    ) {
        // A polygon inscribed in the unit circle, counter-clockwise: convex.
        angles.sort_by(f32::total_cmp);
        let pts: Vec<[f32; 2]> = angles.iter().map(|a| [a.cos(), a.sin()]).collect();
        let n = pts.len();
        let mut min_side = f32::INFINITY;
        for i in 0..n {
            let (p, q) = (pts[i], pts[(i + 1) % n]);
            let e = [q[0] - p[0], q[1] - p[1]];
            let len = e[0].hypot(e[1]);
            prop_assume!(len > 1e-3);
            // Signed distance to the edge's line, positive on the inner side.
            min_side = min_side.min((e[0] * (y - p[1]) - e[1] * (x - p[0])) / len);
        }
        prop_assume!(min_side.abs() > 1e-4);
        prop_assert_eq!(polygon::crossings_inside(&pts, x, y), min_side > 0.0);
    }

    #[test]
    fn no_shape_yields_nan_or_out_of_range_t(
        p0 in point(), p1 in point(), p2 in point(), r in -5.0f32..5.0,
        o in point(), d in direction(), t_max in prop_oneof![Just(INF), 0.0f32..200.0],
    ) {
        prop_assume!(r != 0.0);
        let mut data = GeometryData::default();
        let shapes = [
            Shape::Sphere(SphereShape::new(p0, r)),
            Shape::Triangle(Triangle::new(p0, p1, p2, Triangle::FLAT)),
            Shape::Polygon(PolygonShape::new(&[p0, p1, p2, (p1 + p2) * 0.5 + p0 * 0.1], &mut data)),
            Shape::Cone(ConeShape::new(p0, r, p1, r * 0.5)),
            Shape::Cone(ConeShape::new(p0, r, p1, 0.0)),
            Shape::Plane(PlaneShape::new([p0, p1, p2])),
            Shape::Box(BoxShape::new(p0, p1)),
        ];
        let ray = Ray::new(o, d);
        for shape in shapes {
            let prim = Primitive { shape, material: 0, line: 1, kind: SourceKind::Sphere };
            if let Some(h) = prim.intersect(&ray, t_max, &data) {
                prop_assert!(h.t > 0.0 && h.t < t_max, "{shape:?}: t = {}", h.t);
                let sf = prim.surface(&ray, &h, &data);
                prop_assert!(sf.point.is_finite(), "{shape:?}");
                prop_assert!((sf.normal.length() - 1.0).abs() < 1e-3, "{shape:?} {sf:?}");
                prop_assert!((sf.shading_normal.length() - 1.0).abs() < 1e-3, "{shape:?}");
            }
        }
    }
}
