//! # nffrt — a fast, correct ray tracer for NFF and P3F scenes
//!
//! NFF (Eric Haines' Neutral File Format) is the scene format of the Standard
//! Procedural Databases, and P3F the extended NFF of the IST course that builds on
//! it. The pipeline, one direction of travel: [`load`] reads a scene (parsed by
//! [`nff`] into a [`Scene`]) and the images it names; [`prepare()`] makes it a
//! [`RenderScene`] — the render-time primitives ([`geometry`]) in an acceleration
//! structure ([`accel`]), the materials, light sources, background and shading
//! rules — built once; [`render`] traces images of it, each with its own camera and
//! options ([`render::render_region`]: a crop with exactly the full render's
//! pixels; [`render::debug::trace_pixel`]: one pixel's ray tree); [`image`] encodes
//! them and assembles tiles; [`output`] writes files whole or not at all. [`limits`] holds every limit and default; [`gen`] makes
//! the SPD's classic scenes, at sizes up to 10 million primitives.
//!
//! ```
//! use nffrt::{load::Assets, options::RenderOptions, prepare, render::render};
//! let scene = nffrt::nff::parse("v from 0 0 5 at 0 0 0 up 0 1 0 angle 40 hither 1 resolution 8 8\n\
//!                                l 0 0 10\nf 1 1 1 1 0 1 0 1\ns 0 0 0 1\n").unwrap();
//! let scene = prepare(scene, &Assets::default());
//! let (image, stats) = render(&scene, scene.view(), &RenderOptions::from_view(scene.view())).unwrap();
//! assert_eq!(stats.eye_rays, 64);
//! assert!(image.get(4, 4).x > 0.5); // the sphere fills the centre
//! ```

#![warn(missing_docs)]
// No `unsafe` but in `denoise::ffi`, the calls into Open Image Denoise's C library opened at run
// time, in `accel::traverse::avx`, the run-time-selected AVX traversal kernels (7 % off
// whole renders, measured in BENCHMARKS.md), and in `pages`, one `madvise` asking for huge pages
// under the big arrays of the geometry and the BVH (+16 to +25 % rays per second on a 524 288-
// triangle mount, BENCHMARKS.md), each allowing it for itself alone.
#![deny(unsafe_code)]

pub mod accel;
pub mod aff;
pub mod compare;
pub mod denoise;
pub mod fingerprint;
pub mod gen;
pub mod geometry;
pub mod image;
pub mod limits;
pub mod load;
pub mod math;
pub mod nff;
pub mod options;
pub mod output;
mod pages;
pub mod prepare;
pub mod render;
pub mod scene;
pub mod words;

// The tests' one way of saying that a check is skipped (tests/common/skip.rs).
#[cfg(test)]
#[path = "../tests/common/skip.rs"]
mod test_skip;

pub use prepare::{prepare, RenderScene};
pub use scene::Scene;

/// A short, lower-case description of an I/O error, the same wording everywhere:
/// `no such file or directory`, `permission denied`, `is a directory`, `the reader
/// closed the pipe`, or the system's own text for anything else.
pub fn io_reason(e: &std::io::Error) -> String {
    match e.kind() {
        std::io::ErrorKind::NotFound => "no such file or directory".into(),
        std::io::ErrorKind::PermissionDenied => "permission denied".into(),
        std::io::ErrorKind::IsADirectory => "is a directory".into(),
        std::io::ErrorKind::BrokenPipe => "the reader closed the pipe".into(),
        _ => e.to_string(),
    }
}
