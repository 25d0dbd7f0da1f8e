//! The binary SAH tree collapsed into 8-wide nodes at the least SAH cost.
//!
//! Which binary nodes become wide nodes, which subtrees become a wide node's children
//! and which whole subtrees become one leaf are chosen by dynamic programming over the
//! binary tree, as in Ylitie, Karras and Laine 2017 ("Efficient incoherent ray
//! traversal on GPUs through compressed wide BVHs", section 4.1): `cost(n, i)` is the
//! least SAH cost of the subtree at `n` given as at most `i` children of a wide node.
//! The primitives keep their leaf order (a subtree's are contiguous), so a merged leaf
//! is a range of them like any other.

use super::node::BvhNode;
use super::sah::{leaf_cost, Pack, Packs, TRAVERSAL_COST};
use crate::accel::traverse::wide::{Node8, EMPTY, MAX, MIN, WIDTH};
use rayon::prelude::*;

/// Most primitives in a leaf made by merging a subtree.
pub(in crate::accel) const MAX_MERGED_LEAF: u32 = 16;

/// How a binary node's subtree is given in `i` slots of a wide node.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
enum Choice {
    /// One slot: the whole subtree as one leaf.
    #[default]
    Leaf,
    /// One slot: a wide node of its own.
    Node,
    /// The left subtree in `k` slots, the right one in the rest.
    Split(u8),
    /// As in one slot fewer.
    Fewer,
}

/// Per binary node: its primitive range, kinds, and for each slot count (index
/// `i - 1`) the least cost and the choice that reaches it.
#[derive(Clone, Copy, Default)]
struct Table {
    first: u32,
    count: u32,
    packs: Packs,
    cost: [f32; WIDTH],
    choice: [Choice; WIDTH],
    /// As a wide node of its own: the slots its left subtree takes (the right one
    /// takes the others).
    split: u8,
}

/// Which subtrees are collapsed on a thread of their own.
#[derive(Clone, Copy, Debug)]
struct Joins {
    /// Binary subtrees of more nodes than this are tabulated by `rayon::join`.
    nodes: usize,
    /// Wide subtrees over this many primitives are emitted in parallel, each into a
    /// vector of its own, then spliced in.
    primitives: u32,
}

/// The subtrees [`collapse`] hands to other threads.
const JOINS: Joins = Joins {
    nodes: 2048,
    primitives: 8192,
};

/// Collapses the binary BVH `binary` (root at 0, at least one primitive, numbered as
/// `sah` numbers it: see [`table_of`]) into wide nodes (root at 0) at the least SAH
/// cost; `packs[i]` is the kind of the `i`-th primitive in leaf order. Returns the
/// nodes and the wide tree's depth. The big subtrees are collapsed on several
/// threads, into the same nodes as on one.
pub fn collapse(binary: &[BvhNode], packs: &[Pack]) -> (Vec<Node8>, u32) {
    collapse_with(binary, packs, JOINS)
}

/// [`collapse`], handing the subtrees `joins` names to other threads.
fn collapse_with(binary: &[BvhNode], packs: &[Pack], joins: Joins) -> (Vec<Node8>, u32) {
    let tree = Tree {
        binary,
        table: &tabulate(binary, packs, joins),
        joins,
    };
    let mut out = crate::pages::huge_vec(binary.len() / 4 + 1);
    let depth = tree.emit(0, &mut out);
    (out, depth)
}

/// The dynamic programme's table, one entry per binary node.
fn tabulate(binary: &[BvhNode], packs: &[Pack], joins: Joins) -> Vec<Table> {
    let mut table = crate::pages::huge_vec(binary.len());
    table.par_extend(rayon::iter::repeat_n(Table::default(), binary.len()));
    let (root, below) = table.split_at_mut(1);
    root[0] = table_of(binary, packs, joins, 0, below, 1);
    table
}

