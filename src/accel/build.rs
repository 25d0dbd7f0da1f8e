//! Binned SAH construction of the BVH (Wald 2007, "On fast construction of SAH-based
//! bounding volume hierarchies"), producing the flat node array directly.

use super::node::BvhNode;
use crate::math::{Aabb, Vec3};

/// Bins per axis for the SAH sweep.
const BINS: usize = 16;
/// Relative cost of one traversal step against one primitive test (or one test of a
/// block of [`BLOCK`] packable primitives).
const TRAVERSAL_COST: f32 = 1.0;
/// Packable primitives (triangles) are tested this many at a time, so a leaf of them
/// costs one test per started block of this size rather than one per primitive.
pub const BLOCK: u32 = 4;
/// Leaves never exceed this many primitives unless their centroids coincide.
pub const MAX_LEAF: usize = 8;
/// Past this depth the builder splits at the object median, which bounds the depth
/// by about `MAX_SAH_DEPTH + log2(n)` and so keeps traversal stacks small.
const MAX_SAH_DEPTH: u32 = 32;

/// Output of the builder: nodes (root at 0) and the primitive order of the leaves.
pub struct Built {
    /// Flattened nodes.
    pub nodes: Vec<BvhNode>,
    /// `order[i]` is the input index of the i-th primitive in leaf order.
    pub order: Vec<u32>,
    /// Depth of the deepest leaf (root = 1).
    pub depth: u32,
}

struct Item {
    bounds: Aabb,
    centroid: Vec3,
    index: u32,
    packable: bool,
}

/// SAH cost of intersecting a leaf of `n` primitives of which `unpackable` cannot
/// share a block: a leaf of packable primitives alone is tested a block at a time.
#[inline]
pub fn leaf_cost(n: u32, unpackable: u32) -> f32 {
    if unpackable == 0 {
        n.div_ceil(BLOCK) as f32
    } else {
        n as f32
    }
}

/// Builds a BVH over `bounds` (one box per primitive); `packable[i]` tells whether
/// primitive `i` can be tested in a block of [`BLOCK`] with others of its kind, which
/// the SAH then counts as one test per block.
pub fn build(bounds: &[Aabb], packable: &[bool]) -> Built {
    debug_assert_eq!(bounds.len(), packable.len());
    let mut items: Vec<Item> = bounds
        .iter()
        .zip(packable)
        .enumerate()
        .map(|(i, (b, &packable))| Item {
            bounds: *b,
            centroid: b.centroid(),
            index: i as u32,
            packable,
        })
        .collect();
    let mut nodes = Vec::with_capacity((2 * items.len()).max(1));
    nodes.push(BvhNode::default());
    let mut depth = 1;
    if !items.is_empty() {
        subdivide(&mut items, 0, 0, 1, &mut nodes, &mut depth);
    }
    let order = items.iter().map(|it| it.index).collect();
    Built { nodes, order, depth }
}

fn set_bounds(node: &mut BvhNode, b: Aabb) {
    node.min = b.min.to_array();
    node.max = b.max.to_array();
}

/// Fills `nodes[node]` for `items` (which start at primitive offset `offset`).
fn subdivide(
    items: &mut [Item],
    offset: usize,
    node: usize,
    depth: u32,
    nodes: &mut Vec<BvhNode>,
    max_depth: &mut u32,
) {
    *max_depth = (*max_depth).max(depth);
    let bounds = items.iter().fold(Aabb::EMPTY, |b, it| b.union(it.bounds));
    let centroids = items.iter().fold(Aabb::EMPTY, |b, it| b.grow(it.centroid));
    set_bounds(&mut nodes[node], bounds);
    let n = items.len();
    let make_leaf = |nodes: &mut Vec<BvhNode>| {
        nodes[node].first = offset as u32;
        nodes[node].count = n as u32;
    };
    if n == 1 {
        return make_leaf(nodes);
    }
    let extent = centroids.extent();
    let mid = if extent.max_elem() <= 0.0 {
        // All centroids coincide: no plane separates them.
        if n <= MAX_LEAF {
            return make_leaf(nodes);
        }
        n / 2
    } else if depth >= MAX_SAH_DEPTH {
        median_split(items, extent.dominant_axis())
    } else {
        match sah_split(items, &bounds, &centroids) {
            Some(m) => m,
            None if n <= MAX_LEAF => return make_leaf(nodes),
            None => median_split(items, extent.dominant_axis()),
        }
    };
    let left = nodes.len();
    nodes.push(BvhNode::default());
    nodes.push(BvhNode::default());
    nodes[node].first = left as u32;
    nodes[node].count = 0;
    let (l, r) = items.split_at_mut(mid);
    subdivide(l, offset, left, depth + 1, nodes, max_depth);
    subdivide(r, offset + mid, left + 1, depth + 1, nodes, max_depth);
}

