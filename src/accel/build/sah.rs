//! Binned SAH construction of the BVH (Wald 2007, "On fast construction of SAH-based
//! bounding volume hierarchies"), producing the flat node array directly.
//!
//! Each node makes two passes over its items: one bins them on all three axes at
//! once (in fewer bins the fewer they are: `binning::bins_for`), one partitions them
//! by the chosen plane while folding the bounds and centroid bounds of both children
//! (which the children then start from); a node whose leaf no split can beat makes
//! neither. On several threads, subtrees over [`PARALLEL_ITEMS`] items and over
//! [`JOINS_PER_THREAD`] per thread are built on two threads by `rayon::join`; the right
//! one goes into a vector of its own and is spliced in after the left one, so the
//! nodes are numbered exactly as the sequential depth-first build numbers them and
//! the result does not depend on the thread count. Nodes over [`PASS_PER_JOIN`]
//! times that many items make their two passes in parallel chunks (`parallel`), with
//! the serial passes' results.

use super::binning::{bins_for, Binner, Bins, Box4, Item, BINS};
use super::node::BvhNode;
use super::parallel;
use crate::math::Aabb;
use crate::pages::huge_vec;
use rayon::prelude::*;

/// Relative cost of one traversal step against one primitive test (or one test of a
/// block of packable primitives).
pub const TRAVERSAL_COST: f32 = 1.0;
/// Triangles are tested this many at a time (two blocks of four in one eight-lane
/// test), so a leaf of them costs one test per started group of this size.
pub const TRIANGLES_PER_TEST: u32 = 8;
/// Spheres are tested this many at a time (one block of four).
pub const SPHERES_PER_TEST: u32 = 4;
/// Cones are tested this many at a time (one block of four).
pub const CONES_PER_TEST: u32 = 4;
/// Leaves never exceed this many primitives unless their centroids coincide.
pub const MAX_LEAF: usize = 8;
/// Past this depth the builder splits at the object median, which bounds the depth
/// by about `MAX_SAH_DEPTH + log2(n)` and so keeps traversal stacks small.
const MAX_SAH_DEPTH: u32 = 32;
/// The deepest a tree can be (root = 1): past [`MAX_SAH_DEPTH`] every split halves
/// its primitives (fewer than 2^32) until one is left.
pub const MAX_TREE_DEPTH: u32 = MAX_SAH_DEPTH + u32::BITS + 1;
/// The deepest a queried tree can be: one the builder made, or two of them under
/// the new root of a graft (`accel::graft`). Fixed-size traversal stacks are sized
/// from it.
pub const MAX_QUERY_DEPTH: u32 = MAX_TREE_DEPTH + 1;
/// Subtrees over this many primitives are split between threads, on more than one
/// thread (see [`JOINS_PER_THREAD`]).
pub const PARALLEL_ITEMS: usize = 4096;
/// Subtrees are split between threads only down to this many per thread (of about
/// equal size): enough for the threads to balance their work, few enough that
/// the right subtrees' nodes, each built in a vector of its own and copied into its
/// parent's, are not copied once per level of the tree.
pub const JOINS_PER_THREAD: usize = 8;
/// Nodes over this many times [`PARALLEL_ITEMS`] primitives, and over the share of
/// one thread of all of them, bin and partition them on several threads: the top
/// levels, where `rayon::join` has not yet given every thread a subtree of its own.
pub const PASS_PER_JOIN: usize = 16;
/// The chunked partition (which gathers into a scratch buffer, then copies back) runs
/// only with at least this many threads: on two, the root's took longer than the
/// serial one (mount size 9: build 205 → 236 ms, medians of 3), while the chunked
/// binning alone does not add work.
pub const PARTITION_THREADS: usize = 4;

/// Output of the builder: nodes (root at 0) and the primitive order of the leaves.
pub struct Built {
    /// Flattened nodes.
    pub nodes: Vec<BvhNode>,
    /// `order[i]` is the input index of the i-th primitive in leaf order.
    pub order: Vec<u32>,
    /// Depth of the deepest leaf (root = 1).
    pub depth: u32,
}

/// The kind of block a primitive can share with others of its kind, the blocks then
/// tested several lanes at once.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[repr(u32)]
pub enum Pack {
    /// Tested on its own.
    Alone = 0,
    /// In a block of triangles.
    Triangle = 1,
    /// In a block of spheres.
    Sphere = 2,
    /// In a block of cones.
    Cone = 3,
}

