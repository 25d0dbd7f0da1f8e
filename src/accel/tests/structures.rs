//! The grid and the scan (`--accel grid|none`) give the BVH's answers exactly: the
//! same hit, distance and primitive, ties included, and the same occlusion, on random
//! scenes of spheres, triangles and a plane, on coincident primitives (ties), and on
//! rays along the grid's cell boundaries, for single rays and packets of shadow rays;
//! and each counts the work it does.

use super::*;
use crate::accel::Coherence;
use crate::accel::{Aggregate, QueryCounts, Ray8};
use crate::geometry::SourceKind;
use crate::scene::{Accel, Plane};

/// The three structures over `scene`.
fn all_three(scene: &Scene) -> [Aggregate; 3] {
    [Accel::Bvh, Accel::Grid, Accel::None].map(|kind| Aggregate::new(bvh_of(scene), kind))
}

/// Every structure answers `ray` as the BVH does, for the closest hit and occlusion.
fn assert_same_answers(structures: &[Aggregate; 3], ray: &Ray) {
    let want = structures[0].closest_hit(ray, f32::INFINITY);
    for s in &structures[1..] {
        assert_eq!(
            s.closest_hit(ray, f32::INFINITY),
            want,
            "{:?} on {ray:?}",
            s.kind()
        );
        let mut counts = QueryCounts::default();
        assert_eq!(s.closest_hit_counted(ray, f32::INFINITY, &mut counts), want);
        for t_max in [0.5f32, 3.0, f32::INFINITY] {
            let blocked = structures[0].occluded(ray, t_max);
            assert_eq!(
                s.occluded(ray, t_max),
                blocked,
                "{:?} on {ray:?} below {t_max}",
                s.kind()
            );
        }
    }
}

/// Every structure answers each active ray of the eight-ray queries as the BVH
/// answers it alone.
fn assert_same_packet_answers(structures: &[Aggregate; 3], rays: &[Ray], active: u32) {
    let r8 = crate::accel::Ray8::new(rays);
    let limits = std::array::from_fn(|k| [0.5f32, 3.0, f32::INFINITY][k % 3]);
    for (s, coherence) in structures
        .iter()
        .flat_map(|s| [(s, Coherence::Coherent), (s, Coherence::Mixed)])
    {
        let mut out = [None; 8];
        s.closest_hits8(&r8, f32::INFINITY, active, coherence, &mut out);
        let blocked = s.occluded8(&r8, &limits, active, coherence);
        for k in 0..8 {
            let on = active >> k & 1 != 0;
            let ray = &rays[k.min(rays.len() - 1)];
            let want = on
                .then(|| structures[0].closest_hit(ray, f32::INFINITY))
                .flatten();
            assert_eq!(out[k], want, "{:?}, ray {k}", s.kind());
            let occluded = on && structures[0].occluded(ray, limits[k]);
            assert_eq!(blocked >> k & 1 != 0, occluded, "{:?}, ray {k}", s.kind());
        }
    }
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(48))]

    #[test]
    fn grid_and_scan_give_the_bvhs_answers(
        spheres in prop::collection::vec((v3(10.0), 0.05f32..2.0), 0..50),
        tris in prop::collection::vec((v3(10.0), v3(3.0), v3(3.0)), 0..50),
        plane in any::<bool>(),
        rays in prop::collection::vec((v3(15.0), v3(1.0)), 1..40),
    ) {
        let tris: Vec<[Vec3; 3]> = tris.iter().map(|&(a, d1, d2)| [a, a + d1, a + d2]).collect();
        let mut scene = scene_with(&spheres, &tris);
        if plane {
            scene.planes.push(Plane {
                points: [Vec3::new(0.0, -8.0, 0.0), Vec3::new(0.0, -8.0, 1.0), Vec3::new(1.0, -7.9, 0.0)],
                material: 0,
                line: 1,
            });
        }
        let structures = all_three(&scene);
        let rays: Vec<Ray> = rays.into_iter().filter(|(_, d)| d.length() > 0.01).map(|(o, d)| Ray::new(o, d)).collect();
        for ray in &rays {
            assert_same_answers(&structures, ray);
        }
        for (i, packet) in rays.chunks(8).enumerate() {
            let active = [0xff, 0b0101_1010, 0b1000_0001][i % 3];
            assert_same_packet_answers(&structures, packet, active);
        }
        assert_packets_answer_each_ray(&structures, &rays);
    }
}