/// The table entry of binary node `n`, once those of its descendants are filled in
/// `below`, which holds the entries from index `start` on. A node's descendants are
/// numbered contiguously from its first child on, as the builder numbers them: a
/// node's two children together, then the left child's descendants, then the
/// right's.
fn table_of(
    binary: &[BvhNode],
    packs: &[Pack],
    joins: Joins,
    n: usize,
    below: &mut [Table],
    start: usize,
) -> Table {
    let node = &binary[n];
    if node.is_leaf() {
        debug_assert!(below.is_empty(), "a leaf has no descendants");
        return leaf_table(node, packs);
    }
    let left = node.first as usize;
    debug_assert_eq!(left, start, "the children come first among the descendants");
    let join = below.len() > joins.nodes;
    let (children, rest) = below.split_at_mut(2);
    let right = &binary[left + 1];
    let left_below = match right.is_leaf() {
        true => rest.len(),
        false => right.first as usize - (left + 2),
    };
    let (l_below, r_below) = rest.split_at_mut(left_below);
    let r_start = left + 2 + left_below;
    let mut left_table = || table_of(binary, packs, joins, left, l_below, left + 2);
    let mut right_table = || table_of(binary, packs, joins, left + 1, r_below, r_start);
    let (l, r) = match join {
        true => rayon::join(left_table, right_table),
        false => (left_table(), right_table()),
    };
    children[0] = l;
    children[1] = r;
    interior_table(node, &l, &r)
}

/// The table entry of leaf node `node`.
fn leaf_table(node: &BvhNode, packs: &[Pack]) -> Table {
    let range = node.first as usize..(node.first + node.count) as usize;
    let packs = Packs::of(packs[range].iter().copied());
    let leaf = node.bounds().surface_area() * leaf_cost(node.count, packs);
    Table {
        first: node.first,
        count: node.count,
        packs,
        cost: [leaf; WIDTH],
        ..Table::default()
    }
}

/// The table entry of interior node `node` whose children's entries are `l` and `r`.
fn interior_table(node: &BvhNode, l: &Table, r: &Table) -> Table {
    debug_assert_eq!(
        l.first + l.count,
        r.first,
        "a subtree's primitives are contiguous"
    );
    let area = node.bounds().surface_area();
    let mut t = Table {
        first: l.first,
        count: l.count + r.count,
        packs: l.packs,
        ..Table::default()
    };
    t.packs.add(r.packs);
    // distribute[j - 1]: both subtrees in j slots (j ≥ 2).
    let mut distribute = [(f32::INFINITY, 1u8); WIDTH];
    for j in 2..=WIDTH {
        distribute[j - 1].0 = l.cost[0] + r.cost[j - 2];
        for k in 2..j {
            let c = l.cost[k - 1] + r.cost[j - k - 1];
            if c < distribute[j - 1].0 {
                distribute[j - 1] = (c, k as u8);
            }
        }
    }
    let as_node = area * TRAVERSAL_COST + distribute[WIDTH - 1].0;
    t.split = distribute[WIDTH - 1].1;
    let as_leaf = area * leaf_cost(t.count, t.packs);
    // (With NaN costs, from degenerate boxes, any choice is valid; these are.)
    (t.cost[0], t.choice[0]) = if t.count <= MAX_MERGED_LEAF && as_leaf <= as_node {
        (as_leaf, Choice::Leaf)
    } else {
        (as_node, Choice::Node)
    };
    for i in 2..=WIDTH {
        let (c, k) = distribute[i - 1];
        (t.cost[i - 1], t.choice[i - 1]) = if c < t.cost[i - 2] {
            (c, Choice::Split(k))
        } else {
            (t.cost[i - 2], Choice::Fewer)
        };
    }
    t
}

/// The binary tree, its table, and the subtrees collapsed on threads of their own.
struct Tree<'a> {
    binary: &'a [BvhNode],
    table: &'a [Table],
    joins: Joins,
}

