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

    /// 8-bit RGB bytes: each channel clamped to [0, 1], scaled by 255 and rounded
    /// ([`Encoding::Linear`]).
    pub fn to_rgb8(&self) -> Vec<u8> {
        self.to_rgb8_as(Encoding::Linear)
    }

    /// 8-bit RGB bytes in `encoding`.
    pub fn to_rgb8_as(&self, encoding: Encoding) -> Vec<u8> {
        let byte = encoding.quantizer();
        let mut bytes = Vec::with_capacity(3 * self.pixels.len());
        for p in &self.pixels {
            bytes.extend_from_slice(&[byte(p.x), byte(p.y), byte(p.z)]);
        }
        bytes
    }
}

/// How an 8-bit file (PNG, PPM) holds the linear values; float files (PFM, EXR)
/// hold them as they are.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub enum Encoding {
    /// Clamped to [0, 1] and scaled ([`quantize`]): NFF and P3F colours are display
    /// values, as in the SPD's and the course's own Whitted pictures.
    #[default]
    Linear,
    /// Clamped, then through the sRGB transfer curve ([`quantize_srgb`]), as POV-Ray
    /// and pbrt write their pictures.
    Srgb,
    /// Clamped, then raised to the power 1/2.2 ([`quantize_gamma22`]): the course's
    /// path-tracing template's `toGamma`.
    Gamma22,
}

impl Encoding {
    /// Every encoding, in the order of their names in messages.
    pub const ALL: [Encoding; 3] = [Encoding::Linear, Encoding::Srgb, Encoding::Gamma22];

    /// The function from a linear channel value to its byte.
    pub fn quantizer(self) -> fn(f32) -> u8 {
        match self {
            Encoding::Linear => quantize,
            Encoding::Srgb => quantize_srgb,
            Encoding::Gamma22 => quantize_gamma22,
        }
    }

    /// Its name, as `--encoding` takes it: `linear`, `srgb`, `gamma2.2`.
    pub fn name(self) -> &'static str {
        match self {
            Encoding::Linear => "linear",
            Encoding::Srgb => "srgb",
            Encoding::Gamma22 => "gamma2.2",
        }
    }

    /// The encoding of that name.
    pub fn from_name(name: &str) -> Option<Encoding> {
        Encoding::ALL.into_iter().find(|e| e.name() == name)
    }
}

impl std::fmt::Display for Encoding {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(self.name())
    }
}

impl serde::Serialize for Encoding {
    fn serialize<S: serde::Serializer>(&self, s: S) -> Result<S::Ok, S::Error> {
        s.serialize_str(self.name())
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

/// Maps a linear channel value to its sRGB-encoded byte (NaN maps to 0): clamped to
/// [0, 1], encoded by the sRGB curve of IEC 61966-2-1 — 12.92·v up to 0.0031308,
/// 1.055·v^(1/2.4) − 0.055 above — then scaled and rounded as [`quantize`] does.
pub fn quantize_srgb(v: f32) -> u8 {
    if v.is_nan() {
        return 0;
    }
    let v = v.clamp(0.0, 1.0);
    let encoded = if v <= 0.003_130_8 {
        12.92 * v
    } else {
        1.055 * v.powf(1.0 / 2.4) - 0.055
    };
    quantize(encoded)
}

/// Maps a linear channel value to its gamma-2.2-encoded byte (NaN maps to 0):
/// clamped to [0, 1], raised to the power 1/2.2 (the course's `toGamma`, whose
/// result the framebuffer clamps), then scaled and rounded as [`quantize`] does.
pub fn quantize_gamma22(v: f32) -> u8 {
    if v.is_nan() {
        return 0;
    }
    quantize(v.clamp(0.0, 1.0).powf(1.0 / 2.2))
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
    fn srgb_bytes_are_the_curves() {
        // By hand: 1.055 · 0.5^(1/2.4) − 0.055 = 0.73535, · 255 = 187.5 -> 188 (the
        // sRGB code of linear one half); 0.1 -> 89.04; 0.18 -> 117.6; the linear
        // part, 12.92 · 0.002 · 255 = 6.59 -> 7.
        for (v, want) in [
            (0.5, 188),
            (0.1, 89),
            (0.15, 108),
            (0.3, 149),
            (0.18, 118),
            (0.002, 7),
        ] {
            assert_eq!(quantize_srgb(v), want, "{v}");
        }
        assert_eq!(quantize_srgb(-1.0), 0);
        assert_eq!(quantize_srgb(1.0), 255);
        assert_eq!(quantize_srgb(7.0), 255);
        assert_eq!(quantize_srgb(f32::NAN), 0);
        let image = Image::from_pixels(1, 1, vec![Vec3::new(0.1, 0.15, 0.3)]);
        assert_eq!(image.to_rgb8_as(Encoding::Srgb), [89, 108, 149]);
        assert_eq!(image.to_rgb8(), [26, 38, 77]);
    }

    #[test]
    fn gamma_bytes_are_the_power_curve() {
        // By hand: 0.5^(1/2.2) = 0.72974, · 255 = 186.08 -> 186; 0.1^(1/2.2) =
        // 0.35111 -> 89.53 -> 90; 0.01^(1/2.2) = 0.12328 -> 31.44 -> 31;
        // 0.002^(1/2.2) = 0.05937 -> 15.14 -> 15 (no linear toe, unlike sRGB's 7).
        for (v, want) in [(0.5, 186), (0.1, 90), (0.01, 31), (0.002, 15)] {
            assert_eq!(quantize_gamma22(v), want, "{v}");
        }
        assert_eq!(quantize_gamma22(-1.0), 0);
        assert_eq!(quantize_gamma22(3.0), 255);
        assert_eq!(quantize_gamma22(f32::NAN), 0);
        for e in Encoding::ALL {
            assert_eq!(Encoding::from_name(e.name()), Some(e));
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
