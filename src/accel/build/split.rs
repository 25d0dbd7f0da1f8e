//! Long oblique cones split into pieces for the tree (early split clipping: Ernst
//! and Greiner 2007, "Early split clipping for bounding volume hierarchies").
//!
//! A thin cylinder lying across the axes fills a sliver of its bounding box, and the
//! SPD's rings are thousands of them: every ray passing near one enters its box. The
//! builder gets instead one reference per piece, each with the far smaller box of its
//! part of the side; the leaves then hold the whole cone once per piece, so a ray
//! tests it in whichever leaf it enters first, and finds the same hit in every one.
//! Queries report a split cone by the index of its first copy in leaf order
//! ([`Copies::canonical`]), and its copies share one rank (its place in the scene),
//! so they never compete as different primitives (`traverse::nearest`).

use rayon::prelude::*;

use super::sah::Pack;
use crate::geometry::{ConeShape, Primitive, Shape};
use crate::math::Aabb;

/// The most pieces a cone is split into. Measured on the SPD's rings (`--spd`
/// render, one thread, best of 3): two pieces −7 %, three −4 %, five −3 %: beyond
/// two, the extra copies a ray tests cost more than the tighter boxes save.
const MAX_PIECES: u32 = 2;

// `Bvh::validate` keeps a bit per piece in a `u64`.
const _: () = assert!(MAX_PIECES <= 64);

/// A cone is halved when its halves' boxes have less than this share of its box's
/// surface area (the SAH's measure of how many rays enter them). An axis-parallel
/// cylinder's halves keep all of it (their boxes tile its box) and stay whole.
const SPLIT_BELOW: f32 = 0.8;

/// Only cones at least this many times longer than their widest diameter are split:
/// a ray entering the box of a thin one mostly misses it, one entering the box of a
/// stout one often hits it anyway. Measured: the SPD's tree, whose branches are 2.5
/// to 5.5 diameters long, lost up to 5 % on occlusion with its oblique branches
/// halved (its render 1 % slower); the rings' cylinders are 7.4 diameters long.
const THIN: f32 = 6.0;

/// Which piece of a split primitive a reference stands for.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(in crate::accel) struct Piece {
    /// The piece, from 0 at the base.
    pub index: u8,
    /// How many pieces (1: the whole primitive).
    pub of: u8,
}

impl Piece {
    /// The `of` pieces of a primitive split in `of`, from the base.
    pub fn all(of: u8) -> impl Iterator<Item = Piece> {
        (0..of).map(move |index| Piece { index, of })
    }

    /// The box of this piece of `cone`.
    pub fn bounds_of(self, cone: &ConeShape) -> Aabb {
        let step = cone.length / f32::from(self.of);
        let to = if self.index + 1 == self.of {
            cone.length
        } else {
            step * f32::from(self.index + 1)
        };
        cone.piece_bounds(step * f32::from(self.index), to)
    }
}

/// The boxes the builder sorts: one per primitive, or per piece of a split cone.
pub(in crate::accel) struct References {
    /// Each reference's box.
    pub bounds: Vec<Aabb>,
    /// Each reference's kind of block (its primitive's).
    pub packs: Vec<Pack>,
    /// The primitive each reference stands for.
    pub primitive: Vec<u32>,
    /// The piece each reference stands for.
    pub piece: Vec<Piece>,
}

/// Leaf-order bookkeeping of a tree with split cones (see the module docs).
#[derive(Clone, Debug)]
pub(in crate::accel) struct Copies {
    /// Per leaf-order index, the leaf-order index of the first copy of its primitive:
    /// the index the queries report.
    pub canonical: Vec<u32>,
    /// Per leaf-order index, the piece of its primitive that its leaf holds.
    pub piece: Vec<Piece>,
    /// Distinct bounded primitives.
    pub distinct: usize,
}

impl Copies {
    /// The bookkeeping for the leaf order `order` of references into `refs`.
    pub fn new(refs: &References, order: &[u32], distinct: usize) -> Copies {
        let mut first = vec![u32::MAX; distinct];
        let canonical = order
            .iter()
            .enumerate()
            .map(|(i, &r)| {
                let f = &mut first[refs.primitive[r as usize] as usize];
                if *f == u32::MAX {
                    *f = i as u32;
                }
                *f
            })
            .collect();
        let piece = order.iter().map(|&r| refs.piece[r as usize]).collect();
        Copies {
            canonical,
            piece,
            distinct,
        }
    }
}

/// How many pieces `cone` is split into: if it is [`THIN`], halved while that takes
/// its boxes' surface area below [`SPLIT_BELOW`] of the whole's, up to
/// [`MAX_PIECES`].
pub(in crate::accel) fn pieces(cone: &ConeShape) -> u32 {
    let diameter = 2.0 * cone.base_radius.max(cone.apex_radius());
    // (Packable cones have a finite positive length; NaN radii are never split.)
    if cone.length < THIN * diameter || diameter.is_nan() {
        return 1;
    }
    let area = |of: u32| -> f32 {
        Piece::all(of as u8)
            .map(|p| p.bounds_of(cone).surface_area())
            .sum()
    };
    let mut of = 1;
    let mut current = area(1);
    while of < MAX_PIECES {
        let halved = area(2 * of);
        if halved < SPLIT_BELOW * current {
            of *= 2;
            current = halved;
        } else {
            break;
        }
    }
    of
}

