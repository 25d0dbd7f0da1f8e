//! FLIP's two filter banks, each applied as two one-dimensional passes (NVIDIA's
//! `separatedConvolutions.pdf`): the spatial filters that model the eye's contrast
//! sensitivity, per YCxCz channel (the blue-yellow channel's sum of two Gaussians
//! split into two separable halves), then the colour difference of the filtered
//! pictures; and the edge and point detectors (first and second derivatives of a
//! Gaussian) on the achromatic channel, then the feature difference that sharpens
//! the colour difference into FLIP's error.
//!
//! Pixels past the border repeat the edge pixel. Each output pixel sums its taps in
//! the order NVIDIA's code does, from the lowest offset up, so the maps agree with
//! the reference's whatever the thread count; rows run in parallel.

use std::f32::consts::PI;

use rayon::prelude::*;

use super::color::{
    hunt, hyab, linear_rgb_to_xyz, max_color_difference, xyz_to_lab, xyz_to_linear_rgb, ycxcz_to_xyz, GW, PC,
    PT, QC, QF,
};
use super::Planes;

/// The spatial filters' taps, from offset -radius to +radius: `ycx[k]` weighs Y and
/// Cx, `cz[k]` the two halves of Cz's filter.
pub struct SpatialFilters {
    ycx: Vec<[f32; 2]>,
    cz: Vec<[f32; 2]>,
}

/// The contrast sensitivity functions' Gaussians (FLIP paper, table 1): per channel
/// Y, Cx, Cz, the amplitudes a1, a2 and the widths b1, b2 of a1 sqrt(pi/b1)
/// exp(-pi² x²/b1) + a2 sqrt(pi/b2) exp(-pi² x²/b2), x in degrees.
const A1: [f32; 3] = [1.0, 1.0, 34.1];
const B1: [f32; 3] = [0.0047, 0.0053, 0.04];
const A2: [f32; 3] = [0.0, 0.0, 13.5];
const B2: [f32; 3] = [1.0e-5, 1.0e-5, 0.025];

impl SpatialFilters {
    /// The filters at `ppd` pixels per degree, each normalized to sum to one (Cz's
    /// two halves together, in the sense of the separated convolution).
    pub fn new(ppd: f32) -> SpatialFilters {
        let pi_sq = PI * PI;
        let widest = B1.into_iter().chain(B2).fold(f32::MIN, f32::max);
        // Three standard deviations of the widest Gaussian, in pixels.
        let radius = (3.0 * (widest / (2.0 * pi_sq)).sqrt() * ppd).ceil() as i32;
        // a sqrt(pi/b) exp(-pi² x²/b), and its square root's amplitude for Cz's halves.
        let gaussian = |x2: f32, a: f32, b: f32| a * (PI / b).sqrt() * (-pi_sq * x2 / b).exp();
        let half = |x2: f32, a: f32, b: f32| (a * (PI / b).sqrt()).sqrt() * (-pi_sq * x2 / b).exp();
        let (mut ycx, mut cz) = (Vec::new(), Vec::new());
        let (mut sum_ycx, mut sum_cz) = ([0.0f32; 2], [0.0f32; 2]);
        for x in -radius..=radius {
            let degrees = x as f32 * (1.0 / ppd);
            let x2 = degrees * degrees;
            let w_ycx = [gaussian(x2, A1[0], B1[0]), gaussian(x2, A1[1], B1[1])];
            let w_cz = [half(x2, A1[2], B1[2]), half(x2, A2[2], B2[2])];
            for c in 0..2 {
                sum_ycx[c] += w_ycx[c];
                sum_cz[c] += w_cz[c];
            }
            ycx.push(w_ycx);
            cz.push(w_cz);
        }
        let norm_ycx = [1.0 / sum_ycx[0], 1.0 / sum_ycx[1]];
        let norm_cz = 1.0 / (sum_cz[0] * sum_cz[0] + sum_cz[1] * sum_cz[1]).sqrt();
        for w in &mut ycx {
            *w = [w[0] * norm_ycx[0], w[1] * norm_ycx[1]];
        }
        for w in &mut cz {
            *w = [w[0] * norm_cz, w[1] * norm_cz];
        }
        SpatialFilters { ycx, cz }
    }

