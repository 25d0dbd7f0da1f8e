//! Eye-ray packets against single rays on the seven SPD scenes: every one of the
//! 513 x 513 corner rays of `--spd` must get from [`Bvh::closest_hit_packet`] (rows
//! in packets of eight, as the renderer traces them) exactly the hit
//! [`Bvh::closest_hit`] gives it alone: distance, barycentrics and primitive, ties
//! included. (One teapot ray, meeting two triangles on their shared edge, once got
//! the other triangle from each.)
//!
//! The scenes are those `nffrt gen` writes at the default sizes (within 1e-4 of the
//! SPD's files, tests/gen_spd.rs), so the check runs on every machine; the SPD's own
//! files in `../shared`, whose numbers found that tie, are checked too when present.

use nffrt::accel::{Bvh, PACKET};
use nffrt::gen::{generate, SpdScene};
use nffrt::geometry::build_geometry;
use nffrt::math::Ray;
use nffrt::render::Camera;
use nffrt::Scene;

#[path = "common/skip.rs"]
mod skip;

/// Packets and single rays agree on every corner ray of `scene` at 512 x 512.
fn packets_agree_with_single_rays(name: &str, scene: &Scene) {
    let bvh = Bvh::new(build_geometry(scene));
    let opts = nffrt::options::RenderOptions {
        width: 512,
        height: 512,
        ..Default::default()
    };
    let camera = Camera::new(&scene.view, &opts);
    let bits = |h: Option<(nffrt::geometry::Hit, u32)>| {
        h.map(|(h, p)| (h.t.to_bits(), h.u.to_bits(), h.v.to_bits(), p))
    };
    let (mut hits, mut out) = (0, [None; PACKET]);
    for y in 0..=512u32 {
        let row: Vec<Ray> = (0..=512u32).map(|x| camera.ray_at(x as f32, y as f32)).collect();
        for (c, packet) in row.chunks(PACKET).enumerate() {
            let out = &mut out[..packet.len()];
            bvh.closest_hit_packet(packet, f32::INFINITY, out);
            for (k, (ray, &got)) in packet.iter().zip(out.iter()).enumerate() {
                let single = bvh.closest_hit(ray, f32::INFINITY);
                assert_eq!(
                    bits(got),
                    bits(single),
                    "{name}: corner ({}, {y})",
                    c * PACKET + k
                );
                hits += usize::from(got.is_some());
            }
        }
    }
    // The fewest eye hits, tetra's, are about 50 000 (SPD-INVARIANTS.md).
    assert!(hits > 40_000, "{name}: {hits} eye hits");
}

/// The scene as `nffrt gen NAME` writes it (NFF text, read back).
fn generated(which: SpdScene) -> Scene {
    let mut text = Vec::new();
    nffrt::nff::write_nff(&generate(which, which.default_size()).unwrap(), &mut text).unwrap();
    nffrt::nff::parse_bytes(&text).expect("a generated scene parses")
}

#[test]
fn packets_find_the_single_ray_hits_on_every_generated_spd_scene() {
    for which in SpdScene::ALL {
        packets_agree_with_single_rays(&format!("generated {which}"), &generated(which));
    }
}

#[test]
fn packets_find_the_single_ray_hits_on_every_spd_file() {
    let Some(dir) = skip::shared("scenes/spd") else {
        return;
    };
    for which in SpdScene::ALL {
        let path = dir.join(format!("{which}.nff"));
        let src = std::fs::read(&path).unwrap_or_else(|e| panic!("{}: {e}", path.display()));
        let scene = nffrt::nff::parse_bytes(&src).expect("an SPD scene parses");
        packets_agree_with_single_rays(&which.to_string(), &scene);
    }
}
