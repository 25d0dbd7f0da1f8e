//! Binary PPM (`P6`, 8-bit RGB): encoder and a small decoder for tests and tools.

use std::io::{self, Write};

use super::Image;

/// Writes `image` as binary PPM (`P6`, maxval 255) with the crate's colour mapping.
pub fn encode_ppm(image: &Image, w: &mut (impl Write + ?Sized)) -> io::Result<()> {
    encode_ppm_rgb8(image.width, image.height, &image.to_rgb8(), w)
}

/// Writes 8-bit RGB bytes (`width * height * 3`, top row first) as binary PPM.
pub fn encode_ppm_rgb8(width: u32, height: u32, rgb: &[u8], w: &mut (impl Write + ?Sized)) -> io::Result<()> {
    write!(w, "P6\n{width} {height}\n255\n")?;
    w.write_all(rgb)
}

/// Reads a binary PPM with maxval 255: `(width, height, RGB bytes)`. Comments (`#`
/// to the end of the line) are allowed in the header, as the format permits.
pub fn decode_ppm(bytes: &[u8]) -> Result<(u32, u32, Vec<u8>), String> {
    let ppm = decode_ppm_raster(bytes, u64::MAX)?;
    if ppm.trailing > 0 {
        let want = ppm.rgb.len();
        return Err(format!(
            "raster of {} bytes, expected {want}",
            want + ppm.trailing
        ));
    }
    Ok((ppm.width, ppm.height, ppm.rgb))
}

/// A binary PPM's image, and how many bytes followed its raster.
#[derive(Clone, Debug, PartialEq)]
pub struct PpmRaster {
    /// Width in pixels.
    pub width: u32,
    /// Height in pixels.
    pub height: u32,
    /// `width * height` RGB triples, top row first.
    pub rgb: Vec<u8>,
    /// Bytes after the raster (a final newline that some writers add).
    pub trailing: usize,
}

/// Reads a binary PPM with maxval 255 and at most `max_pixels` pixels, leaving any
/// bytes after its raster to the caller ([`PpmRaster::trailing`]).
pub fn decode_ppm_raster(bytes: &[u8], max_pixels: u64) -> Result<PpmRaster, String> {
    let mut pos = 0;
    let magic = header_token(bytes, &mut pos)?;
    if magic != "P6" {
        return Err(format!("not a binary PPM (magic {magic:?})"));
    }
    let mut num = |what: &str| -> Result<u32, String> {
        let t = header_token(bytes, &mut pos)?;
        t.parse().map_err(|_| format!("bad {what} {t:?}"))
    };
    let (width, height, maxval) = (num("width")?, num("height")?, num("maxval")?);
    if maxval != 255 {
        return Err(format!("maxval {maxval} (only 255 is supported)"));
    }
    let pixels = width as u64 * height as u64;
    if pixels > max_pixels {
        return Err(format!(
            "{width} x {height} pixels, more than the {max_pixels} allowed"
        ));
    }
    // Exactly one whitespace byte separates the header from the raster.
    let data = bytes.get(pos + 1..).ok_or("no raster data")?;
    let want = pixels as usize * 3;
    if data.len() < want {
        return Err(format!("raster of {} bytes, expected {want}", data.len()));
    }
    Ok(PpmRaster {
        width,
        height,
        rgb: data[..want].to_vec(),
        trailing: data.len() - want,
    })
}

/// The next whitespace-separated header token of a PNM/PFM file, skipping comments;
/// leaves `pos` on the byte just after it.
pub(super) fn header_token(bytes: &[u8], pos: &mut usize) -> Result<String, String> {
    loop {
        match bytes.get(*pos) {
            None => return Err("truncated header".into()),
            Some(b'#') => {
                while bytes.get(*pos).is_some_and(|&b| b != b'\n') {
                    *pos += 1;
                }
            }
            Some(b) if b.is_ascii_whitespace() => *pos += 1,
            Some(_) => break,
        }
    }
    let start = *pos;
    while bytes.get(*pos).is_some_and(|b| !b.is_ascii_whitespace()) {
        *pos += 1;
    }
    if *pos >= bytes.len() {
        return Err("truncated header".into());
    }
    Ok(String::from_utf8_lossy(&bytes[start..*pos]).into_owned())
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::math::Vec3;

    fn two_pixels() -> Image {
        Image::from_pixels(2, 1, vec![Vec3::new(1.0, 0.0, 0.5), Vec3::new(2.0, -1.0, 0.2)])
    }

    #[test]
    fn bytes_are_the_p6_layout() {
        let mut out = Vec::new();
        encode_ppm(&two_pixels(), &mut out).unwrap();
        // 0.5 * 255 = 127.5 rounds to 128; 0.2 * 255 = 51.
        assert_eq!(out, b"P6\n2 1\n255\n\xff\x00\x80\xff\x00\x33");
    }

    #[test]
    fn round_trips_and_reads_comments() {
        let mut out = Vec::new();
        encode_ppm(&two_pixels(), &mut out).unwrap();
        let (w, h, rgb) = decode_ppm(&out).unwrap();
        assert_eq!((w, h), (2, 1));
        assert_eq!(rgb, two_pixels().to_rgb8());
        let commented = b"P6 # a comment\n1 1\n# another\n255\n\x01\x02\x03";
        assert_eq!(decode_ppm(commented).unwrap(), (1, 1, vec![1, 2, 3]));
    }

    #[test]
    fn refuses_broken_files() {
        assert!(decode_ppm(b"P5\n1 1\n255\n\x00").is_err());
        assert!(decode_ppm(b"P6\n2 2\n255\n\x00\x00\x00")
            .unwrap_err()
            .contains("expected 12"));
        assert!(decode_ppm(b"P6\n1 1\n65535\n\x00\x00\x00").is_err());
        assert!(decode_ppm(b"P6\n1").is_err());
    }
}
