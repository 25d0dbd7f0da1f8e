//! Two trees grafted under one root (`Rootstock::graft`) answer every query as the
//! tree built over both parts at once: the same hits (distance, barycentrics, and
//! the surface and texture coordinates of the primitive hit, which read the moved
//! geometry arrays), the same occlusion, in single rays and packets; a graft made in
//! the arrays of an earlier one is the fresh graft's tree, entry for entry.

use super::*;
use crate::accel::{Aggregate, Coherence, Ray8, Rootstock};
use crate::scene::{Accel, Patch, Plane};

/// A part of a scene: the soup's spheres, triangles and cones, patches with normals
/// and texture coordinates, a concave polygon and a plane, every primitive on
/// `line` (a part's own line: ties between the parts then go by line in both
/// trees).
fn part(n: usize, seed: u64, line: u32) -> Scene {
    let mut s = soup(n);
    let mut next = uniform(seed);
    let mut point = |scale: f32| Vec3::new(next() - 0.5, next() - 0.5, next() - 0.5) * scale;
    // Moved, so that the two parts overlap without coinciding.
    let shift = point(20.0);
    for sphere in &mut s.spheres {
        sphere.center += shift;
    }
    for v in &mut s.polygon_vertices {
        *v += shift;
    }
    for i in 0..n / 2 {
        let a = point(80.0);
        let corners = [a, a + point(2.0), a + point(2.0)];
        s.patches.push(Patch {
            first: s.patch_vertices.len() as u32,
            count: 3,
            material: 0,
            line,
        });
        s.patch_vertices.extend(corners);
        s.patch_normals
            .extend(corners.map(|_| point(1.0) + Vec3::new(0.0, 0.0, 1.0)));
        s.patch_uvs
            .extend([[0.0, 0.0], [1.0, 0.0], [i as f32 / n as f32, 1.0]]);
    }
    let first = s.polygon_vertices.len() as u32;
    let c = point(30.0);
    // An L: concave, kept whole and tested in its plane's 2D points.
    let l = [
        (0.0, 0.0),
        (4.0, 0.0),
        (4.0, 1.0),
        (1.0, 1.0),
        (1.0, 4.0),
        (0.0, 4.0),
    ];
    s.polygon_vertices
        .extend(l.map(|(x, y)| c + Vec3::new(x, y, 0.5 * x)));
    s.polygons.push(Polygon {
        first,
        count: l.len() as u32,
        material: 0,
        line,
    });
    s.planes.push(Plane {
        points: [
            Vec3::new(0.0, -90.0, 0.0),
            Vec3::new(1.0, -90.0, 0.0),
            Vec3::new(0.0, -90.0, 1.0),
        ],
        material: 0,
        line,
    });
    for sphere in &mut s.spheres {
        sphere.line = line;
    }
    for p in &mut s.polygons {
        p.line = line;
    }
    for cone in &mut s.cones {
        cone.line = line;
    }
    s
}

/// What a query's answer shows: the hit, the bits of its surface (point, normal,
/// shading normal), of its texture coordinates, and the primitive's source line.
type Seen = (Hit, [u32; 9], Option<[u32; 2]>, u32);

/// What `found`, the answer of `bvh` to `ray`, shows.
fn seen(bvh: &Bvh, ray: &Ray, found: Option<(Hit, u32)>) -> Option<Seen> {
    let (hit, index) = found?;
    let p = bvh.primitive(index);
    let s = p.surface(ray, &hit, bvh.data());
    let bits = [s.point, s.normal, s.shading_normal]
        .map(|v| v.to_array().map(f32::to_bits))
        .concat();
    let uv = p.texcoords(&hit, bvh.data()).map(|uv| uv.map(f32::to_bits));
    Some((hit, bits.try_into().unwrap(), uv, p.line))
}

