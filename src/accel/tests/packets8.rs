//! The eight-ray queries (`Bvh::closest_hits8`, `Bvh::occluded8`) give every active
//! ray exactly its single-ray answer, with the kernels this CPU chose and with the
//! portable ones: random scenes, coherent packets and packets of mixed octants, rays
//! along the axes, inactive lanes holding garbage, per-ray limits.

use super::*;
use crate::accel::leaf::ray8::Ray8;
use crate::accel::traverse::packet::Coherence;
use crate::accel::traverse::wide::Portable;

/// A direction component: mostly random, sometimes exactly zero (of either sign).
fn component() -> impl Strategy<Value = f32> {
    prop_oneof![6 => -1.0f32..1.0, 1 => Just(0.0f32), 1 => Just(-0.0f32)]
}

/// A packet: eight rays from around one origin, either spread a little around one
/// direction (coherent, the camera's case) or each its own (mixed octants).
fn packet() -> impl Strategy<Value = Vec<Ray>> {
    let jitter = prop::collection::vec((v3(0.05), (component(), component(), component())), 8);
    (
        v3(12.0),
        (component(), component(), component()),
        jitter,
        any::<bool>(),
    )
        .prop_map(|(o, (x, y, z), jitter, coherent)| {
            let base = Vec3::new(x, y, z);
            jitter
                .into_iter()
                .map(|(dj, (jx, jy, jz))| {
                    let own = Vec3::new(jx, jy, jz);
                    let d = if coherent && base.length() > 0.1 {
                        base + own * 0.02
                    } else if own.length() > 0.1 {
                        own
                    } else {
                        Vec3::new(0.0, 0.0, -1.0)
                    };
                    Ray::new(o + dj, d)
                })
                .collect()
        })
}

/// A limit: none, near, far, or zero.
fn limit() -> impl Strategy<Value = f32> {
    prop_oneof![3 => Just(f32::INFINITY), 2 => 0.5f32..30.0, 1 => Just(0.0f32)]
}

/// `rays` packed, with the inactive lanes' origins and directions spoiled (the
/// queries must not look at them).
fn packed(rays: &[Ray], active: u32) -> Ray8 {
    let mut r = Ray8::new(rays);
    for k in (0..8).filter(|k| active >> k & 1 == 0) {
        for axis in 0..3 {
            r.origin[axis][k] = f32::NAN;
            r.dir[axis][k] = 0.0;
            r.inv[axis][k] = f32::NAN;
        }
    }
    r
}

fn bits(h: &Option<(Hit, u32)>) -> Option<(u32, u32, u32, u32)> {
    h.map(|(h, p)| (h.t.to_bits(), h.u.to_bits(), h.v.to_bits(), p))
}

/// Asserts that both kernels answer every packet as each ray alone, whichever walk
/// the packet takes.
fn assert_packets_agree(bvh: &Bvh, packets: &[(Vec<Ray>, u32, [f32; 8])]) -> Result<(), TestCaseError> {
    for coherence in [Coherence::Coherent, Coherence::Mixed] {
        assert_packets_agree_by(bvh, packets, coherence)?;
    }
    Ok(())
}

