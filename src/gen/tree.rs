//! `tree`: a binary tree of cone branches with spheres at the joints, grown by Aono
//! and Kunii's method (IEEE CG&A, May 1984), on a square field; seven lights.
//!
//! A branch is a cone from its base to its tip, in its own frame from (0,0,0) to
//! (0,0,1), with base radius 0.15 times its scale and tip radius 0.67 times that,
//! capped by a sphere at the tip. Each branch carries two children whose frames are
//! the parent's frame turned about x by the branching angle (40 and 25 degrees),
//! then about z by the divergence (90 and 230 degrees), shrunk by the contraction
//! (0.65 and 0.70) and moved to the parent's tip. A child's radii are those of a
//! branch of scale 0.67 times the parent's. `size` levels of children follow the trunk.
//!
//! Cones and spheres: `2^(size + 1) - 1` each (4095 at the default size 11), plus
//! the field.

use super::builder::{Builder, Camera, Surface};
use super::dvec::{Affine, D3, M3};
use crate::scene::Scene;

/// The SPD's default size.
pub const DEFAULT_SIZE: u32 = 11;

/// Branching angles of the two children, in degrees.
const BRANCH_ANGLE: [f64; 2] = [40.0, 25.0];
/// Divergence angles of the two children, in degrees.
const DIVERGENCE: [f64; 2] = [90.0, 140.0 + 90.0];
/// Length of each child relative to its parent.
const CONTRACTION: [f64; 2] = [0.65, 0.70];
/// Radius of a child branch relative to its parent, and tip radius relative to base.
const DIAMETER: f64 = 0.67;
/// Base radius of a branch of scale 1.
const WIDTH_HEIGHT_RATIO: f64 = 0.15;

/// The frame of each child relative to its parent's frame.
fn child_frames() -> [Affine; 2] {
    [0, 1].map(|i| {
        let turn = M3::rotation_z(DIVERGENCE[i].to_radians())
            .then_after(&M3::rotation_x(BRANCH_ANGLE[i].to_radians()));
        Affine {
            m: M3::scale(CONTRACTION[i]).then_after(&turn),
            t: D3::Z,
        }
    })
}

/// Emits a branch in `frame`, then (depth first) its descendants.
fn grow(b: &mut Builder, children: &[Affine; 2], frame: &Affine, scale: f64, depth: u32) {
    let base = frame.apply(D3::ZERO);
    let tip = frame.apply(D3::Z);
    let base_radius = scale * WIDTH_HEIGHT_RATIO;
    let tip_radius = base_radius * DIAMETER;
    b.cone(base, base_radius, tip, tip_radius);
    b.sphere(tip, tip_radius);
    if depth == 0 {
        return;
    }
    for child in children {
        grow(b, children, &frame.then_after(child), scale * DIAMETER, depth - 1);
    }
}

/// Generates a tree with `size` levels of branching.
pub fn generate(size: u32) -> Scene {
    let camera = Camera {
        from: D3::new(4.5, 0.4, 2.0),
        at: D3::new(0.0, 0.0, 1.5),
        up: D3::Z,
        hither: 1.0,
    };
    let lights = [
        D3::new(-5.0, 5.0, 50.0),
        D3::new(30.0, -30.0, 30.0),
        D3::new(-40.0, -30.0, 20.0),
        D3::new(10.0, 30.0, 40.0),
        D3::new(-30.0, 40.0, 10.0),
        D3::new(50.0, 25.0, 20.0),
        D3::new(-10.0, -60.0, 30.0),
    ];
    let mut b = Builder::new(camera, &lights);
    let branches = (2usize << size) - 1;
    b.reserve(branches, branches, 4, 0);

    b.surface(Surface {
        color: [0.2, 0.7, 0.2],
        kd: 1.0,
        ks: 0.0,
        highlight_deg: 0.0,
        t: 0.0,
        ior: 0.0,
    });
    let f = 50.0;
    b.polygon(&[
        D3::new(f, f, 0.0),
        D3::new(-f, f, 0.0),
        D3::new(-f, -f, 0.0),
        D3::new(f, -f, 0.0),
    ]);

    b.surface(Surface {
        color: [0.55, 0.4, 0.2],
        kd: 1.0,
        ks: 0.0,
        highlight_deg: 0.0,
        t: 0.0,
        ior: 0.0,
    });
    grow(&mut b, &child_frames(), &Affine::IDENTITY, 1.0, size);
    b.finish()
}
