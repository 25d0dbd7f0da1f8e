//! PNG encoding (8-bit RGB) through the `png` crate.

use std::io::Write;

use super::Image;

/// Encodes `image` as an 8-bit RGB PNG into `w`, with optional text chunks.
pub fn encode_png(image: &Image, text: &[(&str, String)], w: impl Write) -> Result<(), png::EncodingError> {
    let mut enc = png::Encoder::new(w, image.width, image.height);
    enc.set_color(png::ColorType::Rgb);
    enc.set_depth(png::BitDepth::Eight);
    for (k, v) in text {
        enc.add_text_chunk(k.to_string(), v.clone())?;
    }
    let mut writer = enc.write_header()?;
    writer.write_image_data(&image.to_rgb8())?;
    writer.finish()
}
