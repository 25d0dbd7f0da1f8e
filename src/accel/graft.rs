//! Two BVHs under one root: a scene's fixed part, built once ([`Rootstock`]), and
//! the part that moves, built per frame, queried as one tree
//! ([`Rootstock::graft`]). An animation's frames (AFF) then rebuild only what
//! moves: the fixed part's arrays come first, the moving part's are appended after
//! them with their indices moved past the fixed part's, and a new root holds the
//! two parts' roots. A graft made in the arrays of the last one copies nothing of
//! the fixed part.
//!
//! The grafted tree holds the same primitives, with the same vertices, as a tree
//! built over both parts at once, and queries answer by the same rule (the nearest
//! hit, ties to the lowest rank), so it gives the same pictures; only the boxes the
//! walks open differ. The moving part's ranks keep its source lines and come after
//! the fixed part's among primitives of one line.

use std::sync::atomic::{AtomicU64, Ordering};

use super::build::sah::MAX_QUERY_DEPTH;
use super::build::split::{Copies, Piece};
use super::bvh::Bvh;
use super::leaf::cone4::Cone4;
use super::leaf::pack::{leaf_kinds, CONE4_LEAF, SPHERE4_LEAF, TRI4_LEAF};
use super::leaf::sphere4::Sphere4;
use super::leaf::tri4::Tri4;
use super::traverse::wide::{Node8, EMPTY, MAX, MIN, WIDTH};
use crate::geometry::{GeometryData, Primitive, Shape, Triangle};
use crate::math::Aabb;

/// A fixed part ready to take moving parts ([`Rootstock::graft`]): its tree under a
/// new root whose first lane holds it, the second left for each moving part.
#[derive(Clone, Debug)]
pub struct Rootstock {
    /// The fixed part's tree under the new root, until lent ([`Rootstock::lend`]).
    base: Option<Bvh>,
    /// What a graft needs to know of the base: its entries' counts, its root, its
    /// unbounded primitives (which go after the moving part's bounded ones).
    shape: StockShape,
    /// The low half of a rank past every fixed primitive's.
    rank: u64,
    /// Carried by the trees grafted onto this stock (`Bvh::stock`), so that one of
    /// them can lend its arrays to the next graft.
    id: u64,
}

/// The counts of the base's entries, its root and what follows its bounded entries.
#[derive(Clone, Debug)]
struct StockShape {
    root: Node8,
    nodes: usize,
    tri4: usize,
    sphere4: usize,
    cone4: usize,
    bounded: usize,
    /// The unbounded primitives and their ranks.
    unbounded: Vec<Primitive>,
    unbounded_ranks: Vec<u64>,
    points_2d: usize,
    normals: usize,
    uvs: usize,
    /// Entries of [`GeometryData::instances`].
    instances: usize,
    depth: u32,
    copies: Option<Copies>,
}

/// How far the moving part's indices move: past the fixed part's entries of each array.
#[derive(Clone, Copy)]
struct Offsets {
    /// Wide nodes (the new root and the fixed part's).
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
    /// Entries of [`GeometryData::instances`].
    instances: u32,
    /// The low half of a rank: past the fixed part's primitives as built.
    rank: u64,
}

/// The lane of the new root that holds the moving part.
const MOVING_LANE: usize = 1;

