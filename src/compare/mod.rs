//! How far a test picture is from a reference: NVIDIA's FLIP ([`flip`]) and the
//! classic metrics ([`Metric`]), as one number and as a map of each pixel's error,
//! drawn in FLIP's magma colours. `nffrt diff` and Python's `nffrt.diff` both
//! come here.
//!
//! ```
//! use nffrt::compare::{compare, Metric, Picture};
//! let reference = Picture::from_rgb8(2, 1, &[0, 0, 0, 255, 255, 255]).unwrap();
//! let test = Picture::from_rgb8(2, 1, &[0, 0, 0, 255, 255, 0]).unwrap();
//! // One channel of six off by 255: MAE 1/6.
//! let mae = compare(&test, &reference, Metric::Mae).unwrap();
//! assert!((mae.value - 1.0 / 6.0).abs() < 1e-6);
//! assert_eq!(compare(&reference, &reference, Metric::Flip).unwrap().value, 0.0);
//! ```

pub mod flip;
mod magma;
mod metrics;
mod picture;

use rayon::prelude::*;

use crate::image::Image;
use crate::math::Vec3;
pub use magma::{magma_image, MAGMA};
pub use metrics::{pixel_error, summarize, Metric};
pub use picture::{Picture, Range, ReadError};

/// Why two pictures cannot be compared.
#[derive(Debug, thiserror::Error)]
pub enum CompareError {
    /// Their sizes differ.
    #[error("the test picture is {test_width}x{test_height} and the reference {width}x{height}: compare pictures of one size")]
    Size {
        /// The test picture's width.
        test_width: u32,
        /// The test picture's height.
        test_height: u32,
        /// The reference's width.
        width: u32,
        /// The reference's height.
        height: u32,
    },
    /// One is an 8-bit picture and the other a float one.
    #[error("the test picture is {} and the reference {}: compare pictures of one kind (8-bit with 8-bit, float with float)", .test.noun(), .reference.noun())]
    Range {
        /// The test picture's.
        test: Range,
        /// The reference's.
        reference: Range,
    },
    /// HDR-FLIP has no exposure to view a reference that is black everywhere at.
    #[error(
        "the reference is black everywhere: HDR-FLIP has no exposure to view it at (use another metric)"
    )]
    BlackReference,
}

/// A test picture's error against a reference.
#[derive(Clone, Debug)]
pub struct Comparison {
    /// The metric.
    pub metric: Metric,
    /// The picture's value: FLIP's mean error, the metric's mean, or PSNR in dB.
    pub value: f64,
    /// Each pixel's error, top row first: FLIP's, or the metric's per pixel (see
    /// [`pixel_error`]; for RMSE its square root).
    pub map: Vec<f32>,
    /// Width of the pictures and the map.
    pub width: u32,
    /// Height.
    pub height: u32,
    /// How FLIP viewed the pictures: `None` for LDR-FLIP (and the other metrics),
    /// HDR-FLIP's exposures otherwise.
    pub exposures: Option<flip::Exposures>,
}

/// Compares `test` with `reference` by `metric`. The pictures must be of one size
/// and one range ([`Range`]); FLIP reads 8-bit values as sRGB-encoded (LDR-FLIP)
/// and float ones as linear (HDR-FLIP, exposures chosen from the reference).
pub fn compare(test: &Picture, reference: &Picture, metric: Metric) -> Result<Comparison, CompareError> {
    if (test.width, test.height) != (reference.width, reference.height) {
        return Err(CompareError::Size {
            test_width: test.width,
            test_height: test.height,
            width: reference.width,
            height: reference.height,
        });
    }
    if test.range != reference.range {
        return Err(CompareError::Range {
            test: test.range,
            reference: reference.range,
        });
    }
    let (w, h) = (test.width as usize, test.height as usize);
    let mut exposures = None;
    let map = match metric {
        Metric::Flip => {
            let pair = |reference, test| flip::Pair {
                reference,
                test,
                width: w,
                height: h,
            };
            match reference.range {
                Range::Display => {
                    let linear = |p: &Picture| -> Vec<[f32; 3]> {
                        p.pixels.par_iter().map(|c| c.map(flip::srgb_to_linear)).collect()
                    };
                    flip::ldr_flip(pair(&linear(reference), &linear(test)), flip::default_ppd())
                }
                Range::Linear => {
                    let e = flip::Exposures::for_reference(&reference.pixels)
                        .ok_or(CompareError::BlackReference)?;
                    exposures = Some(e);
                    flip::hdr_flip(pair(&reference.pixels, &test.pixels), flip::default_ppd(), &e)
                }
            }
        }
        _ => test
            .pixels
            .par_iter()
            .zip(&reference.pixels)
            .map(|(&v, &r)| pixel_error(metric, v, r))
            .collect(),
    };
    let value = summarize(metric, &map);
    let map = if metric == Metric::Rmse {
        map.into_iter().map(f32::sqrt).collect()
    } else {
        map
    };
    Ok(Comparison {
        metric,
        value,
        map,
        width: test.width,
        height: test.height,
        exposures,
    })
}

