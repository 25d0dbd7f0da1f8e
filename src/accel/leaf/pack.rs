//! Leaves packed into blocks: which primitives share a block ([`pack_of`]), the wide
//! leaf lanes repacked into blocks of one kind and marked as such ([`pack_leaves`],
//! [`TRI4_LEAF`] and the other marks), and the sets of leaf kinds a tree holds, each
//! served by a copy of the queries compiled without the other kinds' tests
//! ([`leaf_kinds`]).

use super::cone4::Cone4;
use super::sphere4::Sphere4;
use super::tri4::{Tri4, LANES};
use crate::accel::build::sah::Pack;
use crate::accel::traverse::wide::{Node8, WIDTH};
use crate::geometry::{Primitive, Shape};
use crate::pages::huge_vec;
use rayon::prelude::*;
use std::ops::Range;

/// Marks a wide leaf lane whose primitives are all triangles: its `child` is the first
/// of `count & !TRI4_LEAF` [`Tri4`] blocks instead of the first primitive.
pub(in crate::accel) const TRI4_LEAF: usize = 1 << 31;

/// Marks a wide leaf lane whose primitives are all spheres packed in blocks: its
/// `child` is the first of `count & !SPHERE4_LEAF` [`Sphere4`] blocks.
pub(in crate::accel) const SPHERE4_LEAF: usize = 1 << 30;

/// Marks a wide leaf lane whose primitives are all cones packed in blocks: its
/// `child` is the first of `count & !CONE4_LEAF` [`Cone4`] blocks.
pub(in crate::accel) const CONE4_LEAF: usize = 1 << 29;

/// Sets of leaf kinds, as bits, for the copies of the queries (see [`Bvh::kinds`](crate::accel::bvh::Bvh::kinds)).
pub(in crate::accel) mod leaf_kinds {
    use super::{Node8, CONE4_LEAF, SPHERE4_LEAF, TRI4_LEAF, WIDTH};

    /// Leaves of [`super::Tri4`] blocks.
    pub const TRIANGLES: u32 = 1;
    /// Leaves of [`super::Sphere4`] blocks.
    pub const SPHERES: u32 = 2;
    /// Leaves of [`super::Cone4`] blocks.
    pub const CONES: u32 = 4;
    /// Leaves of primitives tested one by one.
    pub const PRIMITIVES: u32 = 8;
    /// Triangle and sphere blocks (the SPD's balls and mount).
    pub const SPHERES_AND_TRIANGLES: u32 = SPHERES | TRIANGLES;
    /// Every kind.
    pub const ALL: u32 = TRIANGLES | SPHERES | CONES | PRIMITIVES;

    /// The set with a copy of the queries that serves the tree `wide`: the smallest
    /// of [`TRIANGLES`], [`SPHERES_AND_TRIANGLES`] and [`ALL`] holding its leaves'.
    pub fn copy_for(wide: &[Node8]) -> u32 {
        let mut present = 0;
        for node in wide {
            for &count in &node.count[..WIDTH] {
                let count = count as usize;
                present |= match count {
                    0 => 0,
                    _ if count & TRI4_LEAF != 0 => TRIANGLES,
                    _ if count & SPHERE4_LEAF != 0 => SPHERES,
                    _ if count & CONE4_LEAF != 0 => CONES,
                    _ => PRIMITIVES,
                };
            }
        }
        [TRIANGLES, SPHERES_AND_TRIANGLES]
            .into_iter()
            .find(|&set| present & !set == 0)
            .unwrap_or(ALL)
    }
}

/// Evaluates `$call` with the const `$k` set to the kinds of the query copy that
/// serves a tree of leaf kinds `$kinds` (see [`leaf_kinds::copy_for`]).
macro_rules! with_kinds {
    ($kinds:expr, $k:ident => $call:expr) => {
        match $kinds {
            leaf_kinds::TRIANGLES => {
                const $k: u32 = leaf_kinds::TRIANGLES;
                $call
            }
            leaf_kinds::SPHERES_AND_TRIANGLES => {
                const $k: u32 = leaf_kinds::SPHERES_AND_TRIANGLES;
                $call
            }
            _ => {
                const $k: u32 = leaf_kinds::ALL;
                $call
            }
        }
    };
}
pub(in crate::accel) use with_kinds;

/// The kind of block `p` is tested in (see [`Pack`]): triangles, and spheres
/// and (non-degenerate) cones visible from outside, pack four to a block; everything
/// else is tested alone, moving spheres among them (where they are depends on each
/// ray's time, which the blocks' broadcast rays do not carry).
pub(in crate::accel) fn pack_of(p: &Primitive) -> Pack {
    match p.shape {
        Shape::Triangle(_) => Pack::Triangle,
        Shape::Sphere(s) if !s.inside => Pack::Sphere,
        Shape::Cone(c) if !c.inside && c.length > 0.0 => Pack::Cone,
        Shape::MovingSphere(_) => Pack::Alone,
        _ => Pack::Alone,
    }
}

