//! Eye-ray packets against single rays on the seven SPD scenes of `../shared`: every
//! one of the 513 x 513 corner rays of `--spd` must get from
//! [`Bvh::closest_hit_packet`] (rows in packets of eight, as the renderer traces
//! them) exactly the hit [`Bvh::closest_hit`] gives it alone: distance, barycentrics
//! and primitive, ties included. (One teapot ray, meeting two triangles on their
//! shared edge, once got the other triangle from each.)

use std::path::PathBuf;

use nffrt::accel::{Bvh, PACKET};
use nffrt::geometry::build_geometry;
use nffrt::math::Ray;
use nffrt::render::Camera;

const SCENES: [&str; 7] = ["balls", "gears", "mount", "rings", "teapot", "tetra", "tree"];

#[test]
fn packets_find_the_single_ray_hits_on_every_spd_scene() {
    let dir = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../shared/scenes/spd");
    for name in SCENES {
        let path = dir.join(format!("{name}.nff"));
        let Ok(src) = std::fs::read(&path) else {
            eprintln!(
                "note: {} not found: skipping the packet check for {name}",
                path.display()
            );
            continue;
        };
        let scene = nffrt::nff::parse_bytes(&src).expect("an SPD scene parses");
        let bvh = Bvh::new(build_geometry(&scene));
        let opts = nffrt::render::RenderOptions {
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
}
