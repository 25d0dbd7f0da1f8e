//! Textures: 8-bit RGB images that a surface samples at texture coordinates
//! `(u, v)`, bilinearly, wrapping as BART's original renderer wraps (its
//! `Texture::sample` in tuituji/bart `src/texture.cpp`; docs/aff.md):
//!
//! ```text
//! u' = u - trunc(u), plus 1 if negative        (the same for v: the fraction in [0, 1))
//! x  = u' (W - 3),  y = v' (H - 3)             (texel space; W x H texels, row 0 the file's first)
//! colour = bilinear mix of texels (⌊x⌋, ⌊y⌋), (⌊x⌋+1, ⌊y⌋), (⌊x⌋, ⌊y⌋+1), (⌊x⌋+1, ⌊y⌋+1),
//!          weights (1-fx)(1-fy), fx(1-fy), (1-fx) fy, fx fy;  fx = x - ⌊x⌋, fy = y - ⌊y⌋
//! ```
//!
//! The scale by `W - 3` (not `W`) is the original's: it keeps the right-hand texel
//! of the mix inside the image, and leaves the last two columns and rows unseen.
//! Texel values are `byte / 255`. A texture narrower or shorter than 3 texels (where
//! the original reads outside its image) has its texel indices clamped to the image.

use crate::math::Vec3;

/// An 8-bit RGB image sampled by texture coordinates (see the module docs).
#[derive(Clone, PartialEq)]
pub struct Texture {
    width: u32,
    height: u32,
    /// `width * height` RGB triples, the top row (the file's first) first.
    rgb: Vec<u8>,
}

impl std::fmt::Debug for Texture {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "Texture({}x{})", self.width, self.height)
    }
}

impl Texture {
    /// The image of `width * height` RGB triples `rgb`, top row first; `None` if
    /// the sizes disagree or a side is 0.
    pub fn new(width: u32, height: u32, rgb: Vec<u8>) -> Option<Texture> {
        let texels = width as u64 * height as u64;
        (texels > 0 && rgb.len() as u64 == 3 * texels).then_some(Texture { width, height, rgb })
    }

    /// Width in texels.
    pub fn width(&self) -> u32 {
        self.width
    }

    /// Height in texels.
    pub fn height(&self) -> u32 {
        self.height
    }

    /// The RGB triples, top row first.
    pub fn rgb(&self) -> &[u8] {
        &self.rgb
    }

    /// Texel `(x, y)` (column, row from the top) as linear values `byte / 255`,
    /// its indices clamped to the image.
    #[inline]
    pub fn texel(&self, x: i64, y: i64) -> Vec3 {
        let x = x.clamp(0, self.width as i64 - 1) as usize;
        let y = y.clamp(0, self.height as i64 - 1) as usize;
        let i = 3 * (y * self.width as usize + x);
        let c = &self.rgb[i..i + 3];
        Vec3::new(c[0] as f32, c[1] as f32, c[2] as f32) * (1.0 / 255.0)
    }

    /// The colour at texture coordinates `(u, v)`: bilinear, wrapped as the
    /// module docs say. Coordinates that are not finite give texel (0, 0)'s
    /// neighbourhood, never a panic.
    pub fn sample(&self, u: f32, v: f32) -> Vec3 {
        let (x, fx) = Self::texel_coordinate(u, self.width);
        let (y, fy) = Self::texel_coordinate(v, self.height);
        self.texel(x, y) * ((1.0 - fx) * (1.0 - fy))
            + self.texel(x + 1, y) * (fx * (1.0 - fy))
            + self.texel(x, y + 1) * ((1.0 - fx) * fy)
            + self.texel(x + 1, y + 1) * (fx * fy)
    }

    /// A texture coordinate wrapped to its fraction, scaled by `side - 3`: the
    /// texel index and the fraction past it.
    #[inline]
    fn texel_coordinate(c: f32, side: u32) -> (i64, f32) {
        let mut c = c - c.trunc();
        if c < 0.0 {
            c += 1.0;
        }
        let scaled = c * (side as f32 - 3.0);
        if !scaled.is_finite() {
            return (0, 0.0);
        }
        let i = scaled.floor();
        (i as i64, scaled - i)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A 5 x 4 texture whose texel (x, y) is (10 x, 10 y, 7).
    fn ramp() -> Texture {
        let mut rgb = Vec::new();
        for y in 0..4u8 {
            for x in 0..5u8 {
                rgb.extend([10 * x, 10 * y, 7]);
            }
        }
        Texture::new(5, 4, rgb).unwrap()
    }

    fn close(a: Vec3, b: Vec3) -> bool {
        (a - b).abs().max_elem() < 1e-6
    }

    #[test]
    fn samples_bilinearly_on_the_originals_scale() {
        let t = ramp();
        let k = 1.0 / 255.0;
        // u = 0.25 on a 5-wide texture: x = 0.25 * 2 = 0.5, between columns 0 and 1;
        // v = 0.5 on 4 rows: y = 0.5 * 1 = 0.5, between rows 0 and 1.
        let c = t.sample(0.25, 0.5);
        assert!(close(c, Vec3::new(5.0 * k, 5.0 * k, 7.0 * k)), "{c:?}");
        // Texel centres are integers: u = 0.5 is x = 1 exactly.
        assert!(close(t.sample(0.5, 0.0), Vec3::new(10.0 * k, 0.0, 7.0 * k)));
    }

    #[test]
    fn wraps_by_the_fraction_of_the_coordinate() {
        let t = ramp();
        // 1.25 and -0.75 wrap to 0.25; 1 and -1 to 0.
        assert_eq!(t.sample(1.25, 0.5), t.sample(0.25, 0.5));
        assert_eq!(t.sample(-0.75, 0.5), t.sample(0.25, 0.5));
        assert_eq!(t.sample(1.0, 2.0), t.sample(0.0, 0.0));
        assert_eq!(t.sample(-1.0, -3.0), t.sample(0.0, 0.0));
    }

    #[test]
    fn tiny_and_odd_inputs_never_panic() {
        let one = Texture::new(1, 1, vec![255, 0, 0]).unwrap();
        for (u, v) in [
            (0.3, 0.7),
            (f32::NAN, 1.0),
            (f32::INFINITY, -1e30),
            (-1e-12, 0.99999),
        ] {
            assert!(close(one.sample(u, v), Vec3::new(1.0, 0.0, 0.0)), "({u}, {v})");
            let _ = ramp().sample(u, v);
        }
        assert!(Texture::new(2, 2, vec![0; 11]).is_none());
        assert!(Texture::new(0, 2, Vec::new()).is_none());
    }
}