/// The kinds of block found among a set of primitives, as bits (bit `k` for the
/// [`Pack`] numbered `k`): all the SAH needs to know of them, since a leaf's cost
/// depends only on whether its primitives are all of one packable kind
/// ([`leaf_cost`]). A set of bits rather than counts per kind: one `or` per item
/// binned, where three counts took a match and three additions (the builder ran
/// 10 % more instructions so).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct Packs(u32);

impl Packs {
    /// The kind of one primitive of kind `pack`.
    #[inline(always)]
    pub fn one(pack: Pack) -> Packs {
        Packs::of_bits(pack as u32)
    }

    /// The kind of one primitive whose [`Pack`] has the number `pack`.
    #[inline(always)]
    pub fn of_bits(pack: u32) -> Packs {
        Packs(1 << (pack & 3))
    }

    /// The kinds among primitives of kinds `packs`.
    pub fn of(packs: impl IntoIterator<Item = Pack>) -> Packs {
        let mut all = Packs::default();
        for pack in packs {
            all.add(Packs::one(pack));
        }
        all
    }

    /// `Some(self)` when it is exactly one kind.
    pub fn uniform(self) -> Option<Packs> {
        (self.0.count_ones() == 1).then_some(self)
    }

    /// Adds `other`'s kinds.
    #[inline(always)]
    pub fn add(&mut self, other: Packs) {
        self.0 |= other.0;
    }
}

/// SAH cost of intersecting a leaf of `n` primitives of the kinds `packs`: a leaf
/// made only of triangles costs one test per [`TRIANGLES_PER_TEST`], one made only of
/// spheres or only of cones one per [`SPHERES_PER_TEST`] or [`CONES_PER_TEST`], any
/// other leaf one per primitive (nothing for an empty one).
#[inline]
pub fn leaf_cost(n: u32, packs: Packs) -> f32 {
    const TRIANGLES: Packs = Packs(1 << Pack::Triangle as u32);
    const SPHERES: Packs = Packs(1 << Pack::Sphere as u32);
    const CONES: Packs = Packs(1 << Pack::Cone as u32);
    match packs {
        TRIANGLES => n.div_ceil(TRIANGLES_PER_TEST) as f32,
        SPHERES => n.div_ceil(SPHERES_PER_TEST) as f32,
        CONES => n.div_ceil(CONES_PER_TEST) as f32,
        _ => n as f32,
    }
}

/// Builds a BVH over the primitives `i` in `0..packs.len()`, whose boxes are
/// `bounds(i)` (computed as the builder's records are made, with no array of boxes
/// in between); `packs[i]` tells in which kind of block primitive `i` can be tested
/// with others of its kind, which the SAH then counts as one test per block (see
/// [`leaf_cost`]).
pub fn build(bounds: impl Fn(usize) -> Aabb + Sync, packs: &[Pack]) -> Built {
    let uniform = Packs::of(packs.iter().copied()).uniform();
    build_with_kinds(bounds, packs, PARALLEL_ITEMS, uniform)
}

/// [`build`] over the boxes `bounds`, handing subtrees over `parallel_items`
/// primitives (and over [`JOINS_PER_THREAD`] per thread) to `rayon::join` and
/// binning and partitioning nodes over [`PASS_PER_JOIN`] times that many in parallel
/// chunks (`usize::MAX`: all on the calling thread), for the tests: the result is
/// the same for any value, and any number of threads.
#[cfg(test)]
pub fn build_with(bounds: &[Aabb], packs: &[Pack], parallel_items: usize) -> Built {
    assert_eq!(bounds.len(), packs.len(), "one kind of block per box");
    let uniform = Packs::of(packs.iter().copied()).uniform();
    build_with_kinds(|i| bounds[i], packs, parallel_items, uniform)
}

