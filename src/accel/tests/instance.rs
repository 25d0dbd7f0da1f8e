//! Instances (`geometry::instance`): a prototype built once in its own space and
//! placed by affine transforms answers as its triangles copied into world space by
//! the test's own arithmetic (f64, normals by the cofactor matrix computed here):
//! the same primitives met at the same distances, with the same normals, shading
//! normals and texture coordinates, within f32 rounding; occlusion agrees with the
//! hits; packets and the grid and scan structures answer as single rays do, bit for
//! bit; and a graft onto a fixed part with instances moves their indices.

use std::sync::Arc;

use super::*;
use crate::accel::{Aggregate, Coherence, Ray8, Rootstock};
use crate::geometry::Surface;
use crate::prepare::scene_geometry;
use crate::scene::{Accel, Instance, Patch};

type Rows = [[f64; 4]; 3];

/// A rotation about a slanted axis, a stretch, a shear and a move; the same
/// mirrored (a negative determinant); and a small uniform scale.
const PLACINGS: [Rows; 3] = [
    [
        [0.8, -0.9, 0.3, 10.0],
        [0.6, 1.2, 0.1, -4.0],
        [0.0, 0.4, 2.1, 3.0],
    ],
    [
        [-0.8, -0.9, 0.3, -12.0],
        [-0.6, 1.2, 0.1, 5.0],
        [0.0, 0.4, 2.1, -2.0],
    ],
    [
        [0.05, 0.0, 0.0, 0.0],
        [0.0, 0.05, 0.0, 0.0],
        [0.0, 0.0, 0.05, 20.0],
    ],
];

/// A prototype's triangles, in its space: patches with vertex normals and texture
/// coordinates, every one on line 7 and of material `material`.
fn prototype(n: usize, seed: u64, material: u32) -> Scene {
    let mut next = uniform(seed);
    let mut point = |scale: f32| Vec3::new(next() - 0.5, next() - 0.5, next() - 0.5) * scale;
    let mut s = Scene {
        materials: vec![Material::DEFAULT; 2],
        ..Scene::default()
    };
    for _ in 0..n {
        let a = point(8.0);
        let corners = [a, a + point(2.0), a + point(2.0)];
        s.patches.push(Patch {
            first: s.patch_vertices.len() as u32,
            count: 3,
            material,
            line: 7,
        });
        s.patch_vertices.extend(corners);
        s.patch_normals
            .extend(corners.map(|_| point(1.0) + Vec3::new(0.0, 0.0, 1.0)));
        s.patch_uvs
            .extend(corners.map(|_| [point(1.0).x + 0.5, point(1.0).y + 0.5]));
    }
    s
}

/// `p` under `m`, in f64.
fn place_point(m: &Rows, p: Vec3) -> Vec3 {
    let p = p.to_array().map(f64::from);
    Vec3::from_array(m.map(|r| (r[0] * p[0] + r[1] * p[1] + r[2] * p[2] + r[3]) as f32))
}

/// Normal `n` under `m`: by the cofactor matrix of its linear part (the inverse
/// transpose times the determinant), in f64.
fn place_normal(m: &Rows, n: Vec3) -> Vec3 {
    let a = |i: usize, j: usize| m[i][j];
    let cof = [
        [
            a(1, 1) * a(2, 2) - a(1, 2) * a(2, 1),
            a(1, 2) * a(2, 0) - a(1, 0) * a(2, 2),
            a(1, 0) * a(2, 1) - a(1, 1) * a(2, 0),
        ],
        [
            a(0, 2) * a(2, 1) - a(0, 1) * a(2, 2),
            a(0, 0) * a(2, 2) - a(0, 2) * a(2, 0),
            a(0, 1) * a(2, 0) - a(0, 0) * a(2, 1),
        ],
        [
            a(0, 1) * a(1, 2) - a(0, 2) * a(1, 1),
            a(0, 2) * a(1, 0) - a(0, 0) * a(1, 2),
            a(0, 0) * a(1, 1) - a(0, 1) * a(1, 0),
        ],
    ];
    let n = n.to_array().map(f64::from);
    Vec3::from_array(cof.map(|r| (r[0] * n[0] + r[1] * n[1] + r[2] * n[2]) as f32))
}

