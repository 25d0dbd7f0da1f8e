//! `rings`: a pyramid of objects, each six pentagonal rings of cylinders and spheres
//! that join the edge midpoints of a dodecahedron, seen from the pyramid's apex
//! against a white wall; three lights.
//!
//! One ring is the regular pentagon in the xy plane with a vertex on +x; the other
//! five are that pentagon tipped about x by the dodecahedron's dihedral angle
//! `2 acos(cos 60 / sin 36)` and turned about z by 36 + 72k degrees. The object is
//! scaled to fit a unit sphere including the tube radius 0.07412. Layer `d` (from 1)
//! of the pyramid is a `d` x `d` square of objects, two units apart, at
//! `y = d / sin(22.5 degrees)`. Each ring vertex becomes a cylinder to the previous
//! vertex and a sphere, in the six colours red, green, blue, cyan, magenta, yellow.
//!
//! Spheres and cylinders: `5 size (size + 1)(2 size + 1)` each (4200 at the default
//! size 7), plus the wall.

use std::f64::consts::PI;

use super::builder::{Builder, Camera, Surface};
use super::dvec::{D3, M3};
use crate::scene::Scene;

/// The SPD's default size.
pub const DEFAULT_SIZE: u32 = 7;

/// Radius of the cylinders and spheres.
const TUBE: f64 = 0.07412;

const COLORS: [[f64; 3]; 6] = [
    [1.0, 0.0, 0.0],
    [0.0, 1.0, 0.0],
    [0.0, 0.0, 1.0],
    [0.0, 1.0, 1.0],
    [1.0, 0.0, 1.0],
    [1.0, 1.0, 0.0],
];

/// The 30 ring vertices of one object, five per ring, centred on the origin.
fn ring_vertices() -> [D3; 30] {
    let scale = 1.0 / (1.0 + TUBE);
    let mut v = [D3::ZERO; 30];
    for (k, p) in v.iter_mut().take(5).enumerate() {
        let a = k as f64 * 2.0 * PI / 5.0;
        *p = D3::new(scale * a.cos(), scale * a.sin(), 0.0);
    }
    let tip = M3::rotation_x(2.0 * ((PI / 3.0).cos() / (PI / 5.0).sin()).acos());
    for ring in 1..6 {
        let turn = M3::rotation_z(PI * (2.0 * (ring - 1) as f64 + 1.0) / 5.0);
        for k in 0..5 {
            v[5 * ring + k] = turn.apply(tip.apply(v[k]));
        }
    }
    v
}

/// Generates a pyramid of `size` layers.
pub fn generate(size: u32) -> Scene {
    // Layers are spread so that the pyramid fills a 45 degree view from its apex.
    let spread = 1.0 / (PI / 8.0).sin();
    let from = D3::new(-1.0, -spread, 0.5);
    let camera = Camera {
        from,
        at: from + D3::new(0.0, 1.0, 0.0),
        up: D3::Z,
        hither: 1.0,
    };
    let lights = [
        D3::new(3.0, -spread, 3.0),
        D3::new(-4.0, -spread, 1.0),
        D3::new(2.0, -spread, -4.0),
    ];
    let mut b = Builder::new(camera, &lights);
    let n = size as usize;
    let objects = n * (n + 1) * (2 * n + 1) / 6;
    b.reserve(30 * objects, 30 * objects, 4, 0);

    // The wall just spans the 45 degree view, plus 1%.
    b.surface(Surface {
        color: [1.0; 3],
        kd: 1.0,
        ks: 0.0,
        highlight_deg: 0.0,
        t: 0.0,
        ior: 0.0,
    });
    let wy = spread * (size as f64 + 1.0);
    let w = 1.01 * (wy - from.y) * (PI / 8.0).tan();
    b.polygon(&[
        D3::new(w + from.x, wy, w + from.z),
        D3::new(-w + from.x, wy, w + from.z),
        D3::new(-w + from.x, wy, -w + from.z),
        D3::new(w + from.x, wy, -w + from.z),
    ]);

    let verts = ring_vertices();
    for depth in 0..size {
        let y = spread * (depth + 1) as f64;
        for iz in 0..=depth {
            let z = (2 * iz) as f64 - depth as f64;
            for ix in 0..=depth {
                let offset = D3::new((2 * ix) as f64 - depth as f64, y, z);
                for (e, v) in verts.iter().enumerate() {
                    let prev = if e % 5 == 0 {
                        b.surface(Surface {
                            color: COLORS[e / 5],
                            kd: 0.5,
                            ks: 0.2,
                            highlight_deg: 37.0,
                            t: 0.0,
                            ior: 0.0,
                        });
                        e + 4
                    } else {
                        e - 1
                    };
                    let base = *v + offset;
                    b.cone(base, TUBE, verts[prev] + offset, TUBE);
                    b.sphere(base, TUBE);
                }
            }
        }
    }
    b.finish()
}
