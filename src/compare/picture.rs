//! The pictures `nffrt diff` compares, read from PNG, PPM, PFM or OpenEXR files
//! (chosen by extension) or made from pixels: RGB values and what they are, display
//! values of an 8-bit picture or the linear values of a float one.

use std::fmt;
use std::path::Path;

use crate::image::{decode_exr, decode_pfm, decode_png_values, decode_ppm, ImageFormat};
use crate::limits::DEFAULT_MAX_PIXELS;

/// What a picture's values are.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Range {
    /// An 8-bit (or 16-bit PNG) picture for display: values in [0, 1], encoded
    /// for a screen (FLIP reads them as sRGB).
    Display,
    /// A float picture (PFM, OpenEXR, an array of floats): linear values of any
    /// range, as a renderer traced them.
    Linear,
}

impl Range {
    /// How messages name pictures of this range.
    pub fn noun(self) -> &'static str {
        match self {
            Range::Display => "an 8-bit picture",
            Range::Linear => "a float picture",
        }
    }
}

/// A picture to compare: `width * height` RGB pixels, top row first.
#[derive(Clone, Debug, PartialEq)]
pub struct Picture {
    /// Width in pixels, at least 1.
    pub width: u32,
    /// Height in pixels, at least 1.
    pub height: u32,
    /// The pixels, every value finite.
    pub pixels: Vec<[f32; 3]>,
    /// What the values are.
    pub range: Range,
}

/// Why a picture could not be had.
#[derive(Debug)]
pub enum ReadError {
    /// The file could not be read.
    Io(std::io::Error),
    /// Its extension names no picture format.
    UnknownFormat,
    /// The file is not a picture of its format, or its values are unusable.
    Malformed(String),
}

impl fmt::Display for ReadError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            ReadError::Io(e) => write!(f, "cannot read picture: {}", crate::io_reason(e)),
            ReadError::UnknownFormat => write!(f, "unknown image format (use .png, .ppm, .pfm or .exr)"),
            ReadError::Malformed(m) => write!(f, "not a usable picture: {m}"),
        }
    }
}

impl Picture {
    /// An 8-bit picture from `width * height * 3` bytes.
    pub fn from_rgb8(width: u32, height: u32, rgb: &[u8]) -> Result<Picture, String> {
        let values: Vec<f32> = rgb.iter().map(|&v| v as f32 / 255.0).collect();
        Picture::new(width, height, &values, Range::Display)
    }

    /// A picture of `range` from `width * height * 3` values; refused when the
    /// count is wrong, the picture empty or larger than [`DEFAULT_MAX_PIXELS`], or a value
    /// not finite (named by its pixel).
    pub fn new(width: u32, height: u32, values: &[f32], range: Range) -> Result<Picture, String> {
        let pixels_count = width as u64 * height as u64;
        if pixels_count == 0 || pixels_count > DEFAULT_MAX_PIXELS {
            return Err(format!(
                "a {width}x{height} picture (from 1 to {DEFAULT_MAX_PIXELS} pixels are compared)"
            ));
        }
        if values.len() as u64 != pixels_count * 3 {
            return Err(format!("{} values for {width}x{height} RGB pixels", values.len()));
        }
        if let Some(k) = values.iter().position(|v| !v.is_finite()) {
            let p = k / 3;
            let (x, y) = (p % width as usize, p / width as usize);
            return Err(format!(
                "pixel ({x}, {y}) holds {}, not a number FLIP can compare",
                values[k]
            ));
        }
        let pixels = values.chunks_exact(3).map(|c| [c[0], c[1], c[2]]).collect();
        Ok(Picture {
            width,
            height,
            pixels,
            range,
        })
    }

