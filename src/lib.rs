//! # nffrt — a fast, correct Whitted ray tracer for NFF scenes
//!
//! NFF (Eric Haines' Neutral File Format) is the scene format of the Standard
//! Procedural Databases, and P3F, the extended NFF of the IST course that builds on
//! it. The pipeline: [`nff::parse`] text into a [`Scene`] ([`load`] reads a file and
//! the images it names);
//! [`geometry::build_geometry`] converts it into render-time primitives;
//! [`accel::Bvh::new`] builds the hierarchy; [`render::render`] traces the image;
//! [`image`] encodes it. [`gen`] makes the SPD's classic scenes, at sizes up to 10 million primitives.
//! [`PreparedScene`] owns a scene and its BVH, built once, and renders it with
//! checked options (the one object the Python bindings hold).
//! [`render::render_region`] traces a crop with exactly the full render's pixels,
//! and [`image::tiles`] assembles such crops; [`render::debug::trace_pixel`] keeps
//! the ray tree of one pixel.
//!
//! ```
//! use nffrt::{accel::Bvh, geometry::build_geometry, render::{render, RenderOptions}};
//! let scene = nffrt::nff::parse("v from 0 0 5 at 0 0 0 up 0 1 0 angle 40 hither 1 resolution 8 8\n\
//!                                l 0 0 10\nf 1 1 1 1 0 1 0 1\ns 0 0 0 1\n").unwrap();
//! let bvh = Bvh::new(build_geometry(&scene));
//! let (image, stats) = render(&scene, &bvh, &RenderOptions::from_scene(&scene));
//! assert_eq!(stats.eye_rays, 64);
//! assert!(image.get(4, 4).x > 0.5); // the sphere fills the centre
//! ```

#![warn(missing_docs)]
// No `unsafe` but in `accel::traverse::avx`, the run-time-selected AVX traversal kernels (7 % off
// whole renders, measured in BENCHMARKS.md), which allows it for itself alone.
#![deny(unsafe_code)]

pub mod accel;
pub mod fingerprint;
pub mod gen;
pub mod geometry;
pub mod image;
pub mod limits;
pub mod load;
pub mod math;
pub mod nff;
pub mod prepared;
pub mod render;
pub mod scene;

// The tests' one way of saying that a check is skipped (tests/common/skip.rs).
#[cfg(test)]
#[path = "../tests/common/skip.rs"]
mod test_skip;

pub use prepared::PreparedScene;
pub use scene::Scene;

/// A short, lower-case description of an I/O error, the same wording everywhere:
/// `no such file or directory`, `permission denied`, `is a directory`, or the
/// system's own text for anything else.
pub fn io_reason(e: &std::io::Error) -> String {
    match e.kind() {
        std::io::ErrorKind::NotFound => "no such file or directory".into(),
        std::io::ErrorKind::PermissionDenied => "permission denied".into(),
        std::io::ErrorKind::IsADirectory => "is a directory".into(),
        _ => e.to_string(),
    }
}