    fn radius(&self) -> usize {
        self.ycx.len() / 2
    }
}

/// The feature detectors' taps, from offset -radius to +radius: the Gaussian, its
/// first and its second derivative, the Gaussian summing to one and each
/// derivative's positive and negative taps to +1 and -1.
pub fn feature_filter(ppd: f32) -> Vec<[f32; 3]> {
    let sigma = 0.5 * GW * ppd;
    let radius = (3.0 * sigma).ceil() as i32;
    let mut taps = Vec::new();
    let (mut sum_g, mut d_pos, mut d_neg, mut dd_pos, mut dd_neg) = (0.0f32, 0.0f32, 0.0f32, 0.0f32, 0.0f32);
    for x in -radius..=radius {
        let x = x as f32;
        let g = (-(x * x) / (2.0 * sigma * sigma)).exp();
        let dg = -x * g;
        let ddg = (x * x / (sigma * sigma) - 1.0) * g;
        sum_g += g;
        if dg > 0.0 {
            d_pos += dg;
        } else {
            d_neg -= dg;
        }
        if ddg > 0.0 {
            dd_pos += ddg;
        } else {
            dd_neg -= ddg;
        }
        taps.push([g, dg, ddg]);
    }
    for t in &mut taps {
        let d = if t[1] > 0.0 { d_pos } else { d_neg };
        let dd = if t[2] > 0.0 { dd_pos } else { dd_neg };
        *t = [t[0] / sum_g, t[1] / d, t[2] / dd];
    }
    taps
}

/// Row `y` of `plane` (`width` wide) with `radius` copies of its end pixels on
/// either side, so that tap `k` of output pixel `x` reads entry `x + k`.
fn padded_row(plane: &[f32], width: usize, y: usize, radius: usize) -> Vec<f32> {
    let row = &plane[y * width..(y + 1) * width];
    let clamp = |i: usize| row[i.saturating_sub(radius).min(width - 1)];
    (0..width + 2 * radius).map(clamp).collect()
}

/// The row a tap `k` of a vertical filter of `radius` reads for output row `y`.
fn tap_row(y: usize, k: usize, radius: usize, height: usize) -> usize {
    (y + k).saturating_sub(radius).min(height - 1)
}

/// The vertical pass of a filter of `taps` taps over both pictures' rows (each
/// `size.0` x `size.1`) for output row `y`: `add(k, acc, src)` adds tap `k`'s term
/// of the source pixel `src` to the pixel's sums `acc`, taps in order.
fn column_sums<S>(
    rows: [&[S]; 2],
    (w, h): (usize, usize),
    y: usize,
    taps: usize,
    add: impl Fn(usize, &mut [f32; 4], &S),
) -> [Vec<[f32; 4]>; 2] {
    rows.map(|rows| {
        let mut acc = vec![[0.0f32; 4]; w];
        for k in 0..taps {
            let yy = tap_row(y, k, taps / 2, h);
            for (a, src) in acc.iter_mut().zip(&rows[yy * w..(yy + 1) * w]) {
                add(k, a, src);
            }
        }
        acc
    })
}

/// The spatial filters' horizontal pass over a YCxCz picture: per pixel, Y and Cx
/// filtered and Cz through each half of its filter.
fn spatial_rows(p: &Planes, f: &SpatialFilters) -> Vec<[f32; 4]> {
    let (w, r) = (p.width, f.radius());
    let mut out = vec![[0.0f32; 4]; w * p.height];
    out.par_chunks_mut(w).enumerate().for_each(|(y, row)| {
        let [py, pcx, pcz] = [&p.y, &p.cx, &p.cz].map(|plane| padded_row(plane, w, y, r));
        for (k, (wy, wz)) in f.ycx.iter().zip(&f.cz).enumerate() {
            for (x, acc) in row.iter_mut().enumerate() {
                acc[0] += wy[0] * py[x + k];
                acc[1] += wy[1] * pcx[x + k];
                acc[2] += wz[0] * pcz[x + k];
                acc[3] += wz[1] * pcz[x + k];
            }
        }
    });
    out
}

