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

/// Depth limit of the binary tree (the builder stays well below it).
const MAX_DEPTH: usize = 64;

/// Shape statistics of a built BVH (for `info --bvh` and benchmarks).
#[derive(Clone, Debug, PartialEq, serde::Serialize)]
pub struct BvhStats {
    /// Number of nodes.
    pub nodes: usize,
    /// Number of leaves.
    pub leaves: usize,
    /// Depth of the deepest leaf (root = 1).
    pub depth: u32,
    /// Smallest leaf size.
    pub min_leaf: u32,
    /// Largest leaf size.
    pub max_leaf: u32,
    /// Mean leaf size.
    pub mean_leaf: f64,
    /// SAH cost: expected node visits plus primitive tests for a random ray that hits
    /// the root box (traversal and intersection weighted 1 each; a leaf of triangles
    /// counts one test per eight, one of spheres or of cones per four, as they are
    /// intersected; see `sah::leaf_cost`).
    pub sah_cost: f64,
    /// Bounded primitives in the tree.
    pub primitives: usize,
    /// The 8-wide tree the queries traverse (collapsed from the binary one above).
    pub wide: WideStats,
    /// Leaf entries: the bounded primitives, plus one per extra piece of a split cone
    /// (`accel::build::split`).
    pub references: usize,
    /// Unbounded primitives tested beside it.
    pub unbounded: usize,
}

/// Shape statistics of the 8-wide tree the queries traverse.
#[derive(Clone, Debug, Default, PartialEq, serde::Serialize)]
pub struct WideStats {
    /// Number of wide nodes.
    pub nodes: usize,
    /// Lanes holding leaves (a leaf lane holds up to eight primitives, in blocks).
    pub leaf_lanes: usize,
    /// Depth of the deepest wide node (root = 1).
    pub depth: u32,
    /// Occupied lanes per node, on average (of eight).
    pub mean_lanes: f64,
    /// Wide nodes a ray that enters the root box visits, in expectation for random
    /// rays: each node's box's surface area over the root's, summed.
    pub expected_visits: f64,
}

impl Bvh {
    /// Reference query: tests every primitive (for tests and validation only).
    pub fn closest_hit_linear(&self, ray: &Ray, t_max: f32) -> Option<(Hit, u32)> {
        let mut best = None;
        let mut t_best = t_max;
        for (i, p) in self.primitives.iter().enumerate() {
            if let Some(h) = p.intersect(ray, t_best, &self.data) {
                t_best = h.t;
                best = Some((h, i as u32));
            }
        }
        best
    }

    /// The wide tree's [`WideStats`] (all zero for a tree without bounded primitives).
    fn wide_stats(&self) -> WideStats {
        if self.bounded == 0 {
            return WideStats::default();
        }
        let node_box = |n: &Node8| {
            (0..WIDTH)
                .filter(|&lane| n.child[lane] != u32::MAX)
                .map(|lane| n.lane_bounds(lane))
                .reduce(Aabb::union)
                .expect("a wide node has a lane")
        };
        let root_area = node_box(&self.wide[0]).surface_area().max(f32::MIN_POSITIVE) as f64;
        let mut s = WideStats {
            nodes: self.wide.len(),
            ..WideStats::default()
        };
        let mut lanes = 0;
        let mut stack = vec![(0u32, 1u32)];
        while let Some((index, depth)) = stack.pop() {
            let node = &self.wide[index as usize];
            s.depth = s.depth.max(depth);
            s.expected_visits += node_box(node).surface_area() as f64 / root_area;
            for lane in (0..WIDTH).filter(|&lane| node.child[lane] != u32::MAX) {
                lanes += 1;
                if node.count[lane] > 0 {
                    s.leaf_lanes += 1;
                } else {
                    stack.push((node.child[lane], depth + 1));
                }
            }
        }
        s.mean_lanes = lanes as f64 / s.nodes as f64;
        s
    }

