//! Images: the linear floating-point framebuffer, its encoders and decoders, the
//! tiles of a split render (and the bands to split it in), the skybox cube map, and
//! the textures AFF's surfaces sample, and an accumulation buffer (the mean of
//! pictures: motion blur).
//!
//! Colour mapping (one documented default): each linear channel is clamped to [0, 1],
//! multiplied by 255 and rounded to the nearest integer. No gamma curve is applied:
//! NFF colours are display values, as in the SPD's own pictures.
//! [`Encoding::Srgb`] and [`Encoding::Gamma22`] apply the sRGB curve or the power
//! 1/2.2 instead (path-traced pictures take one by default: `options`). PFM and OpenEXR
//! output skip the mapping and keep the linear values as they are.

mod accumulate;
mod bands;
mod exr;
mod format;
mod framebuffer;
mod pfm;
mod png;
mod ppm;
pub mod region;
pub mod skybox;
mod texture;
pub mod tiles;

pub use self::exr::{decode_exr, decode_exr_channels, encode_exr, encode_exr_layers};
pub use self::png::{decode_png, decode_png_values, encode_png, encode_png_rgb8, DecodedPng};
pub use accumulate::Accumulator;
pub use bands::bands;
pub use format::{png_error, ImageFormat, SOFTWARE_TEXT};
pub use framebuffer::{quantize, quantize_gamma22, quantize_srgb, Encoding, Image};
pub use pfm::{decode_pfm, encode_pfm};
pub use ppm::{decode_ppm, decode_ppm_raster, encode_ppm, encode_ppm_rgb8, PpmRaster};
pub use region::Region;
pub use texture::Texture;
