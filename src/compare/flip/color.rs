//! FLIP's colour science: the constants of the metric, linear sRGB to CIE XYZ to
//! FLIP's opponent space YCxCz and back, CIELAB with the Hunt adjustment, the HyAB
//! distance, and the tone mappers HDR-FLIP exposes its pictures through.
//!
//! Every number is NVIDIA's (Andersson et al., "FLIP: A Difference Evaluator for
//! Alternating Images", HPG 2020; "Visualizing Errors in Rendered High Dynamic Range
//! Images", Eurographics 2021; the reference implementation `FLIP.h`, version 1.7),
//! computed in `f32` in the reference's order of operations, so that the error maps
//! agree with NVIDIA's to a few ulps.

// The reference writes its constants with nine digits, more than an f32 holds, so
// that every implementation rounds them to the same f32; they are kept as written.
#![allow(clippy::excessive_precision)]

use std::f32::consts::PI;

/// FLIP's colour-pipeline exponent q_c (the colour difference is HyAB^q_c).
pub const QC: f32 = 0.7;
/// The fraction p_c of the largest colour difference mapped to [0, p_t].
pub const PC: f32 = 0.4;
/// The error p_t at p_c times the largest colour difference.
pub const PT: f32 = 0.95;
/// The edge detector's width w, in degrees of visual angle.
pub const GW: f32 = 0.082;
/// The feature-pipeline exponent q_f.
pub const QF: f32 = 0.5;

/// D65, the white of sRGB, in XYZ (the reference illuminant of CIELAB and YCxCz).
const ILLUMINANT: [f32; 3] = [0.950_428_545, 1.0, 1.088_900_371];
/// 1 / [`ILLUMINANT`], as the reference writes it.
const INV_ILLUMINANT: [f32; 3] = [1.052_156_925, 1.0, 0.918_357_670];

/// Pixels per degree of visual angle for a viewer `distance` metres from a monitor
/// `monitor_width` metres and `resolution_x` pixels wide.
pub fn pixels_per_degree(distance: f32, resolution_x: f32, monitor_width: f32) -> f32 {
    distance * (resolution_x / monitor_width) * (PI / 180.0)
}

/// FLIP's default viewing conditions: 0.7 m from a 0.7 m wide 4K monitor (67.02).
pub fn default_ppd() -> f32 {
    pixels_per_degree(0.7, 3840.0, 0.7)
}

/// An 8-bit picture's value `v` in [0, 1], encoded with the sRGB curve, as linear.
pub fn srgb_to_linear(v: f32) -> f32 {
    if v <= 0.04045 {
        v / 12.92
    } else {
        ((v + 0.055) / 1.055).powf(2.4)
    }
}

/// Linear sRGB (D65) to CIE XYZ; the matrix is sRGB's primaries, in exact fractions.
pub fn linear_rgb_to_xyz([r, g, b]: [f32; 3]) -> [f32; 3] {
    let m = [
        [
            10135552.0 / 24577794.0,
            8788810.0 / 24577794.0,
            4435075.0 / 24577794.0,
        ],
        [
            2613072.0 / 12288897.0,
            8788810.0 / 12288897.0,
            887015.0 / 12288897.0,
        ],
        [
            1425312.0 / 73733382.0,
            8788810.0 / 73733382.0,
            70074185.0 / 73733382.0,
        ],
    ];
    m.map(|row: [f32; 3]| row[0] * r + row[1] * g + row[2] * b)
}

/// CIE XYZ to linear sRGB (D65).
pub fn xyz_to_linear_rgb([x, y, z]: [f32; 3]) -> [f32; 3] {
    let m: [[f32; 3]; 3] = [
        [3.241_003_275, -1.537_398_934, -0.498_615_861],
        [-0.969_224_334, 1.875_930_071, 0.041_554_224],
        [0.055_639_423, -0.204_011_202, 1.057_148_933],
    ];
    m.map(|row| row[0] * x + row[1] * y + row[2] * z)
}

/// CIE XYZ to YCxCz, the linear opponent space FLIP filters in: Y is achromatic,
/// Cx red-green, Cz blue-yellow (the linearized CIELAB of Zhang and Wandell).
pub fn xyz_to_ycxcz(xyz: [f32; 3]) -> [f32; 3] {
    let [x, y, z] = mul(xyz, INV_ILLUMINANT);
    [116.0 * y - 16.0, 500.0 * (x - y), 200.0 * (y - z)]
}

/// YCxCz back to CIE XYZ.
pub fn ycxcz_to_xyz([l, cx, cz]: [f32; 3]) -> [f32; 3] {
    let y = (l + 16.0) / 116.0;
    let cx = cx / 500.0;
    let cz = cz / 200.0;
    mul([y + cx, y, y - cz], ILLUMINANT)
}

