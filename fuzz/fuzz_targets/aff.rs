//! Any bytes as the top file of an AFF scene: it must load or be refused, never
//! panic, hang or allocate out of proportion. Includes and textures are found in
//! `fuzz/corpus/aff-files/` (BART's scene files and textures, linked there by
//! `fuzz/seed.sh`), so that an input may include any of them. A scene that loads
//! is flattened at its first, middle and last frames: each must come out or be
//! refused, and a frame's coordinates must be finite; a small frame's BVH must
//! validate.

#![no_main]

use std::path::Path;
use std::sync::atomic::AtomicBool;

use libfuzzer_sys::fuzz_target;
use nffrt::aff::{parse, AffSource};
use nffrt::load::Assets;
use nffrt::nff::Limits;
use nffrt::prepare;

/// Where the inputs' includes and textures are found.
const FILES: &str = concat!(env!("CARGO_MANIFEST_DIR"), "/corpus/aff-files");

/// Frames of at most this many primitives get their BVH built and validated.
const SMALL_FRAME: usize = 4096;

fuzz_target!(|data: &[u8]| {
    static NEVER: AtomicBool = AtomicBool::new(false);
    let source = AffSource {
        name: "input.aff",
        path: None,
        bytes: data,
        dir: Path::new(FILES),
    };
    // Limits well above BART's scenes, far below what would exhaust memory.
    let limits = Limits {
        max_primitives: 1 << 20,
        max_vertices: 1 << 21,
        max_lights: 1 << 10,
    };
    let Ok(parsed) = parse(source, &limits, 64 << 20, &NEVER) else {
        return;
    };
    let aff = parsed.scene;
    let frames = aff.frames();
    for n in [0, frames / 2, frames.saturating_sub(1)] {
        let Ok(frame) = aff.flatten(aff.time_of_frame(n)) else {
            continue;
        };
        let finite = |v: &[nffrt::math::Vec3]| v.iter().all(|p| p.is_finite());
        assert!(
            finite(&frame.polygon_vertices) && finite(&frame.patch_vertices) && finite(&frame.mesh_vertices)
        );
        assert!(frame
            .spheres
            .iter()
            .all(|s| s.center.is_finite() && s.radius.is_finite()));
        assert!(frame.view.from.is_finite() && frame.view.at.is_finite() && frame.view.up.is_finite());
        if frame.primitive_count() <= SMALL_FRAME {
            let scene = prepare(frame, &Assets::default());
            if let Err(e) = scene.accel().bvh().validate() {
                panic!("invalid BVH: {e}");
            }
        }
    }
});
