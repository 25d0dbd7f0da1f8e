//! PNG encoding (8-bit RGB) and decoding through the `png` crate.

use std::io::{Read, Write};

use super::Image;

/// Encodes `image` as an 8-bit RGB PNG into `w`, with optional text chunks.
pub fn encode_png(image: &Image, text: &[(&str, String)], w: impl Write) -> Result<(), png::EncodingError> {
    encode_png_rgb8(image.width, image.height, &image.to_rgb8(), text, w)
}

/// Encodes raw 8-bit RGB bytes (`width * height * 3`, top row first) as a PNG with
/// the same settings as [`encode_png`], so equal pixels and text give equal files.
pub fn encode_png_rgb8(
    width: u32,
    height: u32,
    rgb: &[u8],
    text: &[(&str, String)],
    w: impl Write,
) -> Result<(), png::EncodingError> {
    let mut enc = png::Encoder::new(w, width, height);
    enc.set_color(png::ColorType::Rgb);
    enc.set_depth(png::BitDepth::Eight);
    for (k, v) in text {
        enc.add_text_chunk(k.to_string(), v.clone())?;
    }
    let mut writer = enc.write_header()?;
    writer.write_image_data(rgb)?;
    writer.finish()
}

/// A decoded 8-bit RGB PNG and its text chunks.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct DecodedPng {
    /// Width in pixels.
    pub width: u32,
    /// Height in pixels.
    pub height: u32,
    /// `width * height * 3` bytes, top row first.
    pub rgb: Vec<u8>,
    /// `tEXt`, `zTXt` and `iTXt` chunks as (keyword, text), in file order per kind.
    pub text: Vec<(String, String)>,
}

impl DecodedPng {
    /// The text of the first chunk with this keyword.
    pub fn text(&self, key: &str) -> Option<&str> {
        self.text.iter().find(|(k, _)| k == key).map(|(_, v)| v.as_str())
    }
}

/// Decodes an 8-bit RGB PNG (as nffrt writes them); other colour types and depths
/// are refused.
pub fn decode_png(r: impl Read) -> Result<DecodedPng, String> {
    let mut dec = png::Decoder::new(r);
    dec.set_transformations(png::Transformations::IDENTITY);
    let mut reader = dec.read_info().map_err(|e| e.to_string())?;
    let mut buf = vec![0; reader.output_buffer_size()];
    let frame = reader.next_frame(&mut buf).map_err(|e| e.to_string())?;
    if frame.color_type != png::ColorType::Rgb || frame.bit_depth != png::BitDepth::Eight {
        return Err(format!(
            "{:?} {:?} PNG (only 8-bit RGB, as nffrt writes, is read)",
            frame.color_type, frame.bit_depth
        ));
    }
    buf.truncate(frame.buffer_size());
    // Text chunks after the image data are only seen once the whole file is read.
    reader.finish().map_err(|e| e.to_string())?;
    let info = reader.info();
    let mut text: Vec<(String, String)> = info
        .uncompressed_latin1_text
        .iter()
        .map(|t| (t.keyword.clone(), t.text.clone()))
        .collect();
    for t in &info.compressed_latin1_text {
        let mut t = t.clone();
        t.decompress_text().map_err(|e| e.to_string())?;
        text.push((t.keyword.clone(), t.get_text().map_err(|e| e.to_string())?));
    }
    for t in &info.utf8_text {
        let mut t = t.clone();
        t.decompress_text().map_err(|e| e.to_string())?;
        text.push((t.keyword.clone(), t.get_text().map_err(|e| e.to_string())?));
    }
    Ok(DecodedPng {
        width: frame.width,
        height: frame.height,
        rgb: buf,
        text,
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::math::Vec3;

    #[test]
    fn round_trips_pixels_and_text() {
        let img = Image::from_pixels(
            3,
            2,
            vec![
                Vec3::new(0.0, 0.5, 1.0),
                Vec3::new(2.0, -1.0, 0.2),
                Vec3::splat(1.0 / 255.0),
                Vec3::ZERO,
                Vec3::ONE,
                Vec3::new(0.25, 0.75, 0.1),
            ],
        );
        let mut out = Vec::new();
        encode_png(
            &img,
            &[
                ("Software", "nffrt".into()),
                ("nffrt:region", "1,2,4,4,8,8".into()),
            ],
            &mut out,
        )
        .unwrap();
        assert!(out.starts_with(b"\x89PNG\r\n\x1a\n"));
        let d = decode_png(&out[..]).unwrap();
        assert_eq!((d.width, d.height), (3, 2));
        // Clamped, scaled by 255 and rounded: 0.5 -> 128, 0.2 -> 51, 0.75 -> 191, 0.1 -> 26.
        assert_eq!(
            d.rgb,
            [0, 128, 255, 255, 0, 51, 1, 1, 1, 0, 0, 0, 255, 255, 255, 64, 191, 26]
        );
        assert_eq!(d.text("Software"), Some("nffrt"));
        assert_eq!(d.text("nffrt:region"), Some("1,2,4,4,8,8"));
        assert_eq!(d.text("Author"), None);
    }

    #[test]
    fn refuses_other_colour_types_and_garbage() {
        let mut out = Vec::new();
        let mut enc = png::Encoder::new(&mut out, 1, 1);
        enc.set_color(png::ColorType::Grayscale);
        enc.write_header().unwrap().write_image_data(&[7]).unwrap();
        assert!(decode_png(&out[..]).unwrap_err().contains("only 8-bit RGB"));
        assert!(decode_png(&b"not a png"[..]).is_err());
    }
}