/// FLIP's colour difference of each pixel, in [0, 1]: both pictures through the
/// spatial filters, clamped to the RGB cube, to CIELAB with the Hunt adjustment,
/// their HyAB distance raised to q_c and compressed above p_c times its maximum.
pub fn color_difference(reference: &Planes, test: &Planes, f: &SpatialFilters) -> Vec<f32> {
    let (w, h) = (reference.width, reference.height);
    let (rows_ref, rows_test) = rayon::join(|| spatial_rows(reference, f), || spatial_rows(test, f));
    let cmax = max_color_difference();
    let pccmax = PC * cmax;
    let mut out = vec![0.0f32; w * h];
    out.par_chunks_mut(w).enumerate().for_each(|(y, row)| {
        let [acc_ref, acc_test] =
            column_sums([&rows_ref, &rows_test], (w, h), y, f.ycx.len(), |k, acc, src| {
                let weights = [f.ycx[k][0], f.ycx[k][1], f.cz[k][0], f.cz[k][1]];
                for c in 0..4 {
                    acc[c] += weights[c] * src[c];
                }
            });
        for ((out, a), b) in row.iter_mut().zip(&acc_ref).zip(&acc_test) {
            let lab = |f: &[f32; 4]| {
                let rgb =
                    xyz_to_linear_rgb(ycxcz_to_xyz([f[0], f[1], f[2] + f[3]])).map(|c| c.clamp(0.0, 1.0));
                hunt(xyz_to_lab(linear_rgb_to_xyz(rgb)))
            };
            let d = hyab(lab(a), lab(b)).powf(QC);
            // [0, p_c c_max) maps linearly to [0, p_t); the rest to [p_t, 1].
            *out = if d < pccmax {
                d * (PT / pccmax)
            } else {
                PT + ((d - pccmax) / (cmax - pccmax)) * (1.0 - PT)
            };
        }
    });
    out
}

/// The feature detectors' horizontal pass over the achromatic channel scaled to
/// [0, 1]: per pixel its first and second x-derivatives and its Gaussian blur.
fn feature_rows(p: &Planes, filter: &[[f32; 3]]) -> Vec<[f32; 3]> {
    let (w, r) = (p.width, filter.len() / 2);
    let gray: Vec<f32> = p.y.iter().map(|&y| y * (1.0 / 116.0) + 16.0 / 116.0).collect();
    let mut out = vec![[0.0f32; 3]; w * p.height];
    out.par_chunks_mut(w).enumerate().for_each(|(y, row)| {
        let src = padded_row(&gray, w, y, r);
        for (k, t) in filter.iter().enumerate() {
            for (x, acc) in row.iter_mut().enumerate() {
                acc[0] += t[1] * src[x + k];
                acc[1] += t[2] * src[x + k];
                acc[2] += t[0] * src[x + k];
            }
        }
    });
    out
}

/// Turns the colour difference `error` into FLIP's error, in place: each pixel's
/// colour difference raised to 1 - (the larger of its edge and point differences,
/// over √2, to the power q_f).
pub fn apply_feature_difference(reference: &Planes, test: &Planes, filter: &[[f32; 3]], error: &mut [f32]) {
    let (w, h) = (reference.width, reference.height);
    let (rows_ref, rows_test) =
        rayon::join(|| feature_rows(reference, filter), || feature_rows(test, filter));
    let norm = 1.0 / 2.0f32.sqrt();
    error.par_chunks_mut(w).enumerate().for_each(|(y, row)| {
        // Per pixel: d/dx, d²/dx², d/dy, d²/dy².
        let [acc_ref, acc_test] =
            column_sums([&rows_ref, &rows_test], (w, h), y, filter.len(), |k, acc, s| {
                let t = filter[k];
                acc[0] += t[0] * s[0];
                acc[1] += t[0] * s[1];
                acc[2] += t[1] * s[2];
                acc[3] += t[2] * s[2];
            });
        for ((e, a), b) in row.iter_mut().zip(&acc_ref).zip(&acc_test) {
            let edge = |d: &[f32; 4]| (d[0] * d[0] + d[2] * d[2]).sqrt();
            let point = |d: &[f32; 4]| (d[1] * d[1] + d[3] * d[3]).sqrt();
            let edge_diff = (edge(a) - edge(b)).abs();
            let point_diff = (point(a) - point(b)).abs();
            let feature = (norm * edge_diff.max(point_diff)).powf(QF);
            *e = e.powf(1.0 - feature);
        }
    });
}