#[test]
fn a_grafted_tree_answers_as_the_tree_of_both_parts() {
    let (fixed, moving) = (part(1500, 0x51, 1), part(900, 0x77, 2));
    let mut whole = fixed.clone();
    whole.append(moving.clone(), &mut |m| m);
    let mut stock = Rootstock::new(bvh_of(&fixed));
    let fresh = stock.graft(bvh_of(&moving), None).unwrap();
    // The stock's arrays lent to a graft, whose arrays another graft then takes.
    let lent = stock.lend();
    let other = stock.graft(bvh_of(&part(300, 0x99, 3)), lent).unwrap();
    assert!(
        stock.graft(bvh_of(&moving), None).is_none(),
        "nothing left to copy"
    );
    let grafted = stock.graft(bvh_of(&moving), Some(other)).unwrap();
    assert_eq!(format!("{grafted:?}"), format!("{fresh:?}"));
    grafted.validate().unwrap();
    let whole = bvh_of(&whole);
    assert_eq!(grafted.primitive_count(), whole.primitive_count());
    let mut next = uniform(0x2545_f491_4f6c_dd1d);
    let mut rays = Vec::new();
    for _ in 0..20_000 {
        let mut coord = |s: f32| (next() - 0.5) * s;
        let origin = Vec3::new(coord(150.0), coord(150.0), coord(150.0));
        let dir = Vec3::new(coord(2.0), coord(2.0), coord(2.0));
        if dir.length_squared() > 1e-6 {
            rays.push(Ray::new(origin, dir.normalize()));
        }
    }
    let mut hits = 0;
    for ray in &rays {
        let want = seen(&whole, ray, whole.closest_hit(ray, f32::INFINITY));
        let got = seen(&grafted, ray, grafted.closest_hit(ray, f32::INFINITY));
        assert_eq!(got, want, "{ray:?}");
        hits += usize::from(want.is_some());
        for t_max in [1.0f32, 10.0, f32::INFINITY] {
            assert_eq!(
                grafted.occluded(ray, t_max),
                whole.occluded(ray, t_max),
                "{ray:?} below {t_max}"
            );
        }
    }
    assert!(hits > rays.len() / 10, "the rays meet the scene: {hits} hits");
    let (whole, grafted) = (
        Aggregate::new(whole, Accel::Bvh),
        Aggregate::new(grafted, Accel::Bvh),
    );
    for chunk in rays.chunks_exact(8).take(500) {
        let r8 = Ray8::new(chunk);
        for coherence in [Coherence::Coherent, Coherence::Mixed] {
            let (mut a, mut b) = ([None; 8], [None; 8]);
            whole.closest_hits8(&r8, f32::INFINITY, 0xff, coherence, &mut a);
            grafted.closest_hits8(&r8, f32::INFINITY, 0xff, coherence, &mut b);
            for k in 0..8 {
                let ray = &chunk[k];
                assert_eq!(seen(grafted.bvh(), ray, b[k]), seen(whole.bvh(), ray, a[k]));
            }
            let limits = [5.0; 8];
            assert_eq!(
                grafted.occluded8(&r8, &limits, 0xff, coherence),
                whole.occluded8(&r8, &limits, 0xff, coherence)
            );
        }
    }
}

#[test]
fn grafting_onto_or_from_an_empty_part_keeps_the_other() {
    let some = part(200, 0x33, 1);
    let empty = Scene {
        materials: vec![Material::DEFAULT],
        ..Scene::default()
    };
    let ray = Ray::new(Vec3::new(0.0, 0.0, -200.0), Vec3::new(0.0, 0.0, 1.0));
    let alone = bvh_of(&some);
    for grafted in [
        Rootstock::new(bvh_of(&empty)).graft(bvh_of(&some), None).unwrap(),
        Rootstock::new(bvh_of(&some)).graft(bvh_of(&empty), None).unwrap(),
    ] {
        grafted.validate().unwrap();
        assert_eq!(grafted.primitive_count(), alone.primitive_count());
        assert_eq!(
            seen(&grafted, &ray, grafted.closest_hit(&ray, f32::INFINITY)),
            seen(&alone, &ray, alone.closest_hit(&ray, f32::INFINITY))
        );
    }
    let none = Rootstock::new(bvh_of(&empty))
        .graft(bvh_of(&empty), None)
        .unwrap();
    none.validate().unwrap();
    assert_eq!(none.closest_hit(&ray, f32::INFINITY), None);
}
