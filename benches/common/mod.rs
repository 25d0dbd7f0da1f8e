//! Scenes for the benchmarks: generated with `nffrt::gen`, so no data file is needed.

#![allow(dead_code)]

use nffrt::gen::{generate, SpdScene};
use nffrt::math::Ray;
use nffrt::render::Camera;
use nffrt::Scene;

/// An SPD scene at the given size.
pub fn scene(which: SpdScene, size: u32) -> Scene {
    generate(which, size).expect("generator sizes used here are valid")
}

/// The scene as NFF text.
pub fn nff_text(scene: &Scene) -> String {
    let mut out = Vec::new();
    nffrt::nff::write_nff(scene, &mut out).expect("writing to memory");
    String::from_utf8(out).expect("the writer emits ASCII")
}

/// One primary ray through each pixel centre at `w` x `h`.
pub fn primary_rays(scene: &Scene, w: u32, h: u32) -> Vec<Ray> {
    let opts = nffrt::options::RenderOptions {
        width: w,
        height: h,
        ..Default::default()
    };
    let camera = Camera::new(&scene.view, &opts);
    (0..h)
        .flat_map(|j| (0..w).map(move |i| camera.ray_at(i as f32 + 0.5, j as f32 + 0.5)))
        .collect()
}