/// The scene of `protos` placed by `placings` (prototype, rows) as instances, and
/// the same triangles copied into world space by the test.
fn both(protos: &[Scene], placings: &[(u32, Rows)]) -> (Scene, Scene) {
    let mut instanced = Scene {
        materials: vec![Material::DEFAULT; 2],
        prototypes: Arc::new(protos.to_vec()),
        ..Scene::default()
    };
    let mut copied = instanced.clone();
    copied.prototypes = Arc::default();
    for (k, &(prototype, m)) in placings.iter().enumerate() {
        let proto = &protos[prototype as usize];
        let line = 100 + k as u32;
        let material = proto.patches[0].material;
        instanced.instances.push(Instance {
            prototype,
            to_world: m,
            material,
            line,
        });
        for p in &proto.patches {
            let r = p.first as usize..(p.first + 3) as usize;
            copied.patches.push(Patch {
                first: copied.patch_vertices.len() as u32,
                line,
                ..*p
            });
            copied.patch_vertices.extend(
                proto.patch_vertices[r.clone()]
                    .iter()
                    .map(|&v| place_point(&m, v)),
            );
            copied.patch_normals.extend(
                proto.patch_normals[r.clone()]
                    .iter()
                    .map(|&n| place_normal(&m, n)),
            );
            copied.patch_uvs.extend_from_slice(&proto.patch_uvs[r]);
        }
    }
    (instanced, copied)
}

/// What a query's answer shows: distance, surface, texture coordinates, material
/// and line.
type Seen = (f32, Surface, Option<[f32; 2]>, u32, u32);

fn seen(bvh: &Bvh, ray: &Ray, found: Option<(Hit, u32)>) -> Option<Seen> {
    let (hit, index) = found?;
    let p = bvh.primitive(index);
    let surface = p.surface(ray, &hit, bvh.data());
    Some((hit.t, surface, p.texcoords(&hit, bvh.data()), p.material, p.line))
}

fn close(a: f32, b: f32, tolerance: f32) -> bool {
    (a - b).abs() <= tolerance * (1.0 + a.abs().max(b.abs()))
}

fn close_v(a: Vec3, b: Vec3, tolerance: f32) -> bool {
    (0..3).all(|i| close(a.to_array()[i], b.to_array()[i], tolerance))
}

/// True if two answers agree within f32 rounding of the two ways of placing.
fn agree(a: &Option<Seen>, b: &Option<Seen>) -> bool {
    match (a, b) {
        (None, None) => true,
        (Some(a), Some(b)) => {
            close(a.0, b.0, 1e-4)
                && close_v(a.1.point, b.1.point, 1e-4)
                && close_v(a.1.normal, b.1.normal, 1e-3)
                && close_v(a.1.shading_normal, b.1.shading_normal, 1e-3)
                && match (a.2, b.2) {
                    (Some(u), Some(v)) => close(u[0], v[0], 1e-3) && close(u[1], v[1], 1e-3),
                    (u, v) => u == v,
                }
                && (a.3, a.4) == (b.3, b.4)
        }
        _ => false,
    }
}

/// Random rays from around the scene, each aimed near one placing's origin.
fn rays(n: usize, seed: u64) -> Vec<Ray> {
    let mut next = uniform(seed);
    let mut coord = |s: f32| (next() - 0.5) * s;
    (0..n)
        .filter_map(|k| {
            let origin = Vec3::new(coord(60.0), coord(60.0), coord(60.0));
            let m = PLACINGS[k % PLACINGS.len()];
            let aim = Vec3::new(m[0][3] as f32, m[1][3] as f32, m[2][3] as f32);
            let at = aim + Vec3::new(coord(8.0), coord(8.0), coord(8.0));
            let dir = at - origin;
            (dir.length_squared() > 1e-6).then(|| Ray::new(origin, dir.normalize()))
        })
        .collect()
}

