//! The metrics `nffrt diff` measures a picture's error by, and the simple ones
//! computed: per pixel over its three channels, then over the picture.
//!
//! With `v` a test value and `r` the reference's (8-bit pictures in [0, 1] as
//! stored, float pictures as they are): MSE is the mean of (v - r)², RMSE its
//! square root, relMSE pbrt's relative MSE, the mean of (v - r)² / (r + 0.01)², MAE
//! the mean of |v - r|, and PSNR 10 log10(1 / MSE) decibels (a peak of 1: 255 in
//! 8-bit levels). FLIP is in [`super::flip`].

/// An error metric.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Metric {
    /// NVIDIA's FLIP: LDR-FLIP for 8-bit pictures, HDR-FLIP for float ones, in [0, 1].
    Flip,
    /// Mean squared error.
    Mse,
    /// Root mean squared error.
    Rmse,
    /// Relative mean squared error, pbrt's MRSE.
    Relmse,
    /// Mean absolute error.
    Mae,
    /// Peak signal-to-noise ratio in decibels, for a peak of 1: higher is closer.
    Psnr,
}

impl Metric {
    /// Every metric, in the order the help lists them.
    pub const ALL: [Metric; 6] = [
        Metric::Flip,
        Metric::Mse,
        Metric::Rmse,
        Metric::Relmse,
        Metric::Mae,
        Metric::Psnr,
    ];

    /// Its name on the command line, in Python and in JSON.
    pub fn name(self) -> &'static str {
        match self {
            Metric::Flip => "flip",
            Metric::Mse => "mse",
            Metric::Rmse => "rmse",
            Metric::Relmse => "relmse",
            Metric::Mae => "mae",
            Metric::Psnr => "psnr",
        }
    }

    /// The metric named `name`.
    pub fn from_name(name: &str) -> Option<Metric> {
        Metric::ALL.into_iter().find(|m| m.name() == name)
    }

    /// True for PSNR, the one metric that grows as pictures get closer.
    pub fn higher_is_closer(self) -> bool {
        self == Metric::Psnr
    }

    /// True when `value` is farther from the reference than `tolerance` allows:
    /// above it, or for PSNR below it.
    pub fn exceeds(self, value: f64, tolerance: f64) -> bool {
        if self.higher_is_closer() {
            value < tolerance
        } else {
            value > tolerance
        }
    }

    /// Orders two values from the closest to the farthest.
    pub fn closest_first(self, a: f64, b: f64) -> std::cmp::Ordering {
        if self.higher_is_closer() {
            b.total_cmp(&a)
        } else {
            a.total_cmp(&b)
        }
    }
}

/// The error of one pixel under `metric` (not FLIP), its channels averaged: for
/// MSE, RMSE and PSNR the squared error, for relMSE the relative squared error, for
/// MAE the absolute error.
pub fn pixel_error(metric: Metric, v: [f32; 3], r: [f32; 3]) -> f32 {
    let per_channel = |f: fn(f32, f32) -> f32| (f(v[0], r[0]) + f(v[1], r[1]) + f(v[2], r[2])) / 3.0;
    match metric {
        // (FLIP has its own map; asked here, it gets the squared error.)
        Metric::Mse | Metric::Rmse | Metric::Psnr | Metric::Flip => per_channel(|v, r| (v - r) * (v - r)),
        // pbrt-v4's MRSE: (v - r)² / (r + 0.01)².
        Metric::Relmse => per_channel(|v, r| (v - r) * (v - r) / ((r + 0.01) * (r + 0.01))),
        Metric::Mae => per_channel(|v, r| (v - r).abs()),
    }
}

/// The picture's value of `metric` from the [`pixel_error`] of each of its pixels.
pub fn summarize(metric: Metric, pixel_errors: &[f32]) -> f64 {
    let mean = pixel_errors.iter().map(|&e| e as f64).sum::<f64>() / pixel_errors.len() as f64;
    match metric {
        Metric::Rmse => mean.sqrt(),
        // 10 log10(peak² / MSE), peak 1; infinite for equal pictures.
        Metric::Psnr => -10.0 * mean.log10(),
        _ => mean,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Two pixels: test (0.5, 0.5, 0.5) and (1, 0, 0.2) against (0.25, 0.5, 1) and
    /// (1, 0.1, 0.2).
    fn errors(metric: Metric) -> (Vec<f32>, f64) {
        let test = [[0.5, 0.5, 0.5], [1.0, 0.0, 0.2]];
        let reference = [[0.25, 0.5, 1.0], [1.0, 0.1, 0.2]];
        let map: Vec<f32> = test
            .iter()
            .zip(&reference)
            .map(|(&v, &r)| pixel_error(metric, v, r))
            .collect();
        let value = summarize(metric, &map);
        (map, value)
    }

    fn close(a: f64, b: f64) -> bool {
        (a - b).abs() <= 1e-6 * b.abs().max(1e-6)
    }

    #[test]
    fn metrics_match_hand_computed_values() {
        // Differences 0.25, 0, -0.5 and 0, -0.1, 0.
        // MSE: pixel 1 (0.0625 + 0 + 0.25) / 3 = 0.104167, pixel 2 0.01 / 3 =
        // 0.003333; mean 0.05375.
        let (map, mse) = errors(Metric::Mse);
        assert!(
            close(map[0] as f64, 0.3125 / 3.0) && close(map[1] as f64, 0.01 / 3.0),
            "{map:?}"
        );
        assert!(close(mse, 0.05375), "{mse}");
        assert!(close(errors(Metric::Rmse).1, 0.05375f64.sqrt()));
        // PSNR: -10 log10(0.05375) = 12.69622 dB.
        assert!(
            close(errors(Metric::Psnr).1, 12.696_22),
            "{}",
            errors(Metric::Psnr).1
        );
        // MAE: (0.25 + 0.5 + 0.1) / 6 = 0.141667.
        assert!(close(errors(Metric::Mae).1, 0.85 / 6.0));
        // relMSE: 0.0625 / 0.26² + 0.25 / 1.01² + 0.01 / 0.11², over 6:
        // 0.924556 + 0.245074 + 0.826446 = 1.996077, / 6 = 0.3326794.
        let rel = 0.0625 / (0.26f64 * 0.26) + 0.25 / (1.01 * 1.01) + 0.01 / (0.11 * 0.11);
        assert!(
            close(errors(Metric::Relmse).1, rel / 6.0),
            "{}",
            errors(Metric::Relmse).1
        );
        assert!(close(rel / 6.0, 0.332_679_4), "{rel}");
    }

    #[test]
    fn equal_pictures_score_zero_or_infinite_psnr() {
        let map = [pixel_error(Metric::Mse, [0.3; 3], [0.3; 3]); 4];
        assert_eq!(summarize(Metric::Mse, &map), 0.0);
        assert_eq!(summarize(Metric::Psnr, &map), f64::INFINITY);
    }

    #[test]
    fn psnr_orders_and_exceeds_the_other_way() {
        use std::cmp::Ordering::Less;
        assert_eq!(Metric::Mse.closest_first(0.1, 0.2), Less);
        assert_eq!(Metric::Psnr.closest_first(40.0, 30.0), Less);
        assert!(Metric::Flip.exceeds(0.2, 0.1) && !Metric::Flip.exceeds(0.1, 0.1));
        assert!(Metric::Psnr.exceeds(25.0, 30.0) && !Metric::Psnr.exceeds(35.0, 30.0));
        for m in Metric::ALL {
            assert_eq!(Metric::from_name(m.name()), Some(m));
        }
        assert_eq!(Metric::from_name("ssim"), None);
    }
}
