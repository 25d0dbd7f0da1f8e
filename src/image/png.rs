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

/// A PNG of any colour type and depth as RGB values in [0, 1] (`width * height * 3`,
/// top row first), each channel its stored value over the depth's largest (255 or
/// 65535), as stored: no curve applied. Grey is repeated in R, G and B, a palette
/// looked up, and alpha ignored (as NVIDIA's FLIP reads pictures). Refused before
/// decoding when it has more than `max_pixels` pixels.
pub fn decode_png_values(r: impl Read, max_pixels: u64) -> Result<(u32, u32, Vec<f32>), String> {
    // Room for the largest picture allowed at 16-bit RGBA, 8 bytes a pixel.
    let bytes = usize::try_from(max_pixels.saturating_mul(8)).unwrap_or(usize::MAX);
    let mut dec = png::Decoder::new_with_limits(
        r,
        png::Limits {
            bytes: bytes.saturating_add(1 << 20),
        },
    );
    dec.set_transformations(png::Transformations::EXPAND);
    let mut reader = dec.read_info().map_err(|e| e.to_string())?;
    let (width, height) = reader.info().size();
    if width as u64 * height as u64 > max_pixels {
        return Err(format!(
            "a {width}x{height} picture has more than {max_pixels} pixels"
        ));
    }
    let mut buf = vec![0; reader.output_buffer_size()];
    let frame = reader.next_frame(&mut buf).map_err(|e| e.to_string())?;
    buf.truncate(frame.buffer_size());
    let channels = frame.color_type.samples();
    let values: Vec<f32> = match frame.bit_depth {
        png::BitDepth::Eight => buf.iter().map(|&v| v as f32 / 255.0).collect(),
        png::BitDepth::Sixteen => buf
            .chunks_exact(2)
            .map(|b| u16::from_be_bytes([b[0], b[1]]) as f32 / 65535.0)
            .collect(),
        depth => return Err(format!("{depth:?}-bit samples after expansion")),
    };
    let rgb = values
        .chunks_exact(channels)
        .flat_map(|p| match channels {
            1 | 2 => [p[0]; 3],
            _ => [p[0], p[1], p[2]],
        })
        .collect();
    Ok((width, height, rgb))
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

    #[test]
    fn reads_every_colour_type_as_values_in_0_1() {
        let encode = |color, depth, data: &[u8]| {
            let mut out = Vec::new();
            let mut enc = png::Encoder::new(&mut out, 2, 1);
            enc.set_color(color);
            enc.set_depth(depth);
            enc.write_header().unwrap().write_image_data(data).unwrap();
            out
        };
        let read = |bytes: Vec<u8>| decode_png_values(&bytes[..], 100).unwrap();
        use png::{BitDepth::*, ColorType::*};
        let rgb = read(encode(Rgb, Eight, &[0, 51, 255, 255, 102, 0]));
        assert_eq!(rgb, (2, 1, vec![0.0, 0.2, 1.0, 1.0, 0.4, 0.0]));
        // Alpha ignored; grey repeated.
        let rgba = read(encode(Rgba, Eight, &[0, 51, 255, 7, 255, 102, 0, 0]));
        assert_eq!(rgba, rgb);
        assert_eq!(
            read(encode(GrayscaleAlpha, Eight, &[51, 0, 255, 9])).2,
            [0.2, 0.2, 0.2, 1.0, 1.0, 1.0]
        );
        // 16-bit samples are big-endian: 0x3333 / 0xffff = 0.2.
        let wide = read(encode(Grayscale, Sixteen, &[0x33, 0x33, 0xff, 0xff]));
        assert_eq!(wide.2, [0.2, 0.2, 0.2, 1.0, 1.0, 1.0]);
        assert!(decode_png_values(&encode(Rgb, Eight, &[0; 6])[..], 1)
            .unwrap_err()
            .contains("more than 1 pixels"));
        assert!(decode_png_values(&b"not a png"[..], 100).is_err());
    }
}
