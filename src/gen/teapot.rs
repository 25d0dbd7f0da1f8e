//! `teapot`: Newell's teapot, its 32 bicubic Bezier patches each cut into a
//! `size` x `size` grid of quadrilaterals and each quadrilateral into two
//! smooth-shaded triangles (`pp`), standing on a `size` x `size` checkerboard from
//! -4 to 4; two lights. Everything is reflective.
//!
//! A patch point is `P(s, t) = sum over i, j of B_i(s) B_j(t) G_ij` with the cubic
//! Bernstein polynomials `B` and control points `G`; its normal is the normalized
//! cross product of the `t` and `s` derivatives. The lid's top and the bottom's
//! centre are cusps where a whole row of control points coincides on the z axis: a
//! triangle with two corners there is degenerate and left out, and a triangle with
//! one corner there gets the normal straight up (lid) or down (bottom) at it.
//!
//! Triangles: `64 size^2 - 8 size` (2256 at the default size 6), plus `size^2` squares.
//! At size 1, which the SPD accepts with a warning, four of the triangles have no
//! area; like the SPD we write them, and readers (ours included) skip them.

use super::builder::{Builder, Camera, Surface};
use super::dvec::D3;
use super::teapot_data::{PATCHES, VERTICES};
use crate::scene::Scene;

/// The SPD's default size.
pub const DEFAULT_SIZE: u32 = 6;

/// Half-width of the checkerboard.
const BOARD: f64 = 4.0;

/// A point on the axis closer than this (in x and y) is a cusp.
const CUSP: f64 = 0.0001;

/// The cubic Bernstein polynomials at `u` and their derivatives.
fn bernstein(u: f64) -> ([f64; 4], [f64; 4]) {
    let v = 1.0 - u;
    let b = [v * v * v, 3.0 * u * v * v, 3.0 * u * u * v, u * u * u];
    let d = [
        -3.0 * v * v,
        3.0 * v * v - 6.0 * u * v,
        6.0 * u * v - 3.0 * u * u,
        3.0 * u * u,
    ];
    (b, d)
}

/// Position and unit normal (zero where undefined) of patch `g` at `(s, t)`.
fn evaluate(g: &[D3; 16], s: f64, t: f64) -> (D3, D3) {
    let (bs, ds) = bernstein(s);
    let (bt, dt) = bernstein(t);
    let (mut p, mut ps, mut pt) = (D3::ZERO, D3::ZERO, D3::ZERO);
    for i in 0..4 {
        for j in 0..4 {
            let c = g[4 * i + j];
            p = p + c * (bs[i] * bt[j]);
            ps = ps + c * (ds[i] * bt[j]);
            pt = pt + c * (bs[i] * dt[j]);
        }
    }
    (p, pt.cross(ps).normalized())
}

/// Emits a triangle unless two corners sit on the cusp; fixes the normal of one that does.
fn triangle(b: &mut Builder, mut corners: [(D3, D3); 3]) {
    let on_axis = |p: D3| p.x.abs() < CUSP && p.y.abs() < CUSP;
    let cusps = corners.iter().filter(|(p, _)| on_axis(*p)).count();
    if cusps > 1 {
        return;
    }
    for (p, n) in corners.iter_mut() {
        if on_axis(*p) {
            // Above the middle of the pot is the lid's knob, below it the bottom.
            *n = if p.z > 1.5 { D3::Z } else { -D3::Z };
        }
    }
    b.patch(&corners.map(|c| c.0), &corners.map(|c| c.1));
}

/// Tessellates every patch into `n` x `n` cells of two triangles.
fn teapot(b: &mut Builder, n: u32) {
    let k = n as usize + 1;
    let mut grid = vec![(D3::ZERO, D3::ZERO); k * k];
    for patch in &PATCHES {
        let g = patch.map(|i| {
            let [x, y, z] = VERTICES[i as usize];
            D3::new(x, y, z)
        });
        for (i, cell) in grid.iter_mut().enumerate() {
            *cell = evaluate(&g, (i / k) as f64 / n as f64, (i % k) as f64 / n as f64);
        }
        let at = |s: usize, t: usize| grid[s * k + t];
        for s in 0..k - 1 {
            for t in 0..k - 1 {
                let quad = [at(s, t), at(s, t + 1), at(s + 1, t + 1), at(s + 1, t)];
                triangle(b, [quad[0], quad[1], quad[2]]);
                triangle(b, [quad[2], quad[3], quad[0]]);
            }
        }
    }
}

/// The checkerboard: first the white squares, then the grey ones.
fn checkerboard(b: &mut Builder, n: u32) {
    let coord = |i: u32| BOARD * (2.0 * i as f64 / n as f64 - 1.0);
    for (shade, odd) in [(1.0, 1), (0.5, 0)] {
        b.surface(Surface {
            color: [shade; 3],
            kd: 0.5,
            ks: 0.5,
            highlight_deg: 30.0,
            t: 0.0,
            ior: 0.0,
        });
        for s in 0..n {
            for t in 0..n {
                if (s + t) % 2 == odd {
                    let (x0, x1, y0, y1) = (coord(s), coord(s + 1), coord(t), coord(t + 1));
                    b.polygon(&[
                        D3::new(x0, y0, 0.0),
                        D3::new(x1, y0, 0.0),
                        D3::new(x1, y1, 0.0),
                        D3::new(x0, y1, 0.0),
                    ]);
                }
            }
        }
    }
}

/// Generates the teapot with each patch cut `size` x `size` times.
pub fn generate(size: u32) -> Scene {
    let camera = Camera {
        from: D3::new(4.86, 7.2, 5.4),
        at: D3::ZERO,
        up: D3::Z,
        hither: 1.0,
    };
    let mut b = Builder::new(camera, &[D3::new(-3.1, 9.8, 12.1), D3::new(11.3, 5.1, 8.8)]);
    let n = size as usize;
    b.reserve(0, 0, 4 * n * n, 3 * 64 * n * n);
    checkerboard(&mut b, size);
    b.surface(Surface {
        color: [1.0, 0.5, 0.1],
        kd: 0.75,
        ks: 0.25,
        highlight_deg: 37.0,
        t: 0.0,
        ior: 0.0,
    });
    teapot(&mut b, size);
    b.finish()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn bernstein_sums_to_one_and_derivatives_to_zero() {
        for u in [0.0, 0.25, 0.6, 1.0] {
            let (b, d) = bernstein(u);
            assert!((b.iter().sum::<f64>() - 1.0).abs() < 1e-15);
            assert!(d.iter().sum::<f64>().abs() < 1e-14);
        }
    }

    #[test]
    fn patches_interpolate_their_corner_control_points() {
        for patch in &PATCHES {
            let g = patch.map(|i| {
                let [x, y, z] = VERTICES[i as usize];
                D3::new(x, y, z)
            });
            for (s, t, k) in [(0.0, 0.0, 0), (0.0, 1.0, 3), (1.0, 0.0, 12), (1.0, 1.0, 15)] {
                assert!((evaluate(&g, s, t).0 - g[k]).length() < 1e-12);
            }
        }
    }
}