/// The references for `primitives` (with their boxes `bounds(i)` and `packs`), or `None`
/// when no cone is worth splitting (then the builder takes the primitives as they
/// are).
pub(in crate::accel) fn split_long_cones(
    primitives: &[Primitive],
    bounds: impl Fn(usize) -> Aabb + Sync,
    packs: &[Pack],
) -> Option<References> {
    if !packs.par_iter().any(|&p| p == Pack::Cone) {
        return None;
    }
    // (In parallel: a generated rings of 280 000 cones spent 25 ms here on one.)
    let counts: Vec<u8> = primitives
        .par_iter()
        .zip(packs)
        .map(|(p, &pack)| match (&p.shape, pack) {
            (Shape::Cone(c), Pack::Cone) => pieces(c) as u8,
            _ => 1,
        })
        .collect();
    if counts.par_iter().all(|&n| n == 1) {
        return None;
    }
    let each = || counts.par_iter().enumerate();
    let bounds = &bounds;
    Some(References {
        bounds: each()
            .flat_map_iter(|(i, &of)| {
                Piece::all(of).map(move |piece| match &primitives[i].shape {
                    Shape::Cone(c) if of > 1 => piece.bounds_of(c),
                    _ => bounds(i),
                })
            })
            .collect(),
        packs: each()
            .flat_map_iter(|(i, &of)| std::iter::repeat_n(packs[i], of.into()))
            .collect(),
        primitive: each()
            .flat_map_iter(|(i, &of)| std::iter::repeat_n(i as u32, of.into()))
            .collect(),
        piece: each().flat_map_iter(|(_, &of)| Piece::all(of)).collect(),
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::math::Vec3;

    /// A thin cylinder across the x and y axes, like the rings' (radius 0.074,
    /// length about 1.09).
    fn oblique() -> ConeShape {
        ConeShape::new(
            Vec3::new(0.930995, 2.61313, 0.0),
            0.07412,
            Vec3::new(0.287693, 1.7277, 0.0),
            0.07412,
        )
    }

    #[test]
    fn oblique_thin_cylinders_are_halved_and_axis_parallel_ones_kept_whole() {
        assert_eq!(pieces(&oblique()), 2);
        let upright = ConeShape::new(Vec3::ZERO, 0.07, Vec3::new(0.0, 0.0, 1.1), 0.07);
        assert_eq!(pieces(&upright), 1);
        // Short and fat: a box it nearly fills whatever its tilt.
        let stubby = ConeShape::new(Vec3::ZERO, 1.0, Vec3::new(0.3, 0.3, 0.0), 1.0);
        assert_eq!(pieces(&stubby), 1);
        // As tilted as the rings' first cylinder but five diameters long (a tree
        // branch): kept whole.
        let branch = ConeShape::new(Vec3::ZERO, 0.1, Vec3::new(-0.59, -0.81, 0.0), 0.1);
        assert_eq!(pieces(&branch), 1);
        let twig = ConeShape::new(Vec3::ZERO, 0.1, Vec3::new(-0.59, -0.81, 0.0) * 1.4, 0.1);
        assert_eq!(pieces(&twig), 2);
    }

    /// Points of the side, computed from the cone's definition (the circle of radius
    /// r(s) around the axis at distance s), each lie in the box of the piece holding
    /// their s, and the pieces together cover the whole side.
    #[test]
    fn each_piece_box_holds_its_part_of_the_side() {
        let cones = [
            oblique(),
            ConeShape::new(Vec3::new(-3.0, 1.0, 2.0), 0.5, Vec3::new(4.0, -2.0, 7.0), 0.1),
            ConeShape::new(
                Vec3::new(100.0, 200.0, -50.0),
                0.01,
                Vec3::new(101.0, 201.0, -49.0),
                0.3,
            ),
        ];
        for cone in cones {
            let w = cone.axis;
            let u = w
                .cross(if w.x.abs() < 0.9 {
                    Vec3::new(1.0, 0.0, 0.0)
                } else {
                    Vec3::new(0.0, 1.0, 0.0)
                })
                .normalize();
            let v = w.cross(u);
            for of in [1u8, 2, 4] {
                let boxes: Vec<Aabb> = Piece::all(of).map(|p| p.bounds_of(&cone)).collect();
                for i in 0..=64 {
                    let s = cone.length * i as f32 / 64.0;
                    let r = cone.base_radius + cone.slope * s;
                    let piece = ((s / cone.length * f32::from(of)) as u8).min(of - 1);
                    for k in 0..32 {
                        let phi = std::f32::consts::TAU * k as f32 / 32.0;
                        let p = cone.base + w * s + (u * phi.cos() + v * phi.sin()) * r;
                        assert!(
                            boxes[piece as usize].contains(&Aabb::new(p, p)),
                            "{p:?} (s = {s}) outside piece {piece} of {of}: {:?}",
                            boxes[piece as usize]
                        );
                    }
                }
            }
        }
    }
}
