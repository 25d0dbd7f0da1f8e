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
/// `primitives`.
pub(in crate::accel) fn pack_leaves(
    wide: &mut [Node8],
    primitives: &[Primitive],
    canonical: Option<&[u32]>,
) -> Blocks {
    // The blocks of each kind counted first, so each array is allocated once (and on
    // huge pages when big, as the queries walk it).
    let mut count = [0; 4];
    for node in wide.iter() {
        for lane in 0..WIDTH {
            if let Some((kind, leaf)) = packed_leaf(node, lane, primitives) {
                count[kind as usize] += leaf.len().div_ceil(LANES);
            }
        }
    }
    let mut blocks = Blocks {
        tri4: huge_vec(count[Pack::Triangle as usize]),
        sphere4: huge_vec(count[Pack::Sphere as usize]),
        cone4: huge_vec(count[Pack::Cone as usize]),
    };
    let (mut triangles, mut spheres, mut cones) = (Vec::new(), Vec::new(), Vec::new());
    for node in wide.iter_mut() {
        for lane in 0..WIDTH {
            let Some((kind, leaf)) = packed_leaf(node, lane, primitives) else {
                continue;
            };
            let first = node.child[lane] as usize;
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
            let leaf = Leaf {
                primitives: leaf,
                first,
                canonical,
            };
            let (range, mark) = match kind {
                Pack::Alone => unreachable!("packed_leaf leaves out primitives tested alone"),
                Pack::Triangle => (
                    leaf.pack(triangle, Tri4::new, &mut triangles, &mut blocks.tri4),
                    TRI4_LEAF,
                ),
                Pack::Sphere => (
                    leaf.pack(sphere, Sphere4::new, &mut spheres, &mut blocks.sphere4),
                    SPHERE4_LEAF,
                ),
                Pack::Cone => (
                    leaf.pack(cone, Cone4::new, &mut cones, &mut blocks.cone4),
                    CONE4_LEAF,
                ),
            };
            node.child[lane] = range.start as u32;
            node.count[lane] = (mark | range.len()) as u32;
        }
    }
    debug_assert_eq!(
        [blocks.tri4.len(), blocks.sphere4.len(), blocks.cone4.len()],
        [Pack::Triangle, Pack::Sphere, Pack::Cone].map(|k| count[k as usize])
    );
    blocks
}

/// The primitives of leaf lane `lane` of `node` and their kind of block, when they
/// all pack in blocks of one kind.
fn packed_leaf<'a>(
    node: &Node8,
    lane: usize,
    primitives: &'a [Primitive],
) -> Option<(Pack, &'a [Primitive])> {
    let (first, count) = (node.child[lane] as usize, node.count[lane] as usize);
    if count == 0 {
        return None;
    }
    let leaf = &primitives[first..first + count];
    let kind = pack_of(&leaf[0]);
    (kind != Pack::Alone && leaf.iter().all(|p| pack_of(p) == kind)).then_some((kind, leaf))
}

/// A leaf to pack: its primitives, the first one's leaf-order index, and how the
/// queries report leaf-order indices (`canonical`, if given).
struct Leaf<'a> {
    primitives: &'a [Primitive],
    first: usize,
    canonical: Option<&'a [u32]>,
}

impl Leaf<'_> {
    /// Appends to `out` the blocks (`make`, [`LANES`] shapes at most, gathered in
    /// `lanes`) of the leaf, whose primitives all have the shape `shape` picks out;
    /// returns the range of the new blocks.
    fn pack<T, B>(
        &self,
        shape: impl Fn(&Shape) -> Option<T>,
        make: impl Fn(&[(T, u32)]) -> B,
        lanes: &mut Vec<(T, u32)>,
        out: &mut Vec<B>,
    ) -> std::ops::Range<usize> {
        let start = out.len();
        for (chunk_index, chunk) in self.primitives.chunks(LANES).enumerate() {
            lanes.clear();
            for (k, p) in chunk.iter().enumerate() {
                if let Some(t) = shape(&p.shape) {
                    let index = self.first + chunk_index * LANES + k;
                    lanes.push((t, self.canonical.map_or(index as u32, |c| c[index])));
                }
            }
            out.push(make(lanes));
        }
        start..out.len()
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