    /// Checks the structural invariants, of the binary tree and of the wide one the
    /// queries use: every bounded primitive in exactly one leaf (of each; a split
    /// cone once per piece), every child box inside its parent (binary), every
    /// primitive box (or piece box) inside its leaf or leaf lane, depth within the
    /// traversal stack. Returns a description of the first violation.
    pub fn validate(&self) -> Result<(), String> {
        if self.depth as usize >= MAX_DEPTH {
            return Err(format!("depth {} exceeds the stack", self.depth));
        }
        let mut seen = vec![0u8; self.bounded];
        if self.bounded > 0 {
            self.validate_node(0, &mut seen)?;
        }
        if let Some(i) = seen.iter().position(|&c| c != 1) {
            return Err(format!("primitive {i} is reached {} times", seen[i]));
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

    /// The box leaf-order entry `index` is filed under: its primitive's, or that of
    /// the piece of a split cone it stands for.
    fn entry_bounds(&self, index: usize) -> Option<Aabb> {
        match self.split_cone(index) {
            Some((cone, piece)) => Some(piece.bounds_of(cone)),
            None => self.primitives[index].bounds(&self.data),
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

    /// The wide tree's part of [`Bvh::validate`]: counts in `seen` the leaf lanes
    /// holding each primitive (directly or through its block), checking its box lies
    /// in the lane's.
    fn validate_wide(&self, seen: &mut [u8]) -> Result<(), String> {
        for (n, node) in self.wide.iter().enumerate() {
            for lane in 0..WIDTH {
                let (first, count) = (node.child[lane] as usize, node.count[lane] as usize);
                if count == 0 {
                    continue;
                }
                let prims = if let Some(b) = marked(&self.tri4, first, count, TRI4_LEAF) {
                    block_prims(b)
                } else if let Some(b) = marked(&self.sphere4, first, count, SPHERE4_LEAF) {
                    block_prims(b)
                } else if let Some(b) = marked(&self.cone4, first, count, CONE4_LEAF) {
                    block_prims(b)
                } else {
                    (first..first + count).map(|i| self.canonical(i)).collect()
                };
                let b = node.lane_bounds(lane);
                for p in prims.into_iter().filter(|&p| p != u32::MAX).map(|p| p as usize) {
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
        Ok(())
    }

    fn validate_node(&self, index: usize, seen: &mut [u8]) -> Result<(), String> {
        let node = &self.nodes[index];
        let b = node.bounds();
        if node.is_leaf() {
            let first = node.first as usize;
            let leaf = first..first + node.count as usize;
            for (i, count) in seen[leaf].iter_mut().enumerate() {
                let pb = self
                    .entry_bounds(first + i)
                    .ok_or("unbounded primitive in a leaf")?;
                if !b.contains(&pb) {
                    return Err(format!("primitive {} sticks out of leaf {index}", first + i));
                }
                *count = count.saturating_add(1);
            }
            return Ok(());
        }
        for c in [node.first as usize, node.first as usize + 1] {
            if c <= index || c >= self.nodes.len() {
                return Err(format!("node {index} has a bad child {c}"));
            }
            if !b.contains(&self.nodes[c].bounds()) {
                return Err(format!("child {c} sticks out of node {index}"));
            }
            self.validate_node(c, seen)?;
        }
        Ok(())
    }

    /// Node counts, depth, leaf sizes and SAH cost.
    pub fn stats(&self) -> BvhStats {
        let mut s = BvhStats {
            nodes: if self.bounded == 0 { 0 } else { self.nodes.len() },
            leaves: 0,
            depth: if self.bounded == 0 { 0 } else { self.depth },
            min_leaf: u32::MAX,
            max_leaf: 0,
            mean_leaf: 0.0,
            sah_cost: 0.0,
            primitives: self.copies.as_ref().map_or(self.bounded, |c| c.distinct),
            wide: self.wide_stats(),
            references: self.bounded,
            unbounded: self.primitives.len() - self.bounded,
        };
        if self.bounded == 0 {
            s.min_leaf = 0;
            return s;
        }
        let root_area = self.nodes[0].bounds().surface_area().max(f32::MIN_POSITIVE) as f64;
        for n in &self.nodes {
            let rel = n.bounds().surface_area() as f64 / root_area;
            if n.is_leaf() {
                s.leaves += 1;
                s.min_leaf = s.min_leaf.min(n.count);
                s.max_leaf = s.max_leaf.max(n.count);
                let first = n.first as usize;
                let leaf = &self.primitives[first..first + n.count as usize];
                let packs = Packs::of(leaf.iter().map(pack_of));
                s.sah_cost += rel * sah::leaf_cost(n.count, packs) as f64;
            } else {
                s.sah_cost += rel;
            }
        }
        s.mean_leaf = self.bounded as f64 / s.leaves as f64;
        s
    }

    /// Bounding box of the bounded primitives, as (min, max); `None` if there are none.
    pub fn bounds(&self) -> Option<(Vec3, Vec3)> {
        (self.bounded > 0).then(|| {
            (
                Vec3::from_array(self.nodes[0].min),
                Vec3::from_array(self.nodes[0].max),
            )
        })
    }
}

/// The primitive indices of `blocks`' lanes (`u32::MAX` for unused ones).
fn block_prims<B: Block>(blocks: &[B]) -> Vec<u32> {
    blocks.iter().flat_map(|b| *b.prims()).collect()
}