fn assert_packets_agree_by(
    bvh: &Bvh,
    packets: &[(Vec<Ray>, u32, [f32; 8])],
    coherence: Coherence,
) -> Result<(), TestCaseError> {
    for (rays, active, limits) in packets {
        let r = packed(rays, *active);
        let t_max = limits[0];
        let mut got = [None; 8];
        let mut portable = [None; 8];
        bvh.closest_hits8(&r, t_max, *active, coherence, &mut got);
        bvh.closest_hits8_with(Portable, &r, t_max, *active, coherence, &mut portable);
        let blocked = bvh.occluded8(&r, limits, *active, coherence);
        let blocked_portable = bvh.occluded8_with(Portable, &r, limits, *active, coherence);
        for (k, ray) in rays.iter().enumerate() {
            if active >> k & 1 == 0 {
                prop_assert!(got[k].is_none() && portable[k].is_none());
                prop_assert_eq!(blocked >> k & 1, 0);
                prop_assert_eq!(blocked_portable >> k & 1, 0);
                continue;
            }
            let single = bits(&bvh.closest_hit(ray, t_max));
            prop_assert_eq!(bits(&got[k]), single, "ray {} ({:?})", k, coherence);
            prop_assert_eq!(
                bits(&portable[k]),
                single,
                "ray {}, portable ({:?})",
                k,
                coherence
            );
            let occluded = bvh.occluded(ray, limits[k]);
            prop_assert_eq!(
                blocked >> k & 1 != 0,
                occluded,
                "ray {} below {} ({:?})",
                k,
                limits[k],
                coherence
            );
            prop_assert_eq!(
                blocked_portable >> k & 1 != 0,
                occluded,
                "ray {}, portable ({:?})",
                k,
                coherence
            );
        }
    }
    Ok(())
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(64))]

    #[test]
    fn eight_ray_queries_give_each_ray_its_single_ray_answer(
        spheres in prop::collection::vec((v3(10.0), 0.05f32..2.0), 0..40),
        tris in prop::collection::vec((v3(10.0), v3(2.0), v3(2.0)), 0..300),
        packets in prop::collection::vec((packet(), 0u32..256, prop::array::uniform8(limit())), 1..12),
    ) {
        let tris: Vec<[Vec3; 3]> = tris.iter().map(|&(a, d1, d2)| [a, a + d1, a + d2]).collect();
        let bvh = Bvh::new(build_geometry(&scene_with(&spheres, &tris)));
        assert_packets_agree(&bvh, &packets)?;
    }
}

/// A deep tree (a grid of 20 000 small triangles and spheres) under camera packets
/// from several eyes, some aimed along the axes, all lanes and some, so the walks
/// go through many levels of their stack, the frustum test, the single-ray handover
/// and the eight-ray triangle tests.
#[test]
fn eight_ray_queries_agree_on_a_deep_tree() {
    let mut tris = Vec::new();
    for i in 0..100 {
        for j in 0..100 {
            let (x, y) = (i as f32 * 0.2 - 10.0, j as f32 * 0.2 - 10.0);
            let z = ((i * 7 + j * 3) % 5) as f32 * 0.05;
            let (a, b, c, d) = (
                Vec3::new(x, y, z),
                Vec3::new(x + 0.2, y, z),
                Vec3::new(x, y + 0.2, z),
                Vec3::new(x + 0.2, y + 0.2, z),
            );
            tris.push([a, b, c]);
            tris.push([b, d, c]);
        }
    }
    let spheres: Vec<(Vec3, f32)> = (0..400)
        .map(|i| {
            (
                Vec3::new((i % 20) as f32 - 10.0, (i / 20) as f32 - 10.0, 1.0),
                0.3,
            )
        })
        .collect();
    let bvh = bvh_of(&scene_with(&spheres, &tris));
    let mut packets = Vec::new();
    for (e, eye) in [
        Vec3::new(0.3, -2.0, 25.0),
        Vec3::new(0.0, 0.0, 8.0),
        Vec3::new(-15.0, 3.0, 0.5),
    ]
    .into_iter()
    .enumerate()
    {
        for j in 0..16 {
            for i in 0..8 {
                let rays: Vec<Ray> = (0..8)
                    .map(|k| {
                        let target = Vec3::new((i * 8 + k) as f32 * 0.3 - 9.5, j as f32 * 1.2 - 9.5, 0.0);
                        let d = if (i + j) % 7 == 0 && k == 3 {
                            Vec3::new(0.0, 0.0, -1.0)
                        } else {
                            (target - eye).normalize()
                        };
                        Ray::new(eye, d)
                    })
                    .collect();
                let active = if (i + j + e) % 3 == 0 { 0b1011_0110 } else { 0xff };
                let limits = std::array::from_fn(|k| [f32::INFINITY, 20.0, 24.9][(k + i) % 3]);
                packets.push((rays, active, limits));
            }
        }
    }
    assert_packets_agree(&bvh, &packets).unwrap();
}