impl Rootstock {
    /// `fixed` under a new root (see the module docs).
    pub fn new(fixed: Bvh) -> Rootstock {
        static STOCKS: AtomicU64 = AtomicU64::new(1);
        let mut base = fixed;
        let mut root = EMPTY;
        if let Some(fixed_root) = base.wide.first() {
            set_lane(&mut root, 0, node_bounds(fixed_root), 1);
        }
        let below = Offsets {
            node: 1,
            tri4: 0,
            sphere4: 0,
            cone4: 0,
            bounded: 0,
            normals: 0,
            points_2d: 0,
            instances: 0,
            rank: 0,
        };
        let nodes = std::mem::take(&mut base.wide);
        base.wide = std::iter::once(root)
            .chain(nodes.iter().map(|n| moved_node(n, below)))
            .collect();
        base.depth += 1;
        let rank = base
            .ranks
            .iter()
            .map(|r| (r & u64::from(u32::MAX)) + 1)
            .max()
            .unwrap_or(0);
        let id = STOCKS.fetch_add(1, Ordering::Relaxed);
        base.stock = id;
        let fb = base.bounded;
        let shape = StockShape {
            root: base.wide[0],
            nodes: base.wide.len(),
            tri4: base.tri4.len(),
            sphere4: base.sphere4.len(),
            cone4: base.cone4.len(),
            bounded: fb,
            unbounded: base.primitives[fb..].to_vec(),
            unbounded_ranks: base.ranks[fb..].to_vec(),
            points_2d: base.data.polygon_points_2d.len(),
            normals: base.data.patch_normals.len(),
            uvs: base.data.patch_uvs.len(),
            instances: base.data.instances.len(),
            depth: base.depth,
            copies: base.copies.clone(),
        };
        Rootstock {
            base: Some(base),
            shape,
            rank,
            id,
        }
    }

    /// The stock's own arrays, to be the first graft's `spare`: a user that hands
    /// each graft's tree to the next copies nothing of the fixed part, ever. Later
    /// grafts without a spare then have nothing to copy (`None`).
    pub fn lend(&mut self) -> Option<Bvh> {
        self.base.take()
    }

    /// The fixed part and `moving` as one tree (see the module docs), made in the
    /// arrays of `spare` when it is an earlier graft onto this stock or the stock's
    /// lent arrays (nothing of the fixed part copied then), else in a copy of the
    /// stock's arrays; `None` when they were lent and `spare` is not a graft onto
    /// this stock.
    pub fn graft(&self, moving: Bvh, spare: Option<Bvh>) -> Option<Bvh> {
        let base = &self.shape;
        let mut tree = match spare {
            Some(tree) if tree.stock == self.id => tree,
            _ => self.base.clone()?,
        };
        let depth = base.depth.max(moving.depth + 1);
        debug_assert!(
            depth <= MAX_QUERY_DEPTH,
            "each part at most as deep as the builder makes"
        );
        let fb = base.bounded;
        let moved = Offsets {
            node: base.nodes as u32,
            tri4: base.tri4 as u32,
            sphere4: base.sphere4 as u32,
            cone4: base.cone4 as u32,
            bounded: fb as u32,
            normals: base.normals as u32,
            points_2d: base.points_2d as u32,
            instances: base.instances as u32,
            rank: self.rank,
        };
        // Back to the fixed part's entries, then the moving part's appended (the
        // unbounded primitives after the bounded ones, the fixed part's first).
        tree.wide.truncate(base.nodes);
        tree.wide[0] = base.root;
        if let Some(root) = moving.wide.first() {
            set_lane(&mut tree.wide[0], MOVING_LANE, node_bounds(root), moved.node);
        }
        tree.wide.extend(moving.wide.iter().map(|n| moved_node(n, moved)));
        append_blocks(&mut tree.tri4, base.tri4, &moving.tri4, moved);
        append_blocks(&mut tree.sphere4, base.sphere4, &moving.sphere4, moved);
        append_blocks(&mut tree.cone4, base.cone4, &moving.cone4, moved);
        let mb = moving.bounded;
        let moved_rank = |r: &u64| r + moved.rank;
        tree.primitives.truncate(fb);
        tree.primitives
            .extend(moving.primitives[..mb].iter().map(|p| moved_primitive(p, moved)));
        tree.primitives.extend_from_slice(&base.unbounded);
        tree.primitives
            .extend(moving.primitives[mb..].iter().map(|p| moved_primitive(p, moved)));
        tree.ranks.truncate(fb);
        tree.ranks.extend(moving.ranks[..mb].iter().map(moved_rank));
        tree.ranks.extend_from_slice(&base.unbounded_ranks);
        tree.ranks.extend(moving.ranks[mb..].iter().map(moved_rank));
        tree.copies = graft_copies(base, &moving, moved);
        append_data(&mut tree.data, base, &moving.data);
        tree.bounded = fb + mb;
        tree.depth = depth;
        tree.kinds = leaf_kinds::copy_for(&tree.wide);
        Some(tree)
    }
}

