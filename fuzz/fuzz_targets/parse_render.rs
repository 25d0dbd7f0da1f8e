//! Any bytes through the whole pipeline: parse, build the geometry and the BVH,
//! validate the BVH, render 8x8 pixels at depth 4 in both sampling modes. Nothing
//! may panic and every pixel must be finite.

#![no_main]

mod common;

use libfuzzer_sys::fuzz_target;
use nffrt::load::Assets;
use nffrt::nff::parse_bytes;
use nffrt::options::{RenderOptions, Sampling};
use nffrt::prepare;
use nffrt::render::render;

/// Longer inputs only make slower renders, not new paths.
const MAX_INPUT: usize = 8192;

fuzz_target!(|data: &[u8]| {
    if data.len() > MAX_INPUT {
        return;
    }
    let Ok(scene) = parse_bytes(data) else {
        return;
    };
    let scene = prepare(scene, &Assets::default());
    if let Err(e) = scene.accel().bvh().validate() {
        panic!("invalid BVH: {e}");
    }
    let pool = common::one_thread();
    for sampling in [Sampling::PixelCenters, Sampling::SpdCorners] {
        let opts = RenderOptions {
            width: 8,
            height: 8,
            max_depth: 4,
            sampling,
            ..Default::default()
        };
        let (image, _) = pool
            .install(|| render(&scene, scene.view(), &opts))
            .expect("an 8x8 render is within every limit");
        assert_eq!(image.pixels.len(), 64);
        for (i, p) in image.pixels.iter().enumerate() {
            assert!(p.is_finite(), "pixel {i} is {p:?}");
        }
    }
});
