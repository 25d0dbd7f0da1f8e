//! `balls`, the sphereflake: a sphere of radius 1/2 sprouting nine spheres of a third
//! its radius, each sprouting nine more, `size` levels deep, above a square floor.
//!
//! Each child touches its parent. The nine children of a sphere growing along the
//! +z axis sit in three trios: the first trio points along `(1,1,0)`, `(1,0,-1)` and
//! `(0,1,-1)` (each over the square root of two), tilted about the axis `(1,-1,0)` by
//! `asin(2/sqrt 6)` so that the first points 54.74 degrees above the equator; the
//! other two trios are that trio turned 120 and 240 degrees about z. A child growing
//! in direction `d` gets the same pattern turned so that +z maps onto `d` (turning
//! about `z x d`). Three lights; mirror-like spheres, a beige floor.
//!
//! Spheres: `sum of 9^k for k = 0..=size` (7381 at the default size 4), plus one polygon.

use super::builder::{Builder, Camera, Surface};
use super::dvec::{D3, M3};
use crate::scene::Scene;

/// The SPD's default size.
pub const DEFAULT_SIZE: u32 = 4;

/// A child's radius relative to its parent's.
const RATIO: f64 = 1.0 / 3.0;

/// The directions of the nine children of a sphere that grows along +z.
fn child_directions() -> [D3; 9] {
    let d = std::f64::consts::FRAC_1_SQRT_2;
    let trio = [D3::new(d, d, 0.0), D3::new(d, 0.0, -d), D3::new(0.0, d, -d)];
    let tilt = M3::rotation(D3::new(1.0, -1.0, 0.0).normalized(), (2.0 / 6f64.sqrt()).asin());
    let mut dirs = [D3::ZERO; 9];
    for set in 0..3 {
        let turn = M3::rotation_z(set as f64 * 2.0 * std::f64::consts::PI / 3.0);
        for (k, v) in trio.iter().enumerate() {
            dirs[set * 3 + k] = turn.apply(tilt.apply(*v));
        }
    }
    dirs
}

/// Directions this close to straight up or down count as exactly vertical.
const VERTICAL: f64 = 1e-9;

/// The rotation taking +z onto the unit vector `dir`. Straight down, every axis in
/// the xy plane would do; like the SPD we turn about y, and we treat directions
/// within rounding error of vertical as vertical, so that noise does not pick the axis.
fn z_onto(dir: D3) -> M3 {
    if dir.z >= 1.0 - VERTICAL {
        M3::IDENTITY
    } else if dir.z <= -1.0 + VERTICAL {
        M3::rotation(D3::new(0.0, 1.0, 0.0), std::f64::consts::PI)
    } else {
        M3::rotation(D3::Z.cross(dir).normalized(), dir.z.acos())
    }
}

/// Emits a sphere, then (depth first) its descendants `depth` levels down.
fn flake(b: &mut Builder, dirs: &[D3; 9], center: D3, radius: f64, dir: D3, depth: u32) {
    b.sphere(center, radius);
    if depth == 0 {
        return;
    }
    let turn = z_onto(dir);
    // Parent and child touch: centres are r + r/3 apart.
    let dist = radius * (1.0 + RATIO);
    for d in dirs {
        let child_dir = turn.apply(*d);
        flake(
            b,
            dirs,
            center + child_dir * dist,
            radius * RATIO,
            child_dir,
            depth - 1,
        );
    }
}

/// Generates the sphereflake with `size` levels of children.
pub fn generate(size: u32) -> Scene {
    let camera = Camera {
        from: D3::new(2.1, 1.3, 1.7),
        at: D3::ZERO,
        up: D3::Z,
        hither: 0.01,
    };
    let lights = [
        D3::new(4.0, 3.0, 2.0),
        D3::new(1.0, -4.0, 4.0),
        D3::new(-3.0, 1.0, 5.0),
    ];
    let mut b = Builder::new(camera, &lights);
    let spheres = (9usize.pow(size + 1) - 1) / 8;
    b.reserve(spheres, 0, 4, 0);

    b.surface(Surface {
        color: [1.0, 0.75, 0.33],
        kd: 0.8,
        ks: 0.0,
        highlight_deg: 0.0,
        t: 0.0,
        ior: 1.0,
    });
    let (w, z) = (12.0, -0.5);
    b.polygon(&[
        D3::new(w, w, z),
        D3::new(-w, w, z),
        D3::new(-w, -w, z),
        D3::new(w, -w, z),
    ]);

    b.surface(Surface {
        color: [1.0, 0.9, 0.7],
        kd: 0.5,
        ks: 0.5,
        highlight_deg: 37.0,
        t: 0.0,
        ior: 1.0,
    });
    flake(&mut b, &child_directions(), D3::ZERO, 0.5, D3::Z, size);
    b.finish()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn children_are_unit_and_spread() {
        let dirs = child_directions();
        for (i, a) in dirs.iter().enumerate() {
            assert!((a.length() - 1.0).abs() < 1e-12);
            for b in &dirs[i + 1..] {
                // Children of radius 1/3 around a unit parent never overlap.
                assert!((*a - *b).length() * (4.0 / 3.0) >= 2.0 / 3.0 - 1e-12);
            }
        }
        // The first child points 54.74 degrees above the equator: z = sin(asin(2/sqrt 6)).
        assert!((dirs[0].z - (2.0f64 / 3.0).sqrt()).abs() < 1e-12);
    }

    #[test]
    fn z_onto_maps_z_to_the_direction() {
        for d in [D3::Z, -D3::Z, D3::new(0.3, -0.4, 0.5).normalized()] {
            assert!((z_onto(d).apply(D3::Z) - d).length() < 1e-12);
        }
    }
}