/// Partitions at the object median along `axis`; returns the split index.
fn median_split(items: &mut [Item], axis: usize) -> usize {
    let mid = items.len() / 2;
    items.select_nth_unstable_by(mid, |a, b| a.centroid[axis].total_cmp(&b.centroid[axis]));
    mid
}

#[derive(Clone, Copy)]
struct Bin {
    bounds: Aabb,
    count: u32,
    unpackable: u32,
}

/// Finds the cheapest binned SAH split over all three axes and partitions `items`
/// by it. `None` when keeping a leaf is cheaper (or no split separates anything).
fn sah_split(items: &mut [Item], bounds: &Aabb, centroids: &Aabb) -> Option<usize> {
    let n = items.len();
    let mut best: Option<(f32, usize, usize)> = None; // (cost, axis, bins left of the plane)
    for axis in 0..3 {
        let lo = centroids.min[axis];
        let ext = centroids.max[axis] - lo;
        if ext <= 0.0 {
            continue;
        }
        let scale = BINS as f32 / ext;
        let mut bins = [Bin {
            bounds: Aabb::EMPTY,
            count: 0,
            unpackable: 0,
        }; BINS];
        for it in items.iter() {
            let b = bin_index(it.centroid[axis], lo, scale);
            bins[b].bounds = bins[b].bounds.union(it.bounds);
            bins[b].count += 1;
            bins[b].unpackable += u32::from(!it.packable);
        }
        // Sweep from the right to get the right-hand areas, counts and leaf costs.
        let mut right_area = [0.0f32; BINS];
        let mut right_count = [0u32; BINS];
        let mut right_cost = [0.0f32; BINS];
        let (mut acc, mut cnt, mut unpackable) = (Aabb::EMPTY, 0, 0);
        for i in (1..BINS).rev() {
            acc = acc.union(bins[i].bounds);
            cnt += bins[i].count;
            unpackable += bins[i].unpackable;
            right_area[i] = acc.surface_area();
            right_count[i] = cnt;
            right_cost[i] = leaf_cost(cnt, unpackable);
        }
        let (mut acc, mut cnt, mut unpackable) = (Aabb::EMPTY, 0, 0);
        for i in 0..BINS - 1 {
            acc = acc.union(bins[i].bounds);
            cnt += bins[i].count;
            unpackable += bins[i].unpackable;
            if cnt == 0 || right_count[i + 1] == 0 {
                continue;
            }
            let cost =
                acc.surface_area() * leaf_cost(cnt, unpackable) + right_area[i + 1] * right_cost[i + 1];
            if best.is_none_or(|(c, _, _)| cost < c) {
                best = Some((cost, axis, i + 1));
            }
        }
    }
    let (cost, axis, split_bin) = best?;
    let area = bounds.surface_area();
    // SAH: split cost = C_trav + (A_L C_L + A_R C_R) / A versus the leaf's own cost,
    // where C is a leaf cost (one per primitive, or per block of packable ones).
    let split_cost = TRAVERSAL_COST + if area > 0.0 { cost / area } else { 0.0 };
    if n <= MAX_LEAF {
        let unpackable = items.iter().filter(|it| !it.packable).count() as u32;
        if split_cost >= leaf_cost(n as u32, unpackable) {
            return None;
        }
    }
    let lo = centroids.min[axis];
    let scale = BINS as f32 / (centroids.max[axis] - lo);
    let mid = partition(items, |it| bin_index(it.centroid[axis], lo, scale) < split_bin);
    (mid > 0 && mid < n).then_some(mid)
}

#[inline]
fn bin_index(c: f32, lo: f32, scale: f32) -> usize {
    (((c - lo) * scale) as usize).min(BINS - 1)
}

/// In-place partition; returns the number of items for which `pred` holds.
fn partition<T>(items: &mut [T], pred: impl Fn(&T) -> bool) -> usize {
    let mut i = 0;
    for j in 0..items.len() {
        if pred(&items[j]) {
            items.swap(i, j);
            i += 1;
        }
    }
    i
}
