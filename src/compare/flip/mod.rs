//! NVIDIA's FLIP, the perceptual difference of a test picture from a reference as a
//! viewer flipping between them sees it: an error map in [0, 1] and its mean.
//!
//! LDR-FLIP compares pictures for display (values in [0, 1], linear RGB here);
//! HDR-FLIP exposes linear pictures of any range at several exposures, tone-maps each
//! with ACES and keeps the largest LDR-FLIP error of each pixel. A port of NVIDIA's
//! reference implementation (`FLIP.h` of <https://github.com/NVlabs/flip>, version
//! 1.7, BSD-3-Clause; Andersson et al., HPG 2020 and Eurographics 2021) with its
//! default viewing conditions (67 pixels per degree) and tone mapper (ACES); the
//! tests in python/tests/test_diff.py hold its means to NVIDIA's `flip-evaluator`.

mod color;
mod filters;

use rayon::prelude::*;

pub use color::{default_ppd, srgb_to_linear};
use color::{linear_rgb_to_xyz, luminance, tone_map, xyz_to_ycxcz, ACES};
use filters::{apply_feature_difference, color_difference, feature_filter, SpatialFilters};

/// A picture in YCxCz, one plane per channel, top row first.
pub struct Planes {
    width: usize,
    height: usize,
    y: Vec<f32>,
    cx: Vec<f32>,
    cz: Vec<f32>,
}

impl Planes {
    /// Linear RGB pixels (row by row) in YCxCz.
    fn from_linear_rgb(pixels: &[[f32; 3]], width: usize, height: usize) -> Planes {
        let ycxcz: Vec<[f32; 3]> = pixels
            .par_iter()
            .map(|&c| xyz_to_ycxcz(linear_rgb_to_xyz(c)))
            .collect();
        Planes {
            width,
            height,
            y: ycxcz.iter().map(|c| c[0]).collect(),
            cx: ycxcz.iter().map(|c| c[1]).collect(),
            cz: ycxcz.iter().map(|c| c[2]).collect(),
        }
    }
}

/// The two pictures FLIP compares: linear RGB pixels of one size, row by row.
#[derive(Clone, Copy)]
pub struct Pair<'a> {
    /// The reference.
    pub reference: &'a [[f32; 3]],
    /// The picture compared with it.
    pub test: &'a [[f32; 3]],
    /// Their width.
    pub width: usize,
    /// Their height.
    pub height: usize,
}

impl Pair<'_> {
    /// Both pictures with `f` applied to each channel value.
    fn map(&self, f: impl Fn(f32) -> f32 + Sync) -> (Vec<[f32; 3]>, Vec<[f32; 3]>) {
        let each = |p: &[[f32; 3]]| -> Vec<[f32; 3]> { p.par_iter().map(|c| c.map(&f)).collect() };
        rayon::join(|| each(self.reference), || each(self.test))
    }

    /// LDR-FLIP of pictures already in [0, 1].
    fn ldr_flip_unclamped(&self, ppd: f32) -> Vec<f32> {
        let (w, h) = (self.width, self.height);
        let (reference, test) = rayon::join(
            || Planes::from_linear_rgb(self.reference, w, h),
            || Planes::from_linear_rgb(self.test, w, h),
        );
        let mut error = color_difference(&reference, &test, &SpatialFilters::new(ppd));
        apply_feature_difference(&reference, &test, &feature_filter(ppd), &mut error);
        error
    }
}

/// LDR-FLIP's error map of the pair (each channel clamped to [0, 1] first), viewed
/// at `ppd` pixels per degree.
pub fn ldr_flip(pair: Pair<'_>, ppd: f32) -> Vec<f32> {
    let n = pair.width * pair.height;
    debug_assert!(pair.reference.len() == n && pair.test.len() == n && n > 0);
    let (reference, test) = pair.map(|v| v.clamp(0.0, 1.0));
    Pair {
        reference: &reference,
        test: &test,
        ..pair
    }
    .ldr_flip_unclamped(ppd)
}

/// The exposures HDR-FLIP views its pictures at: `count` stops evenly spaced from
/// `start` to `stop` (exposure e scales the linear values by 2^e).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Exposures {
    /// The first exposure, which maps the reference's brightest pixel to 0.85 after
    /// tone mapping.
    pub start: f32,
    /// The last, which does the same for its median luminance.
    pub stop: f32,
    /// How many, at least 2.
    pub count: u32,
}

