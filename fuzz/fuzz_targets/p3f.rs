//! Any bytes into the P3F parser: it must return a scene or an error, never panic,
//! hang or allocate out of proportion to the input. A parsed scene must survive
//! `write_p3f` and a second parse with its counts and camera, and writing that again
//! must give the same text; a small one renders 8x8 pixels, every one finite.

#![no_main]

mod common;

use libfuzzer_sys::fuzz_target;
use nffrt::load::Assets;
use nffrt::nff::{parse_format, write_p3f, Format, Limits};
use nffrt::prepare;
use nffrt::options::RenderOptions;
use nffrt::render::render;

/// Longer inputs only make slower renders, not new paths.
const MAX_RENDERED: usize = 8192;

fn p3f(text: &[u8]) -> Result<nffrt::Scene, nffrt::nff::ParseError> {
    parse_format(text, Format::P3f, &Limits::default())
}

fuzz_target!(|data: &[u8]| {
    let Ok(scene) = p3f(data) else {
        return;
    };
    common::assert_round_trip(&scene, p3f, |s, w| write_p3f(s, w));
    if data.len() > MAX_RENDERED {
        return;
    }
    let scene = prepare(scene, &Assets::default());
    let pool = common::one_thread();
    let opts = RenderOptions {
        width: 8,
        height: 8,
        max_depth: 4,
        ..RenderOptions::from_view(scene.view())
    };
    let (image, _) = pool
        .install(|| render(&scene, scene.view(), &opts))
        .expect("an 8x8 render is within every limit");
    for (i, p) in image.pixels.iter().enumerate() {
        assert!(p.is_finite(), "pixel {i} is {p:?}");
    }
});
