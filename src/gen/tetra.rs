//! `tetra`: a recursive tetrahedral pyramid (Mandelbrot's and Norton's Sierpinski
//! tetrahedron, as used by Glassner and by Kay and Kajiya), one light.
//!
//! The unit cube's four corners whose coordinates multiply to +1 form a
//! tetrahedron. It is replaced by the four half-size tetrahedra at its corners,
//! recursively, until `size` levels (counting the whole as the first); each
//! remaining tetrahedron is output as four triangles, wound outwards.
//!
//! Triangles: `4^size` (4096 at the default size 6).

use super::builder::{Builder, Camera, Surface};
use super::dvec::D3;
use crate::scene::Scene;

/// The SPD's default size.
pub const DEFAULT_SIZE: u32 = 6;

/// The corner directions `(x, y, z)` in {-1, 1}^3 with `x y z = 1`, x slowest.
const CORNERS: [[f64; 3]; 4] = [
    [-1.0, -1.0, 1.0],
    [-1.0, 1.0, -1.0],
    [1.0, -1.0, -1.0],
    [1.0, 1.0, 1.0],
];

/// Vertex indices of the four faces, each wound to face outwards.
const FACES: [[usize; 3]; 4] = [[0, 1, 2], [3, 2, 1], [2, 3, 0], [1, 0, 3]];

fn corner(center: D3, half: f64, k: usize) -> D3 {
    let [x, y, z] = CORNERS[k];
    center + D3::new(x, y, z) * half
}

/// Emits the tetrahedron inscribed in the cube of half-side `half` around `center`,
/// subdivided `depth - 1` more times.
fn tetra(b: &mut Builder, center: D3, half: f64, depth: u32) {
    if depth <= 1 {
        for f in FACES {
            b.polygon(&f.map(|k| corner(center, half, k)));
        }
        return;
    }
    for k in 0..4 {
        tetra(b, corner(center, half / 2.0, k), half / 2.0, depth - 1);
    }
}

/// Generates the pyramid with `size` levels (sizes 0 and 1 both give one tetrahedron).
pub fn generate(size: u32) -> Scene {
    let camera = Camera {
        from: D3::new(1.022846, -3.177154, -2.174512),
        at: D3::new(-0.004103, -0.004103, 0.216539),
        up: D3::new(-0.816497, -0.816497, 0.816497),
        hither: 1.0,
    };
    let mut b = Builder::new(camera, &[D3::new(2.0, -18.0, -5.0)]);
    b.reserve(0, 0, 3 << (2 * size.max(1)), 0);
    b.surface(Surface {
        color: [1.0, 0.2, 0.2],
        kd: 1.0,
        ks: 0.0,
        highlight_deg: 0.0,
        t: 0.0,
        ior: 0.0,
    });
    tetra(&mut b, D3::ZERO, 1.0, size);
    b.finish()
}
