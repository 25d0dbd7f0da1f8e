//! Images: the linear floating-point framebuffer and its encoders.
//!
//! Colour mapping (one documented choice): each linear channel is clamped to [0, 1],
//! multiplied by 255 and rounded to the nearest integer. No gamma curve is applied:
//! NFF colours are display values, as in the SPD's own pictures.

mod framebuffer;
mod png;

pub use self::png::encode_png;
pub use framebuffer::Image;
