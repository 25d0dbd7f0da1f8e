//! # nffrt — a fast, correct Whitted ray tracer for NFF scenes
//!
//! NFF (Eric Haines' Neutral File Format) is the scene format of the Standard
//! Procedural Databases. This crate parses it ([`nff`]), describes the scene
//! ([`scene`]) and renders it; [`gen`] makes the SPD's classic scenes at any size.
//!
//! ```
//! let scene = nffrt::nff::parse("v from 0 0 5 at 0 0 0 up 0 1 0 angle 40 hither 1 resolution 8 8\n\
//!                                f 1 1 1 1 0 1 0 1\ns 0 0 0 1\n").unwrap();
//! assert_eq!(scene.spheres[0].radius, 1.0);
//! ```

#![warn(missing_docs)]
#![forbid(unsafe_code)]

pub mod gen;
pub mod math;
pub mod nff;
pub mod scene;

pub use scene::Scene;