/// [`build`] with subtrees handed to other threads as `build_with` (the tests')
/// hands them, where `uniform` is the one kind of every primitive (then the bins do
/// not track kinds), or `None` to track them whatever the primitives: the same tree
/// either way.
pub fn build_with_kinds(
    bounds: impl Fn(usize) -> Aabb + Sync,
    packs: &[Pack],
    parallel_items: usize,
    uniform: Option<Packs>,
) -> Built {
    debug_assert!(uniform.is_none_or(|u| packs.iter().all(|&p| Packs::one(p) == u)));
    let mut items: Vec<Item> = huge_vec(packs.len());
    packs
        .par_iter()
        .enumerate()
        .map(|(i, &pack)| Item::new(&bounds(i), i as u32, pack))
        .collect_into_vec(&mut items);
    let mut nodes = huge_vec((2 * items.len()).max(1));
    nodes.push(BvhNode::default());
    let mut depth = 1;
    let parallel_items = parallel_items.max(2 * MAX_LEAF);
    // Below one thread's share the subtrees already keep every thread busy, and the
    // chunked passes would only add work (on one thread, everywhere).
    let threads = rayon::current_num_threads();
    let share = items.len() / threads + 1;
    let pass_items = parallel_items.saturating_mul(PASS_PER_JOIN).max(share);
    let join_items = match threads {
        1 => usize::MAX,
        _ => parallel_items.max(items.len() / (threads * JOINS_PER_THREAD)),
    };
    if !items.is_empty() {
        let (b, c) = if items.len() >= pass_items {
            parallel::bounds_of(&items)
        } else {
            Box4::of(&items)
        };
        // Where the chunked partitions gather their results.
        let mut scratch = if items.len() >= pass_items && threads >= PARTITION_THREADS {
            items.par_iter().copied().collect()
        } else {
            Vec::new()
        };
        let mut out = Out {
            nodes: &mut nodes,
            depth: &mut depth,
            bins: &mut Bins::new(uniform),
            parallel_items: join_items,
            pass_items,
        };
        out.subdivide(
            &mut items,
            &mut scratch,
            Span {
                offset: 0,
                node: 0,
                depth: 1,
                bounds: b,
                centroids: c,
            },
        );
    }
    let order = items.iter().map(Item::index).collect();
    debug_assert!(depth <= MAX_TREE_DEPTH);
    Built { nodes, order, depth }
}

/// A node to fill: where its items start, its index, depth, bounds and centroid bounds.
struct Span {
    offset: usize,
    node: usize,
    depth: u32,
    bounds: Box4,
    centroids: Box4,
}

/// Where one thread writes: the node vector, its deepest leaf, its scratch bins;
/// and the node sizes from which subtrees go to `rayon::join` and from which passes
/// run in parallel chunks.
struct Out<'a> {
    nodes: &'a mut Vec<BvhNode>,
    depth: &'a mut u32,
    bins: &'a mut Bins,
    parallel_items: usize,
    pass_items: usize,
}

