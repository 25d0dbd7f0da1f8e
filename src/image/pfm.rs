//! Portable float map (`PF`, three 32-bit floats per pixel): the linear output for
//! post-processing. Written little-endian (scale `-1.0`) with rows bottom to top, as
//! the format specifies; values are the renderer's linear colours, unclamped.

use std::io::{self, Write};

use super::ppm::header_token;
use super::Image;
use crate::math::Vec3;

/// Writes `image` as a little-endian colour PFM.
pub fn encode_pfm(image: &Image, w: &mut (impl Write + ?Sized)) -> io::Result<()> {
    write!(w, "PF\n{} {}\n-1.0\n", image.width, image.height)?;
    let mut bytes = Vec::with_capacity(image.pixels.len() * 12);
    for row in image.pixels.chunks(image.width.max(1) as usize).rev() {
        for p in row {
            for c in [p.x, p.y, p.z] {
                bytes.extend_from_slice(&c.to_le_bytes());
            }
        }
    }
    w.write_all(&bytes)
}

/// Reads a colour PFM of either byte order into an image (top row first).
pub fn decode_pfm(bytes: &[u8]) -> Result<Image, String> {
    let mut pos = 0;
    let magic = header_token(bytes, &mut pos)?;
    if magic != "PF" {
        return Err(format!("not a colour PFM (magic {magic:?})"));
    }
    let mut tok = |what: &str| -> Result<String, String> {
        header_token(bytes, &mut pos).map_err(|e| format!("{what}: {e}"))
    };
    let width: u32 = tok("width")?.parse().map_err(|_| "bad width")?;
    let height: u32 = tok("height")?.parse().map_err(|_| "bad height")?;
    let scale: f32 = tok("scale")?.parse().map_err(|_| "bad scale")?;
    if scale == 0.0 || !scale.is_finite() {
        return Err(format!("bad scale {scale}"));
    }
    let little = scale < 0.0;
    let data = bytes.get(pos + 1..).ok_or("no raster data")?;
    let (w, h) = (width as usize, height as usize);
    if data.len() != w * h * 12 {
        return Err(format!("raster of {} bytes, expected {}", data.len(), w * h * 12));
    }
    let f = |c: &[u8]| {
        let b = [c[0], c[1], c[2], c[3]];
        if little {
            f32::from_le_bytes(b)
        } else {
            f32::from_be_bytes(b)
        }
    };
    let mut pixels = vec![Vec3::ZERO; w * h];
    for (k, px) in data.chunks_exact(12).enumerate() {
        // Rows are stored bottom to top.
        let (row, col) = (h - 1 - k / w, k % w);
        pixels[row * w + col] = Vec3::new(f(&px[0..4]), f(&px[4..8]), f(&px[8..12]));
    }
    Ok(Image::from_pixels(width, height, pixels))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn bytes_are_little_endian_bottom_row_first() {
        let img = Image::from_pixels(1, 2, vec![Vec3::new(1.0, 0.0, 0.0), Vec3::new(0.0, 0.0, 2.0)]);
        let mut out = Vec::new();
        encode_pfm(&img, &mut out).unwrap();
        let mut want = b"PF\n1 2\n-1.0\n".to_vec();
        // Bottom row (0, 0, 2) first; 1.0f32 = 0x3f800000, 2.0f32 = 0x40000000.
        want.extend_from_slice(&[0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0x40]);
        want.extend_from_slice(&[0, 0, 0x80, 0x3f, 0, 0, 0, 0, 0, 0, 0, 0]);
        assert_eq!(out, want);
    }

    #[test]
    fn round_trips_exactly_including_out_of_range_values() {
        let img = Image::from_pixels(
            3,
            2,
            (0..6)
                .map(|i| Vec3::new(i as f32 * 0.7 - 1.0, 1e-7 * i as f32, 12.5 + i as f32))
                .collect(),
        );
        let mut out = Vec::new();
        encode_pfm(&img, &mut out).unwrap();
        assert_eq!(decode_pfm(&out).unwrap(), img);
    }

    #[test]
    fn reads_big_endian_and_refuses_garbage() {
        let mut be = b"PF\n1 1\n1.0\n".to_vec();
        for c in [0.5f32, 0.25, 2.0] {
            be.extend_from_slice(&c.to_be_bytes());
        }
        assert_eq!(decode_pfm(&be).unwrap().get(0, 0), Vec3::new(0.5, 0.25, 2.0));
        assert!(decode_pfm(b"Pf\n1 1\n-1.0\n\0\0\0\0").is_err());
        assert!(decode_pfm(b"PF\n1 1\n-1.0\n\0\0\0\0")
            .unwrap_err()
            .contains("expected 12"));
    }
}