impl Tree<'_> {
    /// The binary nodes that subtree `n` in `slots` slots puts in a wide node's lanes.
    fn gather(&self, n: usize, slots: usize, kids: &mut Vec<usize>) {
        if self.binary[n].is_leaf() || slots == 1 {
            kids.push(n);
            return;
        }
        match self.table[n].choice[slots - 1] {
            Choice::Split(k) => {
                let left = self.binary[n].first as usize;
                self.gather(left, k as usize, kids);
                self.gather(left + 1, slots - k as usize, kids);
            }
            _ => self.gather(n, slots - 1, kids),
        }
    }

    /// True when binary node `k` in one slot is a wide node of its own.
    fn is_node(&self, k: usize) -> bool {
        !self.binary[k].is_leaf() && self.table[k].choice[0] != Choice::Leaf
    }

    /// Appends the wide node for binary node `n` and, after it, those below, each
    /// subtree after the one of the lane before; returns the depth of the wide
    /// subtree. The subtrees `joins` names are emitted first, on several threads,
    /// each into a vector of its own, then spliced in where the others would have
    /// put them.
    fn emit(&self, n: usize, out: &mut Vec<Node8>) -> u32 {
        let (binary, table) = (self.binary, self.table);
        let mut kids = Vec::with_capacity(WIDTH);
        if self.is_node(n) {
            let (left, k) = (binary[n].first as usize, table[n].split as usize);
            self.gather(left, k, &mut kids);
            self.gather(left + 1, WIDTH - k, &mut kids);
        } else {
            kids.push(n);
        }
        let mut apart: Vec<Option<(Vec<Node8>, u32)>> = kids
            .par_iter()
            .map(|&k| {
                (self.is_node(k) && table[k].count > self.joins.primitives).then(|| {
                    let mut nodes = Vec::new();
                    let depth = self.emit(k, &mut nodes);
                    (nodes, depth)
                })
            })
            .collect();
        let me = out.len();
        out.push(EMPTY);
        let mut node = EMPTY;
        let mut depth = 1;
        for (lane, &k) in kids.iter().enumerate() {
            let b = &binary[k];
            for axis in 0..3 {
                node.bounds[MIN][axis][lane] = b.min[axis];
                node.bounds[MAX][axis][lane] = b.max[axis];
            }
            if !self.is_node(k) {
                node.child[lane] = table[k].first;
                node.count[lane] = table[k].count;
                continue;
            }
            node.child[lane] = out.len() as u32;
            node.count[lane] = 0;
            let below = match apart[lane].take() {
                Some((nodes, below)) => {
                    splice(out, nodes);
                    below
                }
                None => self.emit(k, out),
            };
            depth = depth.max(1 + below);
        }
        out[me] = node;
        depth
    }
}