/// Every structure's packet occlusion gives each active ray its single-ray answer,
/// and inactive rays nothing, in packets of one to eight rays with lanes left out.
fn assert_packets_answer_each_ray(structures: &[Aggregate; 3], rays: &[Ray]) {
    let t_max = [0.5, 3.0, f32::INFINITY, 1.0, 7.5, 0.1, 20.0, 2.0];
    for (c, packet) in rays.chunks(8).enumerate() {
        let packed = Ray8::new(packet);
        let all = (1u32 << packet.len()) - 1;
        for active in [all, all & (0b1011_0110 >> (c % 3)), 0] {
            for s in structures {
                let want = (0..packet.len())
                    .filter(|&k| active >> k & 1 != 0 && s.occluded(&packet[k], t_max[k]))
                    .fold(0, |bits, k| bits | 1 << k);
                assert_eq!(
                    s.occluded8(&packed, &t_max, active, Coherence::Coherent),
                    want,
                    "{:?}, {active:#b}",
                    s.kind()
                );
            }
        }
    }
}

/// Coincident copies of a sphere and of a quad's two triangles, each copy from its
/// own line of the scene file: every hit is a tie among six. Every structure, alone
/// and in packets, reports the copy from the earliest line, whether the copies are
/// listed in the order of their lines or against it (the place in the scene's lists
/// does not decide, nor does the leaf order the builder chose).
#[test]
fn ties_go_to_the_primitive_first_in_the_file() {
    const COPIES: usize = 6;
    let quad = [
        [
            Vec3::new(-1.0, -1.0, -0.5),
            Vec3::new(1.0, -1.0, -0.5),
            Vec3::new(1.0, 1.0, -0.5),
        ],
        [
            Vec3::new(-1.0, -1.0, -0.5),
            Vec3::new(1.0, 1.0, -0.5),
            Vec3::new(-1.0, 1.0, -0.5),
        ],
    ];
    let tris: Vec<[Vec3; 3]> = (0..COPIES).flat_map(|_| quad).collect();
    let spheres = [(Vec3::new(0.0, 0.0, 2.0), 0.75); COPIES];
    for against in [false, true] {
        // Copy k of every shape on line 10 + k, or on line 10 + COPIES - k.
        let line = |k: usize| 10 + if against { COPIES - k } else { k } as u32;
        let first = line(if against { COPIES - 1 } else { 0 });
        let mut scene = scene_with(&spheres, &tris);
        for (k, s) in scene.spheres.iter_mut().enumerate() {
            s.line = line(k);
        }
        for (k, p) in scene.polygons.iter_mut().enumerate() {
            p.line = line(k / 2);
        }
        let structures = all_three(&scene);
        let mut next = uniform(11);
        let rays: Vec<Ray> = (0..64)
            .map(|_| {
                let o = Vec3::new(next() * 1.6 - 0.8, next() * 1.6 - 0.8, 6.0);
                Ray::new(o, Vec3::new(0.0, 0.0, -1.0))
            })
            .collect();
        let (mut spheres_hit, mut quads_hit) = (0, 0);
        for s in &structures {
            for packet in rays.chunks(8) {
                let mut out = [None; 8];
                s.closest_hits8(
                    &Ray8::new(packet),
                    f32::INFINITY,
                    0xFF,
                    Coherence::Coherent,
                    &mut out,
                );
                for (ray, got) in packet.iter().zip(out) {
                    let (_, prim) = s
                        .closest_hit(ray, f32::INFINITY)
                        .expect("every ray hits the quad");
                    assert_eq!(
                        got.map(|h| h.1),
                        Some(prim),
                        "{:?}: packet and single ray",
                        s.kind()
                    );
                    let p = s.primitive(prim);
                    assert_eq!(p.line, first, "{:?}: {:?} at {:?}", s.kind(), p.kind, ray.origin);
                    match p.kind {
                        SourceKind::Sphere => spheres_hit += 1,
                        _ => quads_hit += 1,
                    }
                }
            }
        }
        assert!(
            spheres_hit > 0 && quads_hit > 0,
            "{spheres_hit} sphere and {quads_hit} quad hits"
        );
    }
}

