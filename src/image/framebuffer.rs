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
        let mut bytes = Vec::with_capacity(3 * self.pixels.len());
        for p in &self.pixels {
            bytes.extend_from_slice(&[quantize(p.x), quantize(p.y), quantize(p.z)]);
        }
        bytes
    }
}

/// Maps a linear channel value to a byte (NaN maps to 0): clamped to [0, 1], scaled
/// by 255 and rounded half away from zero, as `f32::round` rounds (without its
/// library call: the fraction `x − ⌊x⌋` of a number below 256 is exact).
#[inline]
pub fn quantize(v: f32) -> u8 {
    if v.is_nan() {
        return 0;
    }
    let x = v.clamp(0.0, 1.0) * 255.0;
    let whole = x as u8;
    whole + u8::from(x - f32::from(whole) >= 0.5)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn quantize_rounds_as_f32_round_does() {
        // Every value within 64 ulps of each half-step k + 0.5 (where rounding
        // decides), and a sweep of the whole range.
        let mut values: Vec<f32> = (0..255)
            .flat_map(|k| {
                let mid = (k as f32 + 0.5) / 255.0;
                (-64i32..=64).map(move |d| f32::from_bits((mid.to_bits() as i32 + d) as u32))
            })
            .collect();
        values.extend((0..=100_000).map(|i| i as f32 / 100_000.0));
        for v in values {
            let want = (v.clamp(0.0, 1.0) * 255.0).round() as u8;
            assert_eq!(quantize(v), want, "{v:e}");
        }
    }

    #[test]
    fn quantize_clamps_and_rounds() {
        assert_eq!(quantize(-1.0), 0);
        assert_eq!(quantize(0.5), 128);
        assert_eq!(quantize(2.0), 255);
        assert_eq!(quantize(f32::NAN), 0);
        assert_eq!(quantize(1.0 / 255.0), 1);
    }
}
