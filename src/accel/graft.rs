//! Two BVHs under one root ([`Bvh::graft`]): a scene's fixed part, built once, and
//! the part that moves, built per frame, queried as one tree. An animation's frames
//! (AFF) then rebuild only what moves: the fixed part's arrays are copied whole, the
//! moving part's appended after them with its indices moved past the fixed part's,
//! and a new root holds the two parts' roots.
//!
//! The grafted tree holds the same primitives, with the same vertices, as a tree
//! built over both parts at once, and queries answer by the same rule (the nearest
//! hit, ties to the lowest rank), so it gives the same pictures; only the boxes the
//! walks open differ. The moving part's ranks keep its source lines and come after
//! the fixed part's among primitives of one line.

use super::build::sah::MAX_QUERY_DEPTH;
use super::build::split::{Copies, Piece};
use super::bvh::Bvh;
use super::leaf::pack::{leaf_kinds, CONE4_LEAF, SPHERE4_LEAF, TRI4_LEAF};
#[cfg(target_arch = "x86_64")]
use super::traverse::avx::Avx;
use super::traverse::wide::{Node8, EMPTY, MAX, MIN, WIDTH};
use crate::geometry::{GeometryData, Primitive, Shape, Triangle};
use crate::math::Aabb;

/// How far the moving part's indices move: past the fixed part's entries of each array.
#[derive(Clone, Copy)]
struct Offsets {
    /// Wide nodes (both parts also move one place for the new root).
    node: u32,
    tri4: u32,
    sphere4: u32,
    cone4: u32,
    /// Bounded primitives (leaf-order indices).
    bounded: u32,
    /// Entries of [`GeometryData::patch_normals`].
    normals: u32,
    /// Entries of [`GeometryData::polygon_points_2d`].
    points_2d: u32,
    /// The low half of a rank: the fixed part's primitives as built.
    rank: u64,
}

impl Bvh {
    /// `fixed` and `moving` as one tree (see the module docs).
    pub fn graft(fixed: &Bvh, moving: Bvh) -> Bvh {
        let depth = fixed.depth.max(moving.depth) + 1;
        debug_assert!(
            depth <= MAX_QUERY_DEPTH,
            "each part at most as deep as the builder makes"
        );
        let moved = Offsets {
            node: 1 + fixed.wide.len() as u32,
            tri4: fixed.tri4.len() as u32,
            sphere4: fixed.sphere4.len() as u32,
            cone4: fixed.cone4.len() as u32,
            bounded: fixed.bounded as u32,
            normals: fixed.data.patch_normals.len() as u32,
            points_2d: fixed.data.polygon_points_2d.len() as u32,
            rank: fixed
                .ranks
                .iter()
                .map(|r| (r & u64::from(u32::MAX)) + 1)
                .max()
                .unwrap_or(0),
        };
        let wide = graft_nodes(fixed, &moving, moved);
        let mut tri4 = fixed.tri4.clone();
        tri4.extend(moving.tri4.iter().map(|b| {
            let mut b = *b;
            b.prim = b.prim.map(|p| moved_prim(p, moved));
            b
        }));
        let mut sphere4 = fixed.sphere4.clone();
        sphere4.extend(moving.sphere4.iter().map(|b| {
            let mut b = *b;
            b.prim = b.prim.map(|p| moved_prim(p, moved));
            b
        }));
        let mut cone4 = fixed.cone4.clone();
        cone4.extend(moving.cone4.iter().map(|b| {
            let mut b = *b;
            b.prim = b.prim.map(|p| moved_prim(p, moved));
            b
        }));
        let (fb, mb) = (fixed.bounded, moving.bounded);
        let mut primitives = Vec::with_capacity(fixed.primitives.len() + moving.primitives.len());
        let mut ranks = Vec::with_capacity(primitives.capacity());
        let moved_rank = |r: &u64| r + moved.rank;
        // Bounded primitives in leaf order, the fixed part's first; then the unbounded.
        primitives.extend_from_slice(&fixed.primitives[..fb]);
        primitives.extend(moving.primitives[..mb].iter().map(|p| moved_primitive(p, moved)));
        primitives.extend_from_slice(&fixed.primitives[fb..]);
        primitives.extend(moving.primitives[mb..].iter().map(|p| moved_primitive(p, moved)));
        ranks.extend_from_slice(&fixed.ranks[..fb]);
        ranks.extend(moving.ranks[..mb].iter().map(moved_rank));
        ranks.extend_from_slice(&fixed.ranks[fb..]);
        ranks.extend(moving.ranks[mb..].iter().map(moved_rank));
        let copies = graft_copies(fixed, &moving, moved);
        let kinds = leaf_kinds::copy_for(&wide);
        Bvh {
            wide,
            tri4,
            sphere4,
            cone4,
            primitives,
            ranks,
            bounded: fb + mb,
            copies,
            data: graft_data(&fixed.data, &moving.data),
            depth: if fb + mb == 0 { 0 } else { depth },
            kinds,
            #[cfg(target_arch = "x86_64")]
            avx: Avx::detect(),
        }
    }
}

