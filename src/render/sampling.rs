//! Where eye rays go through each pixel: the sampling patterns and their seeds.
//!
//! Stratified jittered supersampling with `spp = N` samples per pixel divides the
//! pixel into `cols x rows` equal strata, `cols * rows = N`, with `cols >= rows` the
//! factor pair closest to square (4 -> 2x2, 9 -> 3x3, 8 -> 4x2, 2 -> 2x1, a prime
//! N -> Nx1), and places one sample uniformly at random in each stratum. The pixel
//! value is the plain mean of its samples (a box filter over the pixel).
//!
//! The random offsets come from a hash of the absolute pixel coordinates and the
//! sample index (SplitMix64's finalizer), not from a per-thread generator: every
//! run, every thread count and every tile of a split render sees the same sample
//! positions, so images are identical and tiles merge byte for byte. `spp = 1` is
//! one sample at the pixel centre, with no jitter.

use std::fmt;

/// Where eye rays go through each pixel.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Sampling {
    /// One ray through each pixel centre.
    PixelCenters,
    /// The SPD benchmark protocol: one ray through each pixel corner
    /// ((w+1) x (h+1) rays), the four corner values averaged into each pixel.
    SpdCorners,
    /// Stratified jittered supersampling with `spp` samples per pixel, box-filtered
    /// (see the module docs); `spp = 1` is [`Sampling::PixelCenters`].
    Stratified {
        /// Samples per pixel, at least 1.
        spp: u32,
    },
}

impl fmt::Display for Sampling {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Sampling::PixelCenters => write!(f, "centres"),
            Sampling::SpdCorners => write!(f, "spd-corners"),
            Sampling::Stratified { spp } => write!(f, "stratified-{spp}"),
        }
    }
}

/// The strata of one pixel for stratified sampling.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Strata {
    /// Strata across the pixel.
    pub cols: u32,
    /// Strata down the pixel.
    pub rows: u32,
}

impl Strata {
    /// The most nearly square `cols x rows = spp` grid with `cols >= rows`
    /// (`spp` of 0 is taken as 1).
    pub fn new(spp: u32) -> Strata {
        let spp = spp.max(1);
        let mut rows = (spp as f64).sqrt() as u32;
        while rows > 1 && !spp.is_multiple_of(rows) {
            rows -= 1;
        }
        let rows = rows.max(1);
        Strata {
            cols: spp / rows,
            rows,
        }
    }

    /// Samples per pixel.
    pub fn samples(&self) -> u32 {
        self.cols * self.rows
    }

    /// Raster position of sample `s` (`0..samples()`) of pixel `(x, y)`: the pixel
    /// centre for a single sample, otherwise a hashed point in stratum `s` (row-major).
    #[inline]
    pub fn position(&self, x: u32, y: u32, s: u32) -> (f32, f32) {
        if self.samples() == 1 {
            return (x as f32 + 0.5, y as f32 + 0.5);
        }
        let (u, v) = jitter(x, y, s);
        let (cx, cy) = (s % self.cols, s / self.cols);
        (
            x as f32 + (cx as f32 + u) / self.cols as f32,
            y as f32 + (cy as f32 + v) / self.rows as f32,
        )
    }
}

/// SplitMix64's output function (Steele, Lea and Flood 2014): a bijective 64-bit mix.
#[inline]
fn mix(z: u64) -> u64 {
    let z = z.wrapping_add(0x9E37_79B9_7F4A_7C15);
    let z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
    let z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
    z ^ (z >> 31)
}

/// Two numbers in [0, 1) for sample `s` of pixel `(x, y)`, from 24 bits each.
#[inline]
pub fn jitter(x: u32, y: u32, s: u32) -> (f32, f32) {
    let h = mix(mix(((x as u64) << 32) | y as u64) ^ s as u64);
    let scale = 1.0 / (1u32 << 24) as f32;
    ((h >> 40) as f32 * scale, ((h >> 8) & 0xFF_FFFF) as f32 * scale)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn strata_are_the_squarest_factor_pair() {
        let shape = |n| {
            let s = Strata::new(n);
            (s.cols, s.rows)
        };
        assert_eq!(shape(1), (1, 1));
        assert_eq!(shape(2), (2, 1));
        assert_eq!(shape(4), (2, 2));
        assert_eq!(shape(7), (7, 1));
        assert_eq!(shape(8), (4, 2));
        assert_eq!(shape(12), (4, 3));
        assert_eq!(shape(16), (4, 4));
        assert_eq!(shape(0), (1, 1));
    }

    #[test]
    fn one_sample_is_the_pixel_centre() {
        assert_eq!(Strata::new(1).position(7, 3, 0), (7.5, 3.5));
    }

    #[test]
    fn every_sample_lies_in_its_own_stratum() {
        for spp in [2, 4, 6, 9, 16] {
            let st = Strata::new(spp);
            for (x, y) in [(0, 0), (5, 9), (511, 0), (1000, 1000)] {
                for s in 0..spp {
                    let (px, py) = st.position(x, y, s);
                    let (cx, cy) = (s % st.cols, s / st.cols);
                    let fx = (px - x as f32) * st.cols as f32 - cx as f32;
                    let fy = (py - y as f32) * st.rows as f32 - cy as f32;
                    assert!((0.0..1.0).contains(&fx) && (0.0..1.0).contains(&fy), "{spp} {s}");
                }
            }
        }
    }

    #[test]
    fn jitter_depends_on_pixel_and_sample_only() {
        assert_eq!(jitter(3, 4, 2), jitter(3, 4, 2));
        // Swapped coordinates, neighbours and other samples get other offsets.
        let all = [jitter(3, 4, 2), jitter(4, 3, 2), jitter(3, 5, 2), jitter(3, 4, 3)];
        for i in 0..all.len() {
            for j in i + 1..all.len() {
                assert_ne!(all[i], all[j]);
            }
        }
        // Roughly uniform: the mean of many offsets is near 1/2.
        let n = 10_000;
        let mean: f32 = (0..n).map(|i| jitter(i, 0, 0).0).sum::<f32>() / n as f32;
        assert!((mean - 0.5).abs() < 0.02, "{mean}");
    }
}
