//! Images: the linear floating-point framebuffer, its encoders and decoders, the
//! tiles of a split render (and the bands to split it in), and the skybox cube map.
//!
//! Colour mapping (one documented choice): each linear channel is clamped to [0, 1],
//! multiplied by 255 and rounded to the nearest integer. No gamma curve is applied:
//! NFF colours are display values, as in the SPD's own pictures. PFM output skips the
//! mapping and keeps the linear values as they are.

mod bands;
mod format;
mod framebuffer;
mod pfm;
mod png;
mod ppm;
pub mod region;
pub mod skybox;
pub mod tiles;

pub use self::png::{decode_png, encode_png, encode_png_rgb8, DecodedPng};
pub use bands::bands;
pub use format::{png_error, ImageFormat, SOFTWARE_TEXT};
pub use framebuffer::{quantize, Image};
pub use pfm::{decode_pfm, encode_pfm};
pub use ppm::{decode_ppm, encode_ppm};
pub use region::Region;