    /// Reads the picture at `path`, its format chosen by extension.
    pub fn read(path: &Path) -> Result<Picture, ReadError> {
        let format = ImageFormat::from_extension(path).ok_or(ReadError::UnknownFormat)?;
        if path.is_dir() {
            let e = std::io::Error::new(std::io::ErrorKind::IsADirectory, "is a directory");
            return Err(ReadError::Io(e));
        }
        let bytes = std::fs::read(path).map_err(ReadError::Io)?;
        Picture::decode(&bytes, format).map_err(ReadError::Malformed)
    }

    /// Decodes a file's bytes in `format`.
    pub fn decode(bytes: &[u8], format: ImageFormat) -> Result<Picture, String> {
        match format {
            ImageFormat::Png => {
                let (w, h, values) = decode_png_values(bytes, DEFAULT_MAX_PIXELS)?;
                Picture::new(w, h, &values, Range::Display)
            }
            ImageFormat::Ppm => {
                let (w, h, rgb) = decode_ppm(bytes)?;
                Picture::from_rgb8(w, h, &rgb)
            }
            ImageFormat::Pfm | ImageFormat::Exr => {
                let image = if format == ImageFormat::Pfm {
                    decode_pfm(bytes)?
                } else {
                    decode_exr(bytes)?
                };
                let values: Vec<f32> = image.pixels.iter().flat_map(|p| [p.x, p.y, p.z]).collect();
                Picture::new(image.width, image.height, &values, Range::Linear)
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::image::{encode_exr, encode_pfm, encode_png_rgb8, encode_ppm_rgb8, Image};
    use crate::math::Vec3;

    #[test]
    fn every_format_reads_as_its_range() {
        let rgb = [0u8, 51, 255, 255, 102, 0];
        let mut png = Vec::new();
        encode_png_rgb8(2, 1, &rgb, &[], &mut png).unwrap();
        let mut ppm = Vec::new();
        encode_ppm_rgb8(2, 1, &rgb, &mut ppm).unwrap();
        let want = Picture {
            width: 2,
            height: 1,
            pixels: vec![[0.0, 0.2, 1.0], [1.0, 0.4, 0.0]],
            range: Range::Display,
        };
        assert_eq!(Picture::decode(&png, ImageFormat::Png).unwrap(), want);
        assert_eq!(Picture::decode(&ppm, ImageFormat::Ppm).unwrap(), want);
        let image = Image::from_pixels(1, 2, vec![Vec3::new(2.5, -1.0, 0.0), Vec3::splat(0.25)]);
        let linear = Picture {
            width: 1,
            height: 2,
            pixels: vec![[2.5, -1.0, 0.0], [0.25; 3]],
            range: Range::Linear,
        };
        let (mut pfm, mut exr) = (Vec::new(), Vec::new());
        encode_pfm(&image, &mut pfm).unwrap();
        encode_exr(&image, &mut exr).unwrap();
        assert_eq!(Picture::decode(&pfm, ImageFormat::Pfm).unwrap(), linear);
        assert_eq!(Picture::decode(&exr, ImageFormat::Exr).unwrap(), linear);
    }

    #[test]
    fn refuses_what_cannot_be_compared() {
        let nan = Picture::new(
            2,
            2,
            &[0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, f32::NAN, 0.0, 0.0, 0.0, 0.0],
            Range::Linear,
        );
        assert!(nan.unwrap_err().contains("pixel (0, 1) holds NaN"));
        assert!(Picture::new(0, 3, &[], Range::Linear).is_err());
        assert!(Picture::new(1, 1, &[0.0; 4], Range::Linear).is_err());
        assert!(Picture::decode(b"P6\n1 1\n255\n", ImageFormat::Ppm).is_err());
        let missing = Picture::read(Path::new("/nonexistent/a.png")).unwrap_err();
        assert!(matches!(missing, ReadError::Io(_)));
        assert_eq!(
            missing.to_string(),
            "cannot read picture: no such file or directory"
        );
        assert!(matches!(
            Picture::read(Path::new("a.jpg")),
            Err(ReadError::UnknownFormat)
        ));
    }
}
