//! Checks and statistics of a built BVH: the brute-force reference query, structural
//! validation, shape statistics (with the SAH cost) and bounds.

use super::bvh::Bvh;
use crate::accel::build::sah::{self, Packs};
use crate::accel::build::split::Piece;
use crate::accel::leaf::pack::{marked, pack_of, CONE4_LEAF, SPHERE4_LEAF, TRI4_LEAF};
use crate::accel::leaf::tri4::Block;
use crate::accel::traverse::wide::{Node8, WIDTH};
use crate::geometry::Hit;
use crate::geometry::{ConeShape, Shape};
use crate::math::{Aabb, Ray, Vec3};

/// Shape statistics of a built BVH: of the 8-wide tree the queries traverse (the
/// binary tree it is collapsed from is not kept), for `info --bvh` and benchmarks.
#[derive(Clone, Debug, Default, PartialEq, serde::Serialize)]
pub struct BvhStats {
    /// Number of wide nodes.
    pub nodes: usize,
    /// Number of leaves: the lanes holding primitives (each up to 16 entries, in
    /// blocks of four where they are all triangles, spheres or cones).
    pub leaves: usize,
    /// Depth of the deepest wide node (root = 1).
    pub depth: u32,
    /// Fewest entries in a leaf.
    pub min_leaf: u32,
    /// Most entries in a leaf.
    pub max_leaf: u32,
    /// Mean entries per leaf.
    pub mean_leaf: f64,
    /// Occupied lanes per node, on average (of eight).
    pub mean_lanes: f64,
    /// Wide nodes a ray that enters the root box visits, in expectation for random
    /// rays: each node's box's surface area over the root's, summed.
    pub expected_visits: f64,
    /// SAH cost: [`BvhStats::expected_visits`] plus the expected primitive tests, each
    /// leaf's weighted by its box's area over the root's (a leaf of triangles counts
    /// one test per eight, one of spheres or of cones per four, as they are
    /// intersected; see `sah::leaf_cost`).
    pub sah_cost: f64,
    /// Bounded primitives in the tree.
    pub primitives: usize,
    /// Leaf entries: the bounded primitives, plus one per extra piece of a split cone
    /// (`accel::build::split`).
    pub references: usize,
    /// Unbounded primitives tested beside it.
    pub unbounded: usize,
}

impl Bvh {
    /// Reference query: tests every primitive (for tests and validation only), and
    /// keeps the nearest hit, of equals the one of the lowest rank (the queries' rule,
    /// written out apart from `Nearest`; a split cone's copies share a rank, so the
    /// first copy's index is kept).
    pub fn closest_hit_linear(&self, ray: &Ray, t_max: f32) -> Option<(Hit, u32)> {
        let mut best: Option<(Hit, u32)> = None;
        for (i, p) in self.primitives.iter().enumerate() {
            if let Some(h) = p.intersect(ray, t_max, &self.data) {
                let nearer = best
                    .is_none_or(|(b, j)| h.t < b.t || (h.t == b.t && self.ranks[i] < self.ranks[j as usize]));
                if nearer {
                    best = Some((h, i as u32));
                }
            }
        }
        best
    }

    /// The box around a wide node's lanes.
    fn node_box(node: &Node8) -> Aabb {
        (0..WIDTH)
            .filter(|&lane| node.child[lane] != u32::MAX)
            .map(|lane| node.lane_bounds(lane))
            .reduce(Aabb::union)
            .expect("a wide node has a lane")
    }

    /// The leaf-order entries of the leaf lane (`first`, `count`), each named by its
    /// first copy (as the queries name them; `u32::MAX` for a block's empty lanes,
    /// left out).
    fn leaf_entries(&self, first: usize, count: usize) -> Vec<u32> {
        let prims = if let Some(b) = marked(&self.tri4, first, count, TRI4_LEAF) {
            block_prims(b)
        } else if let Some(b) = marked(&self.sphere4, first, count, SPHERE4_LEAF) {
            block_prims(b)
        } else if let Some(b) = marked(&self.cone4, first, count, CONE4_LEAF) {
            block_prims(b)
        } else {
            (first..first + count).map(|i| self.canonical(i)).collect()
        };
        prims.into_iter().filter(|&p| p != u32::MAX).collect()
    }