impl Comparison {
    /// The top of the heat map's colour scale: 1 for FLIP (its errors' range, as
    /// NVIDIA draws them), the largest pixel error for the other metrics.
    pub fn heat_top(&self) -> f32 {
        match self.metric {
            Metric::Flip => 1.0,
            _ => self.map.iter().copied().fold(0.0, f32::max),
        }
    }

    /// The map drawn in magma from 0 to [`Comparison::heat_top`], for an 8-bit file.
    pub fn heat_map(&self) -> Image {
        magma_image(&self.map, self.width, self.height, self.heat_top())
    }

    /// The map's values as a grey picture (the same in R, G and B), for a float file.
    pub fn value_map(&self) -> Image {
        Image::from_pixels(
            self.width,
            self.height,
            self.map.iter().map(|&e| Vec3::splat(e)).collect(),
        )
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn linear(width: u32, height: u32, f: impl Fn(u32, u32) -> [f32; 3]) -> Picture {
        let values: Vec<f32> = (0..height)
            .flat_map(|y| (0..width).map(move |x| (x, y)))
            .flat_map(|(x, y)| f(x, y))
            .collect();
        Picture::new(width, height, &values, Range::Linear).unwrap()
    }

    #[test]
    fn sizes_and_kinds_must_match() {
        let a = Picture::from_rgb8(2, 1, &[0; 6]).unwrap();
        let b = Picture::from_rgb8(1, 2, &[0; 6]).unwrap();
        let err = compare(&a, &b, Metric::Mse).unwrap_err();
        assert_eq!(
            err.to_string(),
            "the test picture is 2x1 and the reference 1x2: compare pictures of one size"
        );
        let c = linear(2, 1, |_, _| [0.0; 3]);
        let err = compare(&c, &a, Metric::Flip).unwrap_err();
        assert!(err
            .to_string()
            .starts_with("the test picture is a float picture and the reference an 8-bit picture"));
        assert!(matches!(
            compare(&c, &c, Metric::Flip),
            Err(CompareError::BlackReference)
        ));
    }

    #[test]
    fn maps_and_values_agree() {
        let reference = linear(4, 3, |x, y| [x as f32, y as f32, 0.5]);
        let test = linear(4, 3, |x, y| [x as f32 + 0.5, y as f32, 0.5]);
        // Every pixel off by 0.5 in one channel of three.
        let mse = compare(&test, &reference, Metric::Mse).unwrap();
        assert!(mse.map.iter().all(|&e| (e - 0.25 / 3.0).abs() < 1e-7));
        let rmse = compare(&test, &reference, Metric::Rmse).unwrap();
        assert!((rmse.value - (0.25f64 / 3.0).sqrt()).abs() < 1e-7);
        assert!(rmse
            .map
            .iter()
            .all(|&e| (e as f64 - (0.25f64 / 3.0).sqrt()).abs() < 1e-6));
        assert_eq!(mse.heat_top(), 0.25 / 3.0);
        // Every pixel at the top of the scale: the last colour.
        let [r, g, b] = MAGMA[255];
        assert!(mse.heat_map().pixels.iter().all(|&p| p == Vec3::new(r, g, b)));
        assert_eq!(mse.value_map().get(3, 2), Vec3::splat(0.25 / 3.0));
        // FLIP of a linear picture: HDR-FLIP, some error, exposures recorded.
        let flip = compare(&test, &reference, Metric::Flip).unwrap();
        assert!(flip.exposures.is_some() && flip.value > 0.0 && flip.value <= 1.0);
        assert_eq!(flip.heat_top(), 1.0);
    }
}
