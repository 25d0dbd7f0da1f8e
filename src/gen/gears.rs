//! `gears`: a `size` x `size` x `size` lattice of meshed 36-tooth gears above a
//! reflective square, five lights.
//!
//! Each gear is a concave 144-vertex top face (four vertices per tooth), a 144-vertex
//! bottom face and 144 rectangles joining them. Gears in a layer mesh with their
//! neighbours: alternate gears are turned by half a tooth, and the tooth tips stop at
//! 0.995 of the pitch so that no two surfaces coincide. Layers step down by `1/size`.
//! Colours are pseudo-random fractions of the lattice indices; every gear whose
//! `(4 ix + 2 iy + iz)` is a multiple of 5 is glass.
//!
//! Polygons: `146 size^3 + 1` (9345 at the default size 4).

use std::f64::consts::PI;

use super::builder::{Builder, Camera, Surface};
use super::dvec::{D3, M3};
use crate::scene::Scene;

/// The SPD's default size.
pub const DEFAULT_SIZE: u32 = 4;

/// Teeth per gear (a multiple of 4).
const TEETH: usize = 36;
/// Tooth tips end this far out, as a fraction of the full radius.
const OUTER_EDGE_RATIO: f64 = 0.995;
/// Tooth roots start this far out.
const INNER_EDGE_RATIO: f64 = 0.9;
const EDGE_DIFF: f64 = 1.0 - INNER_EDGE_RATIO;
/// Largest thickness, as a fraction of the gear's width.
const DEPTH_RATIO: f64 = 0.1;

/// The outline of one face: per tooth, two tip points at +-0.19 of the tooth angle
/// and two root points at 0.3 and 0.7. The bottom face runs the other way round
/// (negative `sense`), so both faces are wound to face outwards.
fn face(center: D3, offset: f64, outer: f64, inner: f64, z: f64, sense: f64) -> Vec<D3> {
    let tooth = sense * 2.0 * PI / TEETH as f64;
    let at = |angle: f64, r: f64| center + M3::rotation_z(angle).apply(D3::new(r, 0.0, z));
    let mut pts = Vec::with_capacity(4 * TEETH);
    for n in 0..TEETH {
        let a = offset + n as f64 * tooth;
        pts.push(at(a - 0.19 * tooth, outer));
        pts.push(at(a + 0.19 * tooth, outer));
        pts.push(at(a + 0.3 * tooth, inner));
        pts.push(at(a + 0.7 * tooth, inner));
    }
    pts
}

fn gear(b: &mut Builder, center: D3, offset: f64, outer: f64, inner: f64, thickness: f64) {
    let top = face(center, offset, outer, inner, 0.0, 1.0);
    b.polygon(&top);
    let down = D3::new(0.0, 0.0, thickness);
    for (i, p) in top.iter().enumerate() {
        let q = top[(i + 1) % top.len()];
        b.polygon(&[*p, *p - down, q - down, q]);
    }
    b.polygon(&face(center, offset, outer, inner, -thickness, -1.0));
}

/// `0.01` plus the fractional part of `x`, as the SPD colours its gears.
fn hue(x: f64) -> f64 {
    0.01 + x.fract()
}

/// Generates `size^3` gears.
pub fn generate(size: u32) -> Scene {
    let camera = Camera {
        from: D3::new(-1.1, -2.1, 2.6),
        at: D3::ZERO,
        up: D3::Z,
        hither: 1.0,
    };
    let lights = [
        D3::new(2.0, 4.0, 4.0),
        D3::new(-2.0, 4.0, 3.0),
        D3::new(2.0, -2.5, 2.5),
        D3::new(-1.0, -4.0, 2.0),
        // just behind the eye
        D3::new(-1.111, -2.121, 2.626),
    ];
    let mut b = Builder::new(camera, &lights);
    let n = size as usize;
    b.reserve(0, 0, 4 + n * n * n * 24 * TEETH, 0);

    b.surface(Surface {
        color: [1.0, 0.85, 0.7],
        kd: 0.3,
        ks: 0.6,
        highlight_deg: 37.0,
        t: 0.0,
        ior: 0.0,
    });
    b.polygon(&[
        D3::new(2.0, 2.0, 0.0),
        D3::new(-2.0, 2.0, 0.0),
        D3::new(-2.0, -2.0, 0.0),
        D3::new(2.0, -2.0, 0.0),
    ]);

    let sf = size as f64;
    // The gears fill [-1, 1] in x and y: size gears across, overlapping by EDGE_DIFF/2.
    let radius = 1.0 / (sf - (sf - 1.0) * EDGE_DIFF / 2.0);
    let step = radius * (2.0 - EDGE_DIFF);
    let thickness = DEPTH_RATIO.min(1.0 / (2.0 * sf));
    for iz in 0..size {
        for iy in 0..size {
            for ix in 0..size {
                let center = D3::new(
                    -1.0 + radius + ix as f64 * step,
                    -1.0 + radius + iy as f64 * step,
                    1.0 - iz as f64 / sf,
                );
                let (fx, fy, fz) = (ix as f64, iy as f64, iz as f64);
                let c = [
                    hue((fx * 3.0 + fy * 2.0 + fz + 1.0) * 5.0 / 7.0),
                    hue((fy * 3.0 + fz * 2.0 + fx + 1.0) * 3.0 / 7.0),
                    hue((fz * 3.0 + fx * 2.0 + fy + 1.0) * 2.0 / 7.0),
                ];
                let m = c[0].max(c[1]).max(c[2]);
                let color = [c[0] / m, c[1] / m, c[2] / m];
                let glass = (ix * 4 + iy * 2 + iz) % 5 == 0;
                b.surface(if glass {
                    Surface {
                        color,
                        kd: 0.2,
                        ks: 0.0,
                        highlight_deg: 0.0,
                        t: 0.8,
                        ior: 1.1,
                    }
                } else {
                    Surface {
                        color,
                        kd: 1.0,
                        ks: 0.0,
                        highlight_deg: 0.0,
                        t: 0.0,
                        ior: 0.0,
                    }
                });
                // Neighbours are turned half a tooth against each other so they mesh.
                let offset = PI * ((ix + iy + iz) % 2) as f64 / TEETH as f64;
                gear(
                    &mut b,
                    center,
                    offset,
                    OUTER_EDGE_RATIO * radius,
                    INNER_EDGE_RATIO * radius,
                    thickness,
                );
            }
        }
    }
    b.finish()
}