/// The blocks of [`pack_leaves`].
#[derive(Default)]
pub(in crate::accel) struct Blocks {
    pub tri4: Vec<Tri4>,
    pub sphere4: Vec<Sphere4>,
    pub cone4: Vec<Cone4>,
}

/// Repacks every wide leaf lane made only of triangles into [`Tri4`] blocks (marked
/// with [`TRI4_LEAF`]), every one made only of packable spheres into [`Sphere4`]
/// blocks (marked with [`SPHERE4_LEAF`]) and every one made only of packable cones
/// into [`Cone4`] blocks (marked with [`CONE4_LEAF`]); other leaves keep pointing at
/// `primitives`. `packs[i]` is [`pack_of`] `primitives[i]`.
pub(in crate::accel) fn pack_leaves(
    wide: &mut [Node8],
    primitives: &[Primitive],
    packs: &[Pack],
    canonical: Option<&[u32]>,
) -> Blocks {
    // The lanes pointed at their blocks and the blocks listed, in leaf order, on one
    // thread (this reads only the nodes and the kinds); then the blocks made on all.
    let mut blocks: [Vec<Range<u32>>; 4] = Default::default();
    for node in wide.iter_mut() {
        for lane in 0..WIDTH {
            let Some(kind) = packed_leaf(node, lane, packs) else {
                continue;
            };
            let (first, end) = (node.child[lane], node.child[lane] + node.count[lane]);
            let list = &mut blocks[kind as usize];
            let start = list.len();
            list.extend((first..end).step_by(LANES).map(|b| b..end.min(b + LANES as u32)));
            node.child[lane] = start as u32;
            node.count[lane] = (mark(kind) | (list.len() - start)) as u32;
        }
    }
    let leaves = Leaves {
        primitives,
        canonical,
    };
    let triangle = |s: &Shape| match s {
        Shape::Triangle(t) => Some(*t),
        _ => None,
    };
    let sphere = |s: &Shape| match s {
        Shape::Sphere(s) => Some(*s),
        _ => None,
    };
    let cone = |s: &Shape| match s {
        Shape::Cone(c) => Some(*c),
        _ => None,
    };
    Blocks {
        tri4: leaves.pack(&blocks[Pack::Triangle as usize], triangle, Tri4::new),
        sphere4: leaves.pack(&blocks[Pack::Sphere as usize], sphere, Sphere4::new),
        cone4: leaves.pack(&blocks[Pack::Cone as usize], cone, Cone4::new),
    }
}

/// The mark of a leaf lane packed in blocks of `kind` (not [`Pack::Alone`]).
fn mark(kind: Pack) -> usize {
    match kind {
        Pack::Alone => unreachable!("primitives tested alone are not packed"),
        Pack::Triangle => TRI4_LEAF,
        Pack::Sphere => SPHERE4_LEAF,
        Pack::Cone => CONE4_LEAF,
    }
}

/// The kind of block of leaf lane `lane` of `node`, when its primitives all pack in
/// blocks of one kind (`packs` as in [`pack_leaves`]).
fn packed_leaf(node: &Node8, lane: usize, packs: &[Pack]) -> Option<Pack> {
    let (first, count) = (node.child[lane] as usize, node.count[lane] as usize);
    if count == 0 {
        return None;
    }
    let leaf = &packs[first..first + count];
    let kind = leaf[0];
    (kind != Pack::Alone && leaf.iter().all(|&p| p == kind)).then_some(kind)
}

/// The primitives in leaf order, and how the queries report leaf-order indices
/// (`canonical`, if given).
struct Leaves<'a> {
    primitives: &'a [Primitive],
    canonical: Option<&'a [u32]>,
}

impl Leaves<'_> {
    /// The blocks (`make`, [`LANES`] shapes at most) of the leaf-order ranges
    /// `blocks`, whose primitives all have the shape `shape` picks out; made on all
    /// threads.
    fn pack<T: Send, B: Send>(
        &self,
        blocks: &[Range<u32>],
        shape: impl Fn(&Shape) -> Option<T> + Sync + Send,
        make: impl Fn(&[(T, u32)]) -> B + Sync + Send,
    ) -> Vec<B> {
        let mut out = huge_vec(blocks.len());
        blocks
            .par_iter()
            .map_init(Vec::new, |lanes, block| {
                lanes.clear();
                for index in block.start as usize..block.end as usize {
                    if let Some(t) = shape(&self.primitives[index].shape) {
                        lanes.push((t, self.canonical.map_or(index as u32, |c| c[index])));
                    }
                }
                make(lanes)
            })
            .collect_into_vec(&mut out);
        out
    }
}

/// The blocks of a leaf lane (`first`, `count` as in a [`Node8`]) when its count
/// carries `mark` (blocks of one kind, see [`TRI4_LEAF`] and the others), counted as
/// primitive tests.
#[inline(always)]
pub(in crate::accel) fn marked<B>(blocks: &[B], first: usize, count: usize, mark: usize) -> Option<&[B]> {
    if count & mark == 0 {
        return None;
    }
    let blocks = &blocks[first..first + (count & !mark)];
    count!(PRIMS, blocks.len() * LANES);
    Some(blocks)
}