/// CIE XYZ to CIELAB (D65).
pub fn xyz_to_lab(xyz: [f32; 3]) -> [f32; 3] {
    const DELTA: f32 = 6.0 / 29.0;
    let delta_cube = DELTA * (DELTA * DELTA);
    let factor = 1.0 / (3.0 * (DELTA * DELTA));
    let term = 4.0 / 29.0;
    // f(t) = t^(1/3) above delta^3, the linear segment below it.
    let [x, y, z] = mul(xyz, INV_ILLUMINANT).map(|t| {
        if t > delta_cube {
            t.powf(1.0 / 3.0)
        } else {
            factor * t + term
        }
    });
    [116.0 * y - 16.0, 500.0 * (x - y), 200.0 * (y - z)]
}

/// The Hunt effect: chroma scaled by lightness, a* and b* times 0.01 L*.
pub fn hunt([l, a, b]: [f32; 3]) -> [f32; 3] {
    [l, 0.01 * l * a, 0.01 * l * b]
}

/// HyAB distance: |ΔL| plus the Euclidean distance in (a, b).
pub fn hyab(p: [f32; 3], q: [f32; 3]) -> f32 {
    let (da, db) = (p[1] - q[1], p[2] - q[2]);
    (p[0] - q[0]).abs() + (da * da + db * db).sqrt()
}

/// The largest colour difference, green against blue, raised to q_c: FLIP's c_max.
pub fn max_color_difference() -> f32 {
    let hunt_lab = |rgb| hunt(xyz_to_lab(linear_rgb_to_xyz(rgb)));
    hyab(hunt_lab([0.0, 1.0, 0.0]), hunt_lab([0.0, 0.0, 1.0])).powf(QC)
}

/// Rec. 709 luminance of a linear colour.
pub fn luminance([r, g, b]: [f32; 3]) -> f32 {
    0.2126 * r + 0.7152 * g + 0.0722 * b
}

/// The ACES filmic curve as HDR-FLIP fits it, (a x² + b x + c) / (d x² + e x + f)
/// per channel, its 0.6 pre-exposure folded into the coefficients.
pub const ACES: [f32; 6] = [
    0.6 * 0.6 * 2.51,
    0.6 * 0.03,
    0.0,
    0.6 * 0.6 * 2.43,
    0.6 * 0.59,
    0.14,
];

/// `c` through the rational tone curve `k` (see [`ACES`]).
pub fn tone_map(c: f32, k: &[f32; 6]) -> f32 {
    let c2 = c * c;
    (c2 * k[0] + c * k[1] + k[2]) / (c2 * k[3] + c * k[4] + k[5])
}

fn mul(a: [f32; 3], b: [f32; 3]) -> [f32; 3] {
    [a[0] * b[0], a[1] * b[1], a[2] * b[2]]
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn white_is_the_illuminant_and_round_trips() {
        // Linear white is D65: Y = 1, L* = 100, no chroma.
        let xyz = linear_rgb_to_xyz([1.0, 1.0, 1.0]);
        assert!((xyz[1] - 1.0).abs() < 1e-6, "{xyz:?}");
        let lab = xyz_to_lab(xyz);
        assert!(
            (lab[0] - 100.0).abs() < 1e-4 && lab[1].abs() < 1e-3 && lab[2].abs() < 1e-3,
            "{lab:?}"
        );
        let ycxcz = xyz_to_ycxcz(xyz);
        assert!((ycxcz[0] - 100.0).abs() < 1e-4, "{ycxcz:?}");
        let back = xyz_to_linear_rgb(ycxcz_to_xyz(ycxcz));
        for c in back {
            assert!((c - 1.0).abs() < 1e-5, "{back:?}");
        }
    }

    #[test]
    fn constants_match_the_papers() {
        // 0.7 m from a 0.7 m wide 3840-pixel monitor: 3840 pi / 180 = 67.02 ppd.
        assert!((default_ppd() - 67.020_645).abs() < 1e-4);
        // sRGB's 50 % grey (188/255 encoded) is about 0.5 linear; 0.04045 is the knee.
        assert!((srgb_to_linear(188.0 / 255.0) - 0.5029).abs() < 1e-4);
        assert!((srgb_to_linear(0.04045) - 0.04045 / 12.92).abs() < 1e-9);
        // c_max: green against blue in CIELAB (L*, a*, b* = 87.737, -86.185, 83.181
        // and 32.303, 79.197, -107.864), a* and b* scaled by 0.01 L* (Hunt), HyAB
        // distance 203.3, raised to 0.7: 41.27.
        let hunt_ab = |[l, a, b]: [f64; 3]| [l, 0.01 * l * a, 0.01 * l * b];
        let (g, b) = (
            hunt_ab([87.737, -86.185, 83.181]),
            hunt_ab([32.303, 79.197, -107.864]),
        );
        let hyab = (g[0] - b[0]).abs() + ((g[1] - b[1]).powi(2) + (g[2] - b[2]).powi(2)).sqrt();
        assert!(
            (max_color_difference() as f64 - hyab.powf(0.7)).abs() < 2e-3,
            "{hyab}"
        );
        // ACES: black stays black, the curve rises and stays below 1.
        assert_eq!(tone_map(0.0, &ACES), 0.0);
        assert!(tone_map(1.0, &ACES) < tone_map(2.0, &ACES) && tone_map(1e6, &ACES) < 1.04);
    }
}