    /// Checks the structural invariants of the wide tree the queries use: every node
    /// reached once from the root, every child box inside its parent's lane, every
    /// bounded primitive in exactly one leaf lane (a split cone once per piece), its
    /// box (or its piece's) inside the lane's, depth within the traversal stack.
    /// Returns a description of the first violation.
    pub fn validate(&self) -> Result<(), String> {
        if self.depth > sah::MAX_QUERY_DEPTH {
            return Err(format!("depth {} exceeds the stack", self.depth));
        }
        // The wide leaves' blocks name each copy by its first one: count per name.
        let mut expected = vec![0u8; self.bounded];
        for i in 0..self.bounded {
            let c = self.canonical(i) as usize;
            expected[c] = expected[c].saturating_add(1);
        }
        if let Some(copies) = &self.copies {
            // Each piece of a split cone exactly once (one bit per piece).
            let mut pieces = vec![0u64; self.bounded];
            for (i, piece) in copies.piece.iter().enumerate() {
                let first = copies.canonical[i] as usize;
                let bit = 1u64 << piece.index;
                if copies.piece[first].of != piece.of
                    || usize::from(piece.of) != usize::from(expected[first])
                    || pieces[first] & bit != 0
                {
                    return Err(format!(
                        "entry {i} is piece {} of {} among {} copies",
                        piece.index, piece.of, expected[first]
                    ));
                }
                pieces[first] |= bit;
            }
        }
        let mut seen = vec![0u8; self.bounded];
        self.validate_wide(&mut seen)?;
        match seen.iter().zip(&expected).position(|(s, e)| s != e) {
            Some(i) => Err(format!(
                "primitive {i} is in {} wide leaf lanes, not {}",
                seen[i], expected[i]
            )),
            None => Ok(()),
        }
    }

    /// The box of the entry named `index` (a first copy, as the wide tree's blocks
    /// name every copy) that a wide leaf lane with box `lane` holds: for a split cone,
    /// whichever of its pieces' boxes `lane` contains (the first if none does).
    fn lane_entry_bounds(&self, index: usize, lane: &Aabb) -> Result<Aabb, String> {
        match self.split_cone(index) {
            Some((cone, piece)) => {
                let pieces: Vec<Aabb> = Piece::all(piece.of).map(|p| p.bounds_of(cone)).collect();
                Ok(pieces
                    .iter()
                    .copied()
                    .find(|b| lane.contains(b))
                    .unwrap_or(pieces[0]))
            }
            None => self.primitives[index]
                .bounds(&self.data)
                .ok_or_else(|| "unbounded primitive in a leaf lane".to_string()),
        }
    }

    /// The cone and piece that leaf-order entry `index` stands for, if it is a piece
    /// of a split cone.
    fn split_cone(&self, index: usize) -> Option<(&ConeShape, Piece)> {
        let piece = self.copies.as_ref()?.piece[index];
        match &self.primitives[index].shape {
            Shape::Cone(cone) if piece.of > 1 => Some((cone, piece)),
            _ => None,
        }
    }