impl Exposures {
    /// HDR-FLIP's automatic exposures for `reference` (linear RGB): from the one at
    /// which the tone-mapped brightest luminance is 0.85 to the one at which the
    /// median's is, one per stop, at least two. `None` when the reference is black
    /// everywhere (there is no brightest luminance to expose for).
    pub fn for_reference(reference: &[[f32; 3]]) -> Option<Exposures> {
        // The luminance x_max that the tone curve maps to 0.85: the larger root of
        // (a - t d) x² + (b - t e) x + (c - t f) = 0.
        let t = 0.85;
        let k = ACES;
        let (a, b, c) = (k[0] - t * k[3], k[1] - t * k[4], k[2] - t * k[5]);
        let x_max = if a == 0.0 {
            -c / b
        } else {
            let d1 = -0.5 * (b / a);
            d1 + (d1 * d1 - c / a).sqrt()
        };
        let mut luminances: Vec<f32> = reference.iter().map(|&p| luminance(p)).collect();
        let y_max = luminances.iter().copied().fold(-1e30f32, f32::max);
        let middle = luminances.len() / 2;
        let (_, &mut median, _) = luminances.select_nth_unstable_by(middle, f32::total_cmp);
        // flip-evaluator 1.7: a median of 0 (more than half the picture black) is
        // taken as f32's epsilon.
        let median = median.max(f32::EPSILON);
        let start = (x_max / y_max).log2();
        let stop = (x_max / median).log2();
        if !(start.is_finite() && stop.is_finite() && start <= stop) {
            return None;
        }
        let count = (stop - start).ceil().max(2.0) as u32;
        Some(Exposures { start, stop, count })
    }

    /// The `i`th exposure.
    fn at(&self, i: u32) -> f32 {
        let step = (self.stop - self.start) / (self.count - 1) as f32;
        self.start + i as f32 * step
    }
}

/// HDR-FLIP's error map of the pair (linear RGB of any range): at each of
/// `exposures`, both pictures scaled, tone-mapped with ACES, clamped to [0, 1] and
/// compared by LDR-FLIP; each pixel keeps its largest error.
pub fn hdr_flip(pair: Pair<'_>, ppd: f32, exposures: &Exposures) -> Vec<f32> {
    let mut error = vec![0.0f32; pair.width * pair.height];
    for i in 0..exposures.count {
        let scale = 2.0f32.powf(exposures.at(i));
        let (reference, test) = pair.map(|v| tone_map(v * scale, &ACES).clamp(0.0, 1.0));
        let at_exposure = Pair {
            reference: &reference,
            test: &test,
            ..pair
        }
        .ldr_flip_unclamped(ppd);
        for (e, x) in error.iter_mut().zip(at_exposure) {
            if x > *e {
                *e = x;
            }
        }
    }
    error
}

#[cfg(test)]
mod tests {
    use super::*;

    fn flat(width: usize, height: usize, c: [f32; 3]) -> Vec<[f32; 3]> {
        vec![c; width * height]
    }

    #[test]
    fn equal_pictures_have_no_error() {
        let pixels: Vec<[f32; 3]> = (0..12 * 9)
            .map(|i| [(i % 7) as f32 / 7.0, (i % 5) as f32 / 5.0, (i % 3) as f32 / 3.0])
            .collect();
        let pair = Pair {
            reference: &pixels,
            test: &pixels,
            width: 12,
            height: 9,
        };
        assert!(ldr_flip(pair, default_ppd()).iter().all(|&e| e == 0.0));
    }

    #[test]
    fn black_against_white_is_the_colour_difference_of_their_lightness() {
        // Flat pictures have no edges or points: FLIP is the colour difference alone.
        // Black and white differ by HyAB = 100 (L* 0 and 100, no chroma): 100^0.7 =
        // 25.12, above p_c c_max = 0.4 x 41.27 = 16.51, so the error is
        // p_t + (25.12 - 16.51) / (41.27 - 16.51) x (1 - p_t) = 0.9674.
        let (black, white) = (flat(4, 3, [0.0; 3]), flat(4, 3, [1.0; 3]));
        let e = ldr_flip(
            Pair {
                reference: &black,
                test: &white,
                width: 4,
                height: 3,
            },
            default_ppd(),
        );
        let cmax = 41.2706f32;
        let d = 100f32.powf(0.7);
        let want = 0.95 + (d - 0.4 * cmax) / (cmax - 0.4 * cmax) * 0.05;
        for v in e {
            assert!((v - want).abs() < 1e-3, "{v} vs {want}");
        }
    }

    #[test]
    fn exposures_span_the_brightest_pixel_to_the_median() {
        // Luminance 1 (white) everywhere but one pixel of 16: x_max is the luminance
        // ACES maps to 0.85; start = log2(x_max / 16), stop = log2(x_max / 1).
        let mut p = flat(3, 3, [1.0; 3]);
        p[4] = [16.0; 3];
        let e = Exposures::for_reference(&p).unwrap();
        assert!((e.stop - e.start - 4.0).abs() < 1e-4, "{e:?}");
        assert!((tone_map(2f32.powf(e.stop), &ACES) - 0.85).abs() < 1e-4);
        assert_eq!(e.count, 4);
        assert_eq!(Exposures::for_reference(&flat(2, 2, [0.0; 3])), None);
        // Mostly black: the median is taken as epsilon, not 0.
        let mut dark = flat(3, 3, [0.0; 3]);
        dark[0] = [1.0; 3];
        let e = Exposures::for_reference(&dark).unwrap();
        assert!(
            (e.stop - e.start - (1.0 / f32::EPSILON).log2()).abs() < 1e-3,
            "{e:?}"
        );
    }
}