#[test]
fn ties_between_coincident_triangles_go_to_the_same_primitive() {
    // Ten copies of each of four triangles: every hit is a tie among ten.
    let quad = [
        [
            Vec3::new(-1.0, -1.0, 0.0),
            Vec3::new(1.0, -1.0, 0.0),
            Vec3::new(1.0, 1.0, 0.0),
        ],
        [
            Vec3::new(-1.0, -1.0, 0.0),
            Vec3::new(1.0, 1.0, 0.0),
            Vec3::new(-1.0, 1.0, 0.0),
        ],
        [
            Vec3::new(-1.0, -1.0, 2.0),
            Vec3::new(1.0, -1.0, 2.0),
            Vec3::new(1.0, 1.0, 2.0),
        ],
        [
            Vec3::new(-1.0, -1.0, 2.0),
            Vec3::new(1.0, 1.0, 2.0),
            Vec3::new(-1.0, 1.0, 2.0),
        ],
    ];
    let tris: Vec<[Vec3; 3]> = (0..10).flat_map(|_| quad).collect();
    let structures = all_three(&scene_with(&[(Vec3::new(0.0, 0.0, 1.0), 0.3)], &tris));
    let mut next = uniform(7);
    for _ in 0..500 {
        let o = Vec3::new(next() * 3.0 - 1.5, next() * 3.0 - 1.5, 5.0);
        let ray = Ray::new(o, Vec3::new(next() - 0.5, next() - 0.5, -1.0));
        assert_same_answers(&structures, &ray);
    }
}

#[test]
fn rays_along_cell_boundaries_and_axes_find_the_same_hits() {
    // A lattice of small spheres; rays parallel to the axes through the lattice points
    // run along the boundaries between cells.
    let spheres: Vec<(Vec3, f32)> = (0..8)
        .flat_map(|i| (0..8).flat_map(move |j| (0..8).map(move |k| (i, j, k))))
        .map(|(i, j, k)| (Vec3::new(i as f32, j as f32, k as f32), 0.2))
        .collect();
    let structures = all_three(&scene_with(&spheres, &[]));
    let grid = structures[1].grid().unwrap();
    assert!(grid.cells().iter().all(|&c| c > 1), "{:?}", grid.cells());
    for a in 0..8 {
        for b in 0..8 {
            let (x, y) = (a as f32 * 0.5, b as f32 * 0.5);
            for (o, d) in [
                (Vec3::new(x, y, -3.0), Vec3::new(0.0, 0.0, 1.0)),
                (Vec3::new(x, -3.0, y), Vec3::new(0.0, 1.0, 0.0)),
                (Vec3::new(10.0, x, y), Vec3::new(-1.0, 0.0, 0.0)),
                (Vec3::new(x, y, 3.5), Vec3::new(0.3, -0.2, 1.0)),
            ] {
                assert_same_answers(&structures, &Ray::new(o, d));
            }
        }
    }
}

#[test]
fn each_structure_counts_its_work() {
    let spheres: Vec<(Vec3, f32)> = (0..100)
        .map(|i| (Vec3::new(i as f32 * 3.0, 0.0, 0.0), 1.0))
        .collect();
    let structures = all_three(&scene_with(&spheres, &[]));
    // Along the row: the nearest sphere is the first.
    let ray = Ray::new(Vec3::new(-5.0, 0.0, 0.0), Vec3::new(1.0, 0.0, 0.0));
    let counts = structures.each_ref().map(|s| {
        let mut c = QueryCounts::default();
        let hit = s.closest_hit_counted(&ray, f32::INFINITY, &mut c).unwrap();
        assert!((hit.0.t - 4.0).abs() < 1e-5);
        c
    });
    // The scan tests all 100 and visits nothing; the grid stops in the first cells;
    // the BVH visits a few nodes and tests a few blocks of four.
    assert_eq!(counts[2], QueryCounts { nodes: 0, prims: 100 });
    assert!(counts[1].nodes >= 1 && counts[1].prims < 20, "{:?}", counts[1]);
    assert!(counts[0].nodes >= 1 && counts[0].prims < 40, "{:?}", counts[0]);
}