/// Sets lane `lane` of `node` to the box `b` around child node `child`.
fn set_lane(node: &mut Node8, lane: usize, b: Aabb, child: u32) {
    let (min, max) = (b.min.to_array(), b.max.to_array());
    for axis in 0..3 {
        node.bounds[MIN][axis][lane] = min[axis];
        node.bounds[MAX][axis][lane] = max[axis];
    }
    node.child[lane] = child;
    node.count[lane] = 0;
}

/// Blocks of a kind back to the fixed part's `fixed` first ones, then `moving`'s
/// with their primitive indices moved.
fn append_blocks<B: Copy + BlockPrims>(blocks: &mut Vec<B>, fixed: usize, moving: &[B], moved: Offsets) {
    blocks.truncate(fixed);
    blocks.extend(moving.iter().map(|b| {
        let mut b = *b;
        for p in b.prims_mut() {
            *p = moved_prim(*p, moved);
        }
        b
    }));
}

/// The primitive indices of a leaf block's lanes.
trait BlockPrims {
    fn prims_mut(&mut self) -> &mut [u32];
}

impl BlockPrims for Tri4 {
    fn prims_mut(&mut self) -> &mut [u32] {
        &mut self.prim
    }
}

impl BlockPrims for Sphere4 {
    fn prims_mut(&mut self) -> &mut [u32] {
        &mut self.prim
    }
}

impl BlockPrims for Cone4 {
    fn prims_mut(&mut self) -> &mut [u32] {
        &mut self.prim
    }
}

/// The box around every lane of `node`.
fn node_bounds(node: &Node8) -> Aabb {
    node.used_lanes()
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
        Shape::Instance(i) => *i += moved.instances,
        _ => {}
    }
    p
}

/// The geometry arrays back to the fixed part's (`fixed` counts them), then
/// `moving`'s after them (texture coordinates, kept parallel to the normals, filled
/// with zeros for a part without them).
fn append_data(data: &mut GeometryData, fixed: &StockShape, moving: &GeometryData) {
    data.polygon_points_2d.truncate(fixed.points_2d);
    data.polygon_points_2d
        .extend_from_slice(&moving.polygon_points_2d);
    data.patch_normals.truncate(fixed.normals);
    data.patch_normals.extend_from_slice(&moving.patch_normals);
    data.patch_uvs.truncate(fixed.uvs);
    if !(fixed.uvs == 0 && moving.patch_uvs.is_empty()) {
        data.patch_uvs.resize(fixed.normals, [0.0; 2]);
        data.patch_uvs.extend_from_slice(&moving.patch_uvs);
        data.patch_uvs.resize(data.patch_normals.len(), [0.0; 2]);
    }
    data.instances.truncate(fixed.instances);
    data.instances.extend_from_slice(&moving.instances);
}

/// The split cones' bookkeeping of the grafted tree: `None` when neither part has
/// split cones.
fn graft_copies(fixed: &StockShape, moving: &Bvh, moved: Offsets) -> Option<Copies> {
    if fixed.copies.is_none() && moving.copies.is_none() {
        return None;
    }
    let whole = Piece { index: 0, of: 1 };
    let part = |copies: &Option<Copies>, bounded: usize, base: u32| -> (Vec<u32>, Vec<Piece>, usize) {
        match copies {
            Some(c) => (
                c.canonical.iter().map(|&i| i + base).collect(),
                c.piece.clone(),
                c.distinct,
            ),
            None => (
                (0..bounded as u32).map(|i| i + base).collect(),
                vec![whole; bounded],
                bounded,
            ),
        }
    };
    let (mut canonical, mut piece, fixed_distinct) = part(&fixed.copies, fixed.bounded, 0);
    let (c, p, moving_distinct) = part(&moving.copies, moving.bounded, moved.bounded);
    canonical.extend(c);
    piece.extend(p);
    Some(Copies {
        canonical,
        piece,
        distinct: fixed_distinct + moving_distinct,
    })
}