impl Out<'_> {
    /// Fills `nodes[s.node]` for `items`, and its subtree. `scratch` is as long as
    /// `items` where the chunked partition may run (see [`PARTITION_THREADS`]), else
    /// empty.
    fn subdivide(&mut self, items: &mut [Item], scratch: &mut [Item], s: Span) {
        *self.depth = (*self.depth).max(s.depth);
        let b = s.bounds.aabb();
        let node = &mut self.nodes[s.node];
        node.min = b.min.to_array();
        node.max = b.max.to_array();
        node.first = s.offset as u32;
        node.count = items.len() as u32;
        let n = items.len();
        if n == 1 {
            return;
        }
        let cb = s.centroids.aabb();
        let extent = cb.extent();
        let (mid, children) = if extent.max_elem() <= 0.0 {
            // All centroids coincide: no plane separates them.
            if n <= MAX_LEAF {
                return;
            }
            (n / 2, None)
        } else if s.depth >= MAX_SAH_DEPTH {
            (median_split(items, extent.dominant_axis()), None)
        } else {
            match self.sah_split(items, scratch, &s) {
                Split::Plane(mid, l, r) => (mid, Some((l, r))),
                Split::Leaf if n <= MAX_LEAF => return,
                Split::Leaf => (median_split(items, extent.dominant_axis()), None),
            }
        };
        let (l, r) = items.split_at_mut(mid);
        let (l_scratch, r_scratch) = match scratch.is_empty() {
            true => (&mut [][..], &mut [][..]),
            false => scratch.split_at_mut(mid),
        };
        let ((lb, lc), (rb, rc)) = children.unwrap_or_else(|| (Box4::of(l), Box4::of(r)));
        let left = self.nodes.len();
        self.nodes.push(BvhNode::default());
        self.nodes.push(BvhNode::default());
        self.nodes[s.node].first = left as u32;
        self.nodes[s.node].count = 0;
        let depth = s.depth + 1;
        let (lo, ro) = (s.offset, s.offset + mid);
        let ls = Span {
            offset: lo,
            node: left,
            depth,
            bounds: lb,
            centroids: lc,
        };
        if n <= self.parallel_items {
            self.subdivide(l, l_scratch, ls);
            let rs = Span {
                offset: ro,
                node: left + 1,
                depth,
                bounds: rb,
                centroids: rc,
            };
            self.subdivide(r, r_scratch, rs);
            return;
        }
        // The right subtree into its own vector (its root at 0), then spliced in.
        let (parallel_items, pass_items) = (self.parallel_items, self.pass_items);
        let mut bins = self.bins.like();
        let (_, (sub, sub_depth)) = rayon::join(
            || self.subdivide(l, l_scratch, ls),
            || {
                let (mut nodes, mut deepest) = (huge_vec(2 * r.len()), 0);
                nodes.push(BvhNode::default());
                let mut out = Out {
                    nodes: &mut nodes,
                    depth: &mut deepest,
                    bins: &mut bins,
                    parallel_items,
                    pass_items,
                };
                out.subdivide(
                    r,
                    r_scratch,
                    Span {
                        offset: ro,
                        node: 0,
                        depth,
                        bounds: rb,
                        centroids: rc,
                    },
                );
                (nodes, deepest)
            },
        );
        *self.depth = (*self.depth).max(sub_depth);
        // Local node k >= 1 lands at base + k - 1; local 0 is node `left + 1`.
        let base = self.nodes.len() as u32;
        let relocate = |mut nd: BvhNode| {
            if nd.count == 0 {
                nd.first = nd.first - 1 + base;
            }
            nd
        };
        self.nodes[left + 1] = relocate(sub[0]);
        self.nodes.extend(sub[1..].iter().map(|&nd| relocate(nd)));
    }

    /// Finds the cheapest binned SAH split over all three axes and partitions `items`
    /// by it, returning the children's bounds and centroid bounds too. `Leaf` when
    /// keeping a leaf is cheaper or no split separates anything.
    fn sah_split(&mut self, items: &mut [Item], scratch: &mut [Item], s: &Span) -> Split {
        let n = items.len();
        if n <= MAX_LEAF && leaf_wins(items, &s.bounds) {
            return Split::Leaf;
        }
        let binner = Binner::new(&s.centroids, bins_for(n));
        if n == 2 {
            return split_pair(items, s, &binner);
        }
        let bins = &mut *self.bins;
        let chunked = n >= self.pass_items;
        if chunked {
            parallel::fill_bins(bins, items, &binner);
        } else {
            bins.fill(items, &binner);
        }
        let cb = s.centroids.aabb();
        let mut best: Option<(f32, usize, usize)> = None; // (cost, axis, bins left of the plane)
        for axis in 0..3 {
            let mut used = [0usize; BINS];
            let mut k = 0;
            for i in 0..binner.count {
                used[k] = i;
                k += (bins.count[axis][i] > 0) as usize;
            }
            let used = &used[..k];
            if !flat(&cb, axis) {
                if let Some((cost, split)) = sweep(bins, axis, used) {
                    if best.is_none_or(|(c, _, _)| cost < c) {
                        best = Some((cost, axis, split));
                    }
                }
            }
            for &i in used {
                bins.clear(axis, i);
            }
        }
        let Some((cost, axis, split_bin)) = best else {
            return Split::Leaf;
        };
        let area = s.bounds.aabb().surface_area();
        // SAH: split cost = C_trav + (A_L C_L + A_R C_R) / A versus the leaf's own
        // cost, where C is a leaf cost (one per primitive, or per block of packable ones).
        let split_cost = TRAVERSAL_COST + if area > 0.0 { cost / area } else { 0.0 };
        if n <= MAX_LEAF && split_cost >= leaf_cost_of(items) {
            return Split::Leaf;
        }
        let (mid, l, r) = if chunked && scratch.len() == n {
            parallel::partition(items, scratch, &binner, axis, split_bin)
        } else {
            partition(items, &binner, axis, split_bin)
        };
        if mid > 0 && mid < n {
            Split::Plane(mid, l, r)
        } else {
            Split::Leaf
        }
    }
}

/// Outcome of [`Out::sah_split`]: the split index and both children's (bounds,
/// centroid bounds), or no split.
enum Split {
    Plane(usize, (Box4, Box4), (Box4, Box4)),
    Leaf,
}

/// Do the centroids span nothing along `axis`? A plain `<=`, so a NaN extent counts
/// as an axis to bin (all into bin 0, giving no plane).
#[inline]
fn flat(cb: &Aabb, axis: usize) -> bool {
    cb.max[axis] - cb.min[axis] <= 0.0
}

