//! A linear-RGB `f32` image in row-major order, top row first.

use crate::math::Vec3;

/// A `width` x `height` linear-RGB image, row-major, top row first.
#[derive(Clone, Debug, PartialEq)]
pub struct Image {
    /// Width in pixels.
    pub width: u32,
    /// Height in pixels.
    pub height: u32,
    /// `width * height` pixels.
    pub pixels: Vec<Vec3>,
}

impl Image {
    /// Wraps a pixel vector; it must hold exactly `width * height` pixels.
    pub fn from_pixels(width: u32, height: u32, pixels: Vec<Vec3>) -> Image {
        assert_eq!(pixels.len(), width as usize * height as usize, "pixel count");
        Image {
            width,
            height,
            pixels,
        }
    }

    /// The pixel at column `x`, row `y`.
    pub fn get(&self, x: u32, y: u32) -> Vec3 {
        self.pixels[y as usize * self.width as usize + x as usize]
    }

    /// 8-bit RGB bytes: each channel clamped to [0, 1], scaled by 255 and rounded.
    pub fn to_rgb8(&self) -> Vec<u8> {
        self.pixels
            .iter()
            .flat_map(|p| [quantize(p.x), quantize(p.y), quantize(p.z)])
            .collect()
    }
}

/// Maps a linear channel value to a byte (NaN maps to 0).
#[inline]
pub fn quantize(v: f32) -> u8 {
    if v.is_nan() {
        return 0;
    }
    (v.clamp(0.0, 1.0) * 255.0).round() as u8
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn quantize_clamps_and_rounds() {
        assert_eq!(quantize(-1.0), 0);
        assert_eq!(quantize(0.5), 128);
        assert_eq!(quantize(2.0), 255);
        assert_eq!(quantize(f32::NAN), 0);
        assert_eq!(quantize(1.0 / 255.0), 1);
    }
}