    /// The wide tree's part of [`Bvh::validate`]: walks it from the root, checking
    /// that each node is reached once, that every child node's box lies in its
    /// parent's lane, and that each leaf entry's box lies in its lane; counts in
    /// `seen` the leaf lanes holding each primitive (directly or through its block).
    fn validate_wide(&self, seen: &mut [u8]) -> Result<(), String> {
        if self.bounded == 0 {
            return Ok(());
        }
        let mut reached = vec![false; self.wide.len()];
        let mut stack = vec![0usize];
        reached[0] = true;
        while let Some(n) = stack.pop() {
            let node = &self.wide[n];
            for lane in (0..WIDTH).filter(|&lane| node.child[lane] != u32::MAX) {
                let (first, count) = (node.child[lane] as usize, node.count[lane] as usize);
                let b = node.lane_bounds(lane);
                if count == 0 {
                    if first >= self.wide.len() || reached[first] {
                        return Err(format!("lane {lane} of wide node {n} has a bad child {first}"));
                    }
                    if !b.contains(&Self::node_box(&self.wide[first])) {
                        return Err(format!("wide node {first} sticks out of lane {lane} of node {n}"));
                    }
                    reached[first] = true;
                    stack.push(first);
                    continue;
                }
                for p in self.leaf_entries(first, count).into_iter().map(|p| p as usize) {
                    let pb = self.lane_entry_bounds(p, &b)?;
                    if !b.contains(&pb) {
                        return Err(format!(
                            "primitive {p} sticks out of lane {lane} of wide node {n}"
                        ));
                    }
                    seen[p] = seen[p].saturating_add(1);
                }
            }
        }
        match reached.iter().position(|&r| !r) {
            Some(n) => Err(format!("wide node {n} is not reached from the root")),
            None => Ok(()),
        }
    }

    /// Node and leaf counts, depth, leaf sizes and SAH cost of the wide tree.
    pub fn stats(&self) -> BvhStats {
        let mut s = BvhStats {
            primitives: self.copies.as_ref().map_or(self.bounded, |c| c.distinct),
            references: self.bounded,
            unbounded: self.primitives.len() - self.bounded,
            ..BvhStats::default()
        };
        if self.bounded == 0 {
            return s;
        }
        let root_area = Self::node_box(&self.wide[0])
            .surface_area()
            .max(f32::MIN_POSITIVE) as f64;
        let area = |b: Aabb| b.surface_area() as f64 / root_area;
        let (mut lanes, mut entries) = (0, 0);
        s.nodes = self.wide.len();
        s.min_leaf = u32::MAX;
        let mut stack = vec![(0u32, 1u32)];
        while let Some((index, depth)) = stack.pop() {
            let node = &self.wide[index as usize];
            s.depth = s.depth.max(depth);
            s.expected_visits += area(Self::node_box(node));
            for lane in (0..WIDTH).filter(|&lane| node.child[lane] != u32::MAX) {
                lanes += 1;
                let (first, count) = (node.child[lane], node.count[lane] as usize);
                if count == 0 {
                    stack.push((first, depth + 1));
                    continue;
                }
                let leaf = self.leaf_entries(first as usize, count);
                let n = leaf.len() as u32;
                let packs = Packs::of(leaf.iter().map(|&p| pack_of(&self.primitives[p as usize])));
                s.sah_cost += area(node.lane_bounds(lane)) * sah::leaf_cost(n, packs) as f64;
                s.leaves += 1;
                s.min_leaf = s.min_leaf.min(n);
                s.max_leaf = s.max_leaf.max(n);
                entries += leaf.len();
            }
        }
        s.sah_cost += s.expected_visits;
        s.mean_lanes = lanes as f64 / s.nodes as f64;
        s.mean_leaf = entries as f64 / s.leaves as f64;
        s
    }

    /// Bounding box of the bounded primitives, as (min, max); `None` if there are none.
    pub fn bounds(&self) -> Option<(Vec3, Vec3)> {
        (self.bounded > 0).then(|| {
            let b = Self::node_box(&self.wide[0]);
            (b.min, b.max)
        })
    }
}

/// The primitive indices of `blocks`' lanes (`u32::MAX` for unused ones).
fn block_prims<B: Block>(blocks: &[B]) -> Vec<u32> {
    blocks.iter().flat_map(|b| *b.prims()).collect()
}