/// [`Out::sah_split`] for two items, without the bins: every axis that bins them
/// apart costs `A_0 + A_1`, so the first such axis wins; same result, same order.
fn split_pair(items: &mut [Item], s: &Span, binner: &Binner) -> Split {
    let cb = s.centroids.aabb();
    let (b0, b1) = (binner.bins(items[0].centroid()), binner.bins(items[1].centroid()));
    let apart = |a: usize| !flat(&cb, a) && b0[a] != b1[a];
    let Some(axis) = (0..3).find(|&a| apart(a)) else {
        return Split::Leaf;
    };
    let area = |it: &[Item]| Box4::of(it).0.aabb().surface_area();
    let (lo, hi) = if b0[axis] < b1[axis] { (0, 1) } else { (1, 0) };
    // A single primitive costs 1 as a leaf, packable or not.
    let cost = area(&items[lo..lo + 1]) + area(&items[hi..hi + 1]);
    let area = s.bounds.aabb().surface_area();
    let split_cost = TRAVERSAL_COST + if area > 0.0 { cost / area } else { 0.0 };
    if split_cost >= leaf_cost_of(items) {
        return Split::Leaf;
    }
    if lo == 1 {
        items.swap(0, 1);
    }
    Split::Plane(1, Box4::of(&items[..1]), Box4::of(&items[1..]))
}

/// The cheapest plane between two of the non-empty bins `used` of `axis`, as (cost,
/// number of bins left of the plane). Planes between empty bins are skipped: they
/// cost exactly what the plane after the last non-empty bin before them costs.
fn sweep(bins: &Bins, axis: usize, used: &[usize]) -> Option<(f32, usize)> {
    let k = used.len();
    if k < 2 {
        return None;
    }
    // Sweep from the right to get the right-hand areas and leaf costs.
    let mut right_area = [0.0f32; BINS];
    let mut right_cost = [0.0f32; BINS];
    let (mut acc, mut cnt, mut packs) = (Box4::EMPTY, 0, Packs::default());
    for j in (1..k).rev() {
        acc.add_box(&bins.bounds[axis][used[j]]);
        cnt += bins.count[axis][used[j]];
        packs.add(bins.packs(axis, used[j]));
        right_area[j] = acc.surface_area();
        right_cost[j] = leaf_cost(cnt, packs);
    }
    let mut best: Option<(f32, usize)> = None;
    let (mut acc, mut cnt, mut packs) = (Box4::EMPTY, 0, Packs::default());
    for j in 0..k - 1 {
        acc.add_box(&bins.bounds[axis][used[j]]);
        cnt += bins.count[axis][used[j]];
        packs.add(bins.packs(axis, used[j]));
        let cost = acc.surface_area() * leaf_cost(cnt, packs) + right_area[j + 1] * right_cost[j + 1];
        if best.is_none_or(|(c, _)| cost < c) {
            best = Some((cost, used[j] + 1));
        }
    }
    best
}

/// In-place partition by `bin < split_bin` on `axis`, keeping the items that go left
/// in their order; returns their number and the (bounds, centroid bounds) of both
/// sides.
fn partition(
    items: &mut [Item],
    binner: &Binner,
    axis: usize,
    split_bin: usize,
) -> (usize, (Box4, Box4), (Box4, Box4)) {
    let (mut lb, mut lc, mut rb, mut rc) = (Box4::EMPTY, Box4::EMPTY, Box4::EMPTY, Box4::EMPTY);
    let mut i = 0;
    for j in 0..items.len() {
        let it = items[j];
        let c = it.centroid();
        if (binner.bins(c)[axis] as usize) < split_bin {
            lb.add(&it);
            lc.add_point(c);
            items.swap(i, j);
            i += 1;
        } else {
            rb.add(&it);
            rc.add_point(c);
        }
    }
    (i, (lb, lc), (rb, rc))
}

/// True when `items` (a node's, whose bounds are `bounds`) are cheaper as a leaf than
/// split whatever the split: the leaf costs at most one test ([`TRAVERSAL_COST`]),
/// which any split costs before its children (`C_trav + (A_L C_L + A_R C_R) / A`
/// with non-negative areas, or `C_trav` alone when the node has no area). Then the
/// bins need not be filled: [`Out::sah_split`] would find a leaf. A node's children
/// lie inside it, so with a finite area their areas are finite too and the cost is
/// never NaN (which would not compare as more).
fn leaf_wins(items: &[Item], bounds: &Box4) -> bool {
    leaf_cost_of(items) <= TRAVERSAL_COST && bounds.surface_area().is_finite()
}

/// [`leaf_cost`] of `items` as one leaf.
fn leaf_cost_of(items: &[Item]) -> f32 {
    let mut packs = Packs::default();
    for it in items {
        packs.add(it.packs());
    }
    leaf_cost(items.len() as u32, packs)
}

/// Partitions at the object median along `axis`; returns the split index.
fn median_split(items: &mut [Item], axis: usize) -> usize {
    let mid = items.len() / 2;
    items.select_nth_unstable_by(mid, |a, b| a.centroid_on(axis).total_cmp(&b.centroid_on(axis)));
    mid
}