/// Appends `nodes` (a wide subtree, its root at 0) to `out`, renumbering its links.
fn splice(out: &mut Vec<Node8>, nodes: Vec<Node8>) {
    let offset = out.len() as u32;
    out.extend(nodes.into_iter().map(|mut node| {
        for lane in 0..WIDTH {
            if node.count[lane] == 0 && node.child[lane] != u32::MAX {
                node.child[lane] += offset;
            }
        }
        node
    }));
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::accel::build::sah::{build_with, MAX_LEAF};
    use crate::accel::tests::random_boxes;
    use crate::math::Aabb;

    /// The collapse this module replaced, kept as a yardstick: repeatedly open the
    /// interior child with the largest surface area until the node has eight.
    fn greedy(binary: &[BvhNode], n: usize, out: &mut Vec<Node8>) {
        let mut kids = if binary[n].is_leaf() {
            vec![n]
        } else {
            vec![binary[n].first as usize, binary[n].first as usize + 1]
        };
        while kids.len() < WIDTH {
            let area = |k: usize| binary[k].bounds().surface_area();
            let widest = (0..kids.len())
                .filter(|&s| !binary[kids[s]].is_leaf())
                .max_by(|&a, &b| area(kids[a]).total_cmp(&area(kids[b])));
            let Some(slot) = widest else { break };
            let k = kids[slot];
            kids[slot] = binary[k].first as usize;
            kids.push(binary[k].first as usize + 1);
        }
        let me = out.len();
        out.push(EMPTY);
        let mut node = EMPTY;
        for (lane, &k) in kids.iter().enumerate() {
            let b = &binary[k];
            for axis in 0..3 {
                node.bounds[MIN][axis][lane] = b.min[axis];
                node.bounds[MAX][axis][lane] = b.max[axis];
            }
            if b.is_leaf() {
                (node.child[lane], node.count[lane]) = (b.first, b.count);
            } else {
                node.child[lane] = out.len() as u32;
                greedy(binary, k, out);
            }
        }
        out[me] = node;
    }

    /// The SAH cost of a wide tree, computed from its nodes alone: every wide node
    /// costs its box's area times `TRAVERSAL_COST`, every leaf lane its box's area
    /// times its `leaf_cost`. Also checks the tree's shape: each node reached once,
    /// each primitive in exactly one leaf, leaves no larger than `max_leaf`.
    fn sah(wide: &[Node8], packs: &[Pack], max_leaf: u32) -> f64 {
        let mut reached = vec![false; wide.len()];
        let mut covered = vec![0u32; packs.len()];
        let mut cost = 0.0f64;
        let mut stack = vec![(0usize, None::<Aabb>)];
        while let Some((n, own)) = stack.pop() {
            assert!(!reached[n], "node {n} reached twice");
            reached[n] = true;
            let node = &wide[n];
            let lanes = (0..WIDTH).filter(|&l| node.child[l] != u32::MAX);
            let own = own.unwrap_or_else(|| {
                lanes
                    .clone()
                    .map(|l| node.lane_bounds(l))
                    .fold(Aabb::EMPTY, Aabb::union)
            });
            cost += f64::from(own.surface_area() * TRAVERSAL_COST);
            for lane in lanes {
                let (first, count) = (node.child[lane], node.count[lane]);
                if count == 0 {
                    stack.push((first as usize, Some(node.lane_bounds(lane))));
                    continue;
                }
                assert!(count <= max_leaf, "a leaf of {count} primitives");
                let range = first as usize..(first + count) as usize;
                range.clone().for_each(|p| covered[p] += 1);
                let kinds = Packs::of(packs[range].iter().copied());
                cost += f64::from(node.lane_bounds(lane).surface_area() * leaf_cost(count, kinds));
            }
        }
        assert!(reached.iter().all(|&r| r), "every node is reached");
        assert!(covered.iter().all(|&c| c == 1), "every primitive is in one leaf");
        cost
    }

    #[test]
    fn the_optimal_collapse_never_costs_more_than_the_greedy_one() {
        let kinds = [
            Pack::Triangle,
            Pack::Triangle,
            Pack::Sphere,
            Pack::Alone,
            Pack::Triangle,
        ];
        let mut improved = 0;
        for kind in 0..5 {
            for (seed, n) in [(1, 1), (2, 9), (3, 100), (4, 3000), (5, 20_000)] {
                let boxes = random_boxes(n, seed, kind);
                // Uniform kinds (packable leaves) on even seeds, mixed on odd ones.
                let packs: Vec<Pack> = (0..n)
                    .map(|i| kinds[if seed % 2 == 0 { 0 } else { i % 5 }])
                    .collect();
                let built = build_with(&boxes, &packs, usize::MAX);
                let leaf_packs: Vec<Pack> = built.order.iter().map(|&i| packs[i as usize]).collect();
                let (optimal, depth) = collapse(&built.nodes, &leaf_packs);
                assert!(depth <= built.depth);
                let mut reference = Vec::new();
                greedy(&built.nodes, 0, &mut reference);
                let cost = sah(&optimal, &leaf_packs, MAX_MERGED_LEAF.max(MAX_LEAF as u32 * 2));
                let yardstick = sah(&reference, &leaf_packs, u32::MAX);
                // Degenerate boxes (kinds 1, 3, 4) give infinite or NaN costs: only
                // the shape is checked there.
                if kind == 0 || kind == 2 {
                    let what = format!("kind {kind}, {n} boxes: {cost} against {yardstick}");
                    assert!(cost <= yardstick * (1.0 + 1e-6), "{what}");
                    improved += usize::from(cost < yardstick * (1.0 - 1e-3));
                }
            }
        }
        assert!(
            improved >= 3,
            "the optimal collapse beat the greedy one only {improved} times"
        );
    }

    /// The subtrees handed to other threads (tabulated by `rayon::join`, emitted apart
    /// and spliced in) give the wide nodes that collapsing all on one thread gives,
    /// bit for bit, whichever subtrees go and on however many threads.
    #[test]
    fn the_collapse_on_several_threads_equals_the_serial_one() {
        let serial = Joins {
            nodes: usize::MAX,
            primitives: u32::MAX,
        };
        let every = Joins {
            nodes: 0,
            primitives: 0,
        };
        let bits = |wide: &[Node8]| -> Vec<u32> {
            wide.iter()
                .flat_map(|n| {
                    let bounds = n.bounds.iter().flatten().flatten().map(|x| x.to_bits());
                    bounds.chain(n.child).chain(n.count).collect::<Vec<_>>()
                })
                .collect()
        };
        let pool = rayon::ThreadPoolBuilder::new().num_threads(3).build().unwrap();
        for kind in 0..5 {
            for (seed, n) in [(1, 1), (2, 9), (3, 300), (4, 40_000)] {
                let boxes = random_boxes(n, seed, kind);
                let packs: Vec<Pack> = (0..n)
                    .map(|i| [Pack::Triangle, Pack::Sphere][usize::from(i % 7 == 0)])
                    .collect();
                let built = build_with(&boxes, &packs, usize::MAX);
                let leaf_packs: Vec<Pack> = built.order.iter().map(|&i| packs[i as usize]).collect();
                let (one, depth) = collapse_with(&built.nodes, &leaf_packs, serial);
                for joins in [JOINS, every] {
                    let (wide, d) = pool.install(|| collapse_with(&built.nodes, &leaf_packs, joins));
                    let what = format!("kind {kind}, {n} boxes, {joins:?}");
                    assert_eq!(d, depth, "{what}");
                    assert_eq!(wide.len(), one.len(), "{what}");
                    assert!(bits(&wide) == bits(&one), "{what}");
                }
            }
        }
    }
}