/// The new root, then `fixed`'s nodes, then `moving`'s, each child index moved.
fn graft_nodes(fixed: &Bvh, moving: &Bvh, moved: Offsets) -> Vec<Node8> {
    if fixed.bounded + moving.bounded == 0 {
        return Vec::new();
    }
    let mut wide = Vec::with_capacity(1 + fixed.wide.len() + moving.wide.len());
    let mut root = EMPTY;
    let parts = [(fixed, 1), (moving, moved.node)];
    for (lane, (part, first)) in parts.into_iter().filter(|(p, _)| !p.wide.is_empty()).enumerate() {
        let b = node_bounds(&part.wide[0]);
        for axis in 0..3 {
            root.bounds[MIN][axis][lane] = b.min.to_array()[axis];
            root.bounds[MAX][axis][lane] = b.max.to_array()[axis];
        }
        root.child[lane] = first;
    }
    wide.push(root);
    let fixed_moved = Offsets {
        node: 1,
        tri4: 0,
        sphere4: 0,
        cone4: 0,
        bounded: 0,
        ..moved
    };
    wide.extend(fixed.wide.iter().map(|n| moved_node(n, fixed_moved)));
    wide.extend(moving.wide.iter().map(|n| moved_node(n, moved)));
    wide
}

/// The box around every lane of `node`.
fn node_bounds(node: &Node8) -> Aabb {
    (0..WIDTH)
        .filter(|&lane| node.child[lane] != u32::MAX || node.count[lane] != 0)
        .map(|lane| node.lane_bounds(lane))
        .fold(Aabb::EMPTY, Aabb::union)
}

/// `node` with its children's indices moved by `moved`: interior children by the
/// node offset, leaves by the offset of the array they point into.
fn moved_node(node: &Node8, moved: Offsets) -> Node8 {
    let mut n = *node;
    for lane in 0..WIDTH {
        let count = n.count[lane] as usize;
        if count == 0 && n.child[lane] == u32::MAX {
            continue;
        }
        n.child[lane] += match count {
            0 => moved.node,
            _ if count & TRI4_LEAF != 0 => moved.tri4,
            _ if count & SPHERE4_LEAF != 0 => moved.sphere4,
            _ if count & CONE4_LEAF != 0 => moved.cone4,
            _ => moved.bounded,
        };
    }
    n
}

/// A block lane's primitive index moved, an empty lane's (`u32::MAX`) kept.
fn moved_prim(p: u32, moved: Offsets) -> u32 {
    if p == u32::MAX {
        p
    } else {
        p + moved.bounded
    }
}

/// A moving primitive with its indices into the geometry arrays moved past the
/// fixed part's entries.
fn moved_primitive(p: &Primitive, moved: Offsets) -> Primitive {
    let mut p = *p;
    match &mut p.shape {
        Shape::Triangle(t) if t.normals != Triangle::FLAT => t.normals += moved.normals,
        Shape::Polygon(poly) => poly.first += moved.points_2d,
        _ => {}
    }
    p
}

/// The two parts' geometry arrays, the moving part's after the fixed part's
/// (texture coordinates, kept parallel to the normals, filled with zeros for a part
/// without them).
fn graft_data(fixed: &GeometryData, moving: &GeometryData) -> GeometryData {
    let uvs = if fixed.patch_uvs.is_empty() && moving.patch_uvs.is_empty() {
        Vec::new()
    } else {
        let padded = |d: &GeometryData| {
            let mut uvs = d.patch_uvs.clone();
            uvs.resize(d.patch_normals.len(), [0.0; 2]);
            uvs
        };
        [padded(fixed), padded(moving)].concat()
    };
    GeometryData {
        polygon_points_2d: [&fixed.polygon_points_2d[..], &moving.polygon_points_2d].concat(),
        patch_normals: [&fixed.patch_normals[..], &moving.patch_normals].concat(),
        patch_uvs: uvs,
    }
}

/// The split cones' bookkeeping of the grafted tree: `None` when neither part has
/// split cones.
fn graft_copies(fixed: &Bvh, moving: &Bvh, moved: Offsets) -> Option<Copies> {
    if fixed.copies.is_none() && moving.copies.is_none() {
        return None;
    }
    let whole = Piece { index: 0, of: 1 };
    let part = |bvh: &Bvh, base: u32| -> (Vec<u32>, Vec<Piece>, usize) {
        match &bvh.copies {
            Some(c) => (
                c.canonical.iter().map(|&i| i + base).collect(),
                c.piece.clone(),
                c.distinct,
            ),
            None => (
                (0..bvh.bounded as u32).map(|i| i + base).collect(),
                vec![whole; bvh.bounded],
                bvh.bounded,
            ),
        }
    };
    let (mut canonical, mut piece, fixed_distinct) = part(fixed, 0);
    let (c, p, moving_distinct) = part(moving, moved.bounded);
    canonical.extend(c);
    piece.extend(p);
    Some(Copies {
        canonical,
        piece,
        distinct: fixed_distinct + moving_distinct,
    })
}