#[test]
fn instances_answer_as_their_triangles_copied_into_the_scene() {
    let protos = [prototype(300, 0x1234, 0), prototype(150, 0x5678, 1)];
    let placings: Vec<(u32, Rows)> = PLACINGS
        .iter()
        .enumerate()
        .map(|(k, &m)| ((k % 2) as u32, m))
        .chain([(1, PLACINGS[0])])
        .collect();
    let (instanced, copied) = both(&protos, &placings);
    let instanced = Bvh::new(scene_geometry(&instanced));
    instanced.validate().unwrap();
    assert_eq!(instanced.primitive_count(), placings.len());
    let copied = bvh_of(&copied);
    let rays = rays(20_000, 0x9e37_79b9);
    let (mut hits, mut differ) = (0, 0);
    for ray in &rays {
        let want = seen(&copied, ray, copied.closest_hit(ray, f32::INFINITY));
        let got = seen(&instanced, ray, instanced.closest_hit(ray, f32::INFINITY));
        if !agree(&got, &want) {
            differ += 1;
        }
        hits += usize::from(want.is_some());
        if let Some(w) = want {
            // Occlusion agrees with the hit, short of it and past it.
            assert!(!instanced.occluded(ray, w.0 * 0.999), "{ray:?}");
            assert!(instanced.occluded(ray, w.0 * 1.001 + 1e-3), "{ray:?}");
        }
    }
    assert!(hits > rays.len() / 5, "the rays meet the instances: {hits} hits");
    // Rays that graze an edge may fall on either side of it in the two spaces.
    assert!(
        differ <= rays.len() / 2000,
        "{differ} of {} rays answered otherwise",
        rays.len()
    );
}

#[test]
fn packets_and_other_structures_answer_instances_as_single_rays_do() {
    let protos = [prototype(200, 0x4321, 0)];
    let placings: Vec<(u32, Rows)> = PLACINGS.iter().map(|&m| (0, m)).collect();
    let (instanced, _) = both(&protos, &placings);
    let bvh = Bvh::new(scene_geometry(&instanced));
    let rays = rays(4_000, 0x51ed_270b);
    let single: Vec<Option<(Hit, u32)>> = rays.iter().map(|r| bvh.closest_hit(r, f32::INFINITY)).collect();
    assert!(single.iter().flatten().count() > rays.len() / 5);
    let bvh = Aggregate::new(bvh, Accel::Bvh);
    for (chunk, want) in rays.chunks_exact(8).zip(single.chunks_exact(8)) {
        let r8 = Ray8::new(chunk);
        for coherence in [Coherence::Coherent, Coherence::Mixed] {
            let mut got = [None; 8];
            bvh.closest_hits8(&r8, f32::INFINITY, 0xff, coherence, &mut got);
            assert_eq!(&got[..], want);
        }
    }
    for accel in [Accel::Grid, Accel::None] {
        let other = Aggregate::new(Bvh::new(scene_geometry(&instanced)), accel);
        for (ray, want) in rays.iter().zip(&single) {
            let got = other.closest_hit(ray, f32::INFINITY);
            assert_eq!(
                got.map(|(h, i)| (h, other.bvh().primitive(i).line)),
                want.map(|(h, i)| (h, bvh.bvh().primitive(i).line))
            );
            assert_eq!(
                other.occluded(ray, 20.0),
                bvh.occluded(ray, 20.0),
                "{accel:?} {ray:?}"
            );
        }
    }
}

#[test]
fn a_graft_moves_the_moving_parts_instances_past_the_fixed_parts() {
    let protos = vec![prototype(120, 0x7777, 0), prototype(80, 0x8888, 1)];
    let (fixed, _) = both(&protos, &[(0, PLACINGS[0]), (1, PLACINGS[2])]);
    let (mut moving, _) = both(&protos, &[(1, PLACINGS[1])]);
    moving.prototypes = fixed.prototypes.clone();
    let mut whole = fixed.clone();
    whole.append(moving.clone(), &mut |m| m);
    let stock = Rootstock::new(Bvh::new(scene_geometry(&fixed)));
    let grafted = stock.graft(Bvh::new(scene_geometry(&moving)), None).unwrap();
    grafted.validate().unwrap();
    let whole = Bvh::new(scene_geometry(&whole));
    let mut hits = 0;
    for ray in &rays(5_000, 0x2545_f491) {
        let want = seen(&whole, ray, whole.closest_hit(ray, f32::INFINITY));
        assert_eq!(seen(&grafted, ray, grafted.closest_hit(ray, f32::INFINITY)), want);
        hits += usize::from(want.is_some());
    }
    assert!(hits > 500, "{hits} hits");
}
