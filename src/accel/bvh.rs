//! The BVH over a scene's primitives and its two queries, `closest_hit` and `occluded`.

use super::build;
use std::cell::{Cell, RefCell};

#[cfg(target_arch = "x86_64")]
use super::avx::Avx;
use super::node::BvhNode;
use super::tri4::{Ray4, Tri4, LANES};
use super::wide::{self, Node8, Portable, RayBoxes, SlabTest, WIDTH};
use crate::geometry::{Geometry, GeometryData, Hit, Primitive, Shape};
use crate::math::{Ray, Vec3};

/// Depth limit of the binary tree (the builder stays well below it).
const MAX_DEPTH: usize = 64;

thread_local! {
    /// Each thread's traversal stack of (wide node, entry distance), reused across
    /// queries so that no query pays for allocating or clearing one.
    static STACK: RefCell<Vec<(u32, f32)>> = RefCell::new(Vec::with_capacity(256));
}

/// Traversal counters (feature `counters`): wide nodes visited, primitives tested.
#[cfg(feature = "counters")]
pub mod counters {
    use std::sync::atomic::{AtomicU64, Ordering};
    /// Wide nodes visited.
    pub static NODES: AtomicU64 = AtomicU64::new(0);
    /// Primitive intersection tests.
    pub static PRIMS: AtomicU64 = AtomicU64::new(0);
    /// Adds to a counter.
    #[inline(always)]
    pub fn add(c: &AtomicU64, n: u64) {
        c.fetch_add(n, Ordering::Relaxed);
    }
}

macro_rules! count {
    ($c:ident, $n:expr) => {
        #[cfg(feature = "counters")]
        counters::add(&counters::$c, $n as u64);
    };
}

/// Insertion sort by decreasing distance (at most `WIDTH` entries).
#[inline(always)]
fn sort_descending(v: &mut [(u32, f32)]) {
    for i in 1..v.len() {
        let mut j = i;
        while j > 0 && v[j - 1].1 < v[j].1 {
            v.swap(j - 1, j);
            j -= 1;
        }
    }
}

/// Marks a wide leaf lane whose primitives are all triangles: its `child` is the first
/// of `count & !TRI4_LEAF` [`Tri4`] blocks instead of the first primitive.
const TRI4_LEAF: usize = 1 << 31;

/// Repacks every wide leaf lane made only of triangles into [`Tri4`] blocks (marked
/// with [`TRI4_LEAF`]); other leaves keep pointing at `primitives`.
fn pack_triangle_leaves(wide: &mut [Node8], primitives: &[Primitive]) -> Vec<Tri4> {
    let mut blocks = Vec::new();
    let mut lane_triangles = Vec::with_capacity(LANES);
    for node in wide.iter_mut() {
        for lane in 0..WIDTH {
            let (first, count) = (node.child[lane] as usize, node.count[lane] as usize);
            if count == 0 {
                continue;
            }
            let leaf = &primitives[first..first + count];
            if !leaf.iter().all(|p| matches!(p.shape, Shape::Triangle(_))) {
                continue;
            }
            let start = blocks.len();
            for (chunk_index, chunk) in leaf.chunks(LANES).enumerate() {
                lane_triangles.clear();
                for (k, p) in chunk.iter().enumerate() {
                    if let Shape::Triangle(t) = p.shape {
                        lane_triangles.push((t, (first + chunk_index * LANES + k) as u32));
                    }
                }
                blocks.push(Tri4::new(&lane_triangles));
            }
            node.child[lane] = start as u32;
            node.count[lane] = (TRI4_LEAF | (blocks.len() - start)) as u32;
        }
    }
    blocks
}

/// A bounding volume hierarchy over the bounded primitives, with the unbounded ones
/// (planes) kept beside it and tested linearly.
#[derive(Clone, Debug)]
pub struct Bvh {
    /// The binary SAH tree (kept for statistics and validation).
    nodes: Vec<BvhNode>,
    /// The same tree collapsed to 8-wide nodes, used by the queries. A leaf lane made
    /// only of triangles refers to [`Tri4`] blocks (see [`TRI4_LEAF`]).
    wide: Vec<Node8>,
    /// The triangles of all-triangle leaves, four to a block, in leaf order.
    tri4: Vec<Tri4>,
    /// Bounded primitives in leaf order, then the unbounded ones.
    primitives: Vec<Primitive>,
    bounded: usize,
    data: GeometryData,
    depth: u32,
    /// The AVX kernels, when the CPU has them (detected once, at build time).
    #[cfg(target_arch = "x86_64")]
    avx: Option<Avx>,
}

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
    /// counts one test per block of four, as they are intersected).
    pub sah_cost: f64,
    /// Bounded primitives in the tree.
    pub primitives: usize,
    /// Unbounded primitives tested beside it.
    pub unbounded: usize,
}

impl Bvh {
    /// Builds the hierarchy over `geometry`, reordering its bounded primitives into
    /// leaf order.
    pub fn new(geometry: Geometry) -> Bvh {
        let Geometry { primitives, data } = geometry;
        // Sized up front: grown by doubling, these two were the peak of a whole render's
        // memory (old and new buffers side by side, up to twice the length).
        let n = primitives.len();
        let (mut bounded, mut bounds, mut unbounded) =
            (Vec::with_capacity(n), Vec::with_capacity(n), Vec::new());
        for p in primitives {
            match p.bounds(&data) {
                Some(b) => {
                    bounded.push(p);
                    bounds.push(b);
                }
                None => unbounded.push(p),
            }
        }
        // Triangles are intersected four at a time (tri4 blocks), which the SAH knows.
        let packable: Vec<bool> = bounded
            .iter()
            .map(|p: &Primitive| matches!(p.shape, Shape::Triangle(_)))
            .collect();
        let built = build::build(&bounds, &packable);
        let mut ordered: Vec<Primitive> = built.order.iter().map(|&i| bounded[i as usize]).collect();
        let n_bounded = ordered.len();
        ordered.extend(unbounded);
        let mut wide = if n_bounded > 0 {
            wide::collapse(&built.nodes).0
        } else {
            Vec::new()
        };
        let tri4 = pack_triangle_leaves(&mut wide, &ordered);
        Bvh {
            nodes: built.nodes,
            wide,
            tri4,
            primitives: ordered,
            bounded: n_bounded,
            data,
            depth: built.depth,
            #[cfg(target_arch = "x86_64")]
            avx: Avx::detect(),
        }
    }

    /// Primitive `index` as returned by the queries.
    #[inline]
    pub fn primitive(&self, index: u32) -> &Primitive {
        &self.primitives[index as usize]
    }

    /// All primitives: bounded ones in leaf order, then unbounded ones.
    pub fn primitives(&self) -> &[Primitive] {
        &self.primitives
    }

    /// The shared geometry arrays.
    pub fn data(&self) -> &GeometryData {
        &self.data
    }

    /// The flattened nodes (root at 0).
    pub fn nodes(&self) -> &[BvhNode] {
        &self.nodes
    }

    /// The nearest hit with `0 < t < t_max`, and the index of the primitive hit.
    #[inline]
    pub fn closest_hit(&self, ray: &Ray, t_max: f32) -> Option<(Hit, u32)> {
        #[cfg(target_arch = "x86_64")]
        if let Some(avx) = self.avx {
            return avx.closest_hit(self, ray, t_max);
        }
        self.closest_hit_with(Portable, ray, t_max)
    }

    /// [`Bvh::closest_hit`] with the slab test `slabs` (inlined into each caller, so
    /// that an AVX caller compiles all of it for AVX).
    #[inline(always)]
    pub(super) fn closest_hit_with<S: SlabTest>(
        &self,
        slabs: S,
        ray: &Ray,
        t_max: f32,
    ) -> Option<(Hit, u32)> {
        let mut best: Option<(Hit, u32)> = None;
        let mut t_best = t_max;
        for (i, p) in self.primitives[self.bounded..].iter().enumerate() {
            if let Some(h) = p.intersect(ray, t_best, &self.data) {
                t_best = h.t;
                best = Some((h, (self.bounded + i) as u32));
            }
        }
        if self.wide.is_empty() {
            return best;
        }
        let boxes = RayBoxes::new(ray);
        let ray4 = Ray4::new(ray);
        STACK.with_borrow_mut(|stack| {
            stack.clear();
            let mut index = 0u32;
            loop {
                let node = &self.wide[index as usize];
                count!(NODES, 1);
                let (t, mut mask) = slabs.entries(node, &boxes, t_best, t_best);
                let mut inner = [(0u32, 0.0f32); WIDTH];
                let mut n_inner = 0;
                while mask != 0 {
                    let lane = mask.trailing_zeros() as usize;
                    mask &= mask - 1;
                    let count = node.count[lane] as usize;
                    if count == 0 {
                        inner[n_inner] = (node.child[lane], t[lane]);
                        n_inner += 1;
                        continue;
                    }
                    if t[lane] >= t_best {
                        continue;
                    }
                    let first = node.child[lane] as usize;
                    if count & TRI4_LEAF != 0 {
                        let blocks = &self.tri4[first..first + (count & !TRI4_LEAF)];
                        count!(PRIMS, blocks.len() * LANES);
                        for block in blocks {
                            if let Some((h, prim)) = block.closest_hit(&ray4, t_best) {
                                t_best = h.t;
                                best = Some((h, prim));
                            }
                        }
                        continue;
                    }
                    count!(PRIMS, count);
                    for (k, p) in self.primitives[first..first + count].iter().enumerate() {
                        if let Some(h) = p.intersect(ray, t_best, &self.data) {
                            t_best = h.t;
                            best = Some((h, (first + k) as u32));
                        }
                    }
                }
                // Go straight on to the nearest child; push the others far to near so
                // that the nearer ones are popped first.
                let inner = &mut inner[..n_inner];
                sort_descending(inner);
                let nearest = match inner.split_last() {
                    Some((&nearest, farther)) => {
                        // Element by element: a slice copy of at most four entries
                        // would be a call to memmove.
                        for &entry in farther {
                            stack.push(entry);
                        }
                        Some(nearest)
                    }
                    None => None,
                };
                // A leaf just tested may have moved `t_best` in front of a child.
                match nearest.filter(|&(_, t)| t < t_best) {
                    Some((next, _)) => index = next,
                    None => loop {
                        match stack.pop() {
                            Some((next, t_entry)) if t_entry < t_best => {
                                index = next;
                                break;
                            }
                            Some(_) => {}
                            None => return,
                        }
                    },
                }
            }
        });
        best
    }

    /// True when anything lies on the ray with `0 < t < t_max` (stops at the first hit).
    #[inline]
    pub fn occluded(&self, ray: &Ray, t_max: f32) -> bool {
        self.occluder(ray, t_max).is_some()
    }

    /// [`Bvh::occluded`] that first tries primitive `hint` (an index from an earlier
    /// query; any value is safe) and leaves in it the occluder found, if any: neighbouring
    /// shadow rays are usually blocked by the same primitive (Haines' shadow cache). The
    /// answer is the same as `occluded`'s.
    #[inline]
    pub fn occluded_hinted(&self, ray: &Ray, t_max: f32, hint: &Cell<u32>) -> bool {
        if let Some(p) = self.primitives.get(hint.get() as usize) {
            if p.intersect(ray, t_max, &self.data).is_some() {
                return true;
            }
        }
        match self.occluder(ray, t_max) {
            Some(index) => {
                hint.set(index);
                true
            }
            None => false,
        }
    }

    /// Some primitive lying on the ray with `0 < t < t_max` (the first one found).
    fn occluder(&self, ray: &Ray, t_max: f32) -> Option<u32> {
        #[cfg(target_arch = "x86_64")]
        if let Some(avx) = self.avx {
            return avx.occluder(self, ray, t_max);
        }
        self.occluder_with(Portable, ray, t_max)
    }

    /// [`Bvh::occluder`] with the slab test `slabs` (see [`Bvh::closest_hit_with`]).
    #[inline(always)]
    pub(super) fn occluder_with<S: SlabTest>(&self, slabs: S, ray: &Ray, t_max: f32) -> Option<u32> {
        let unbounded = &self.primitives[self.bounded..];
        if let Some(i) = unbounded
            .iter()
            .position(|p| p.intersect(ray, t_max, &self.data).is_some())
        {
            return Some((self.bounded + i) as u32);
        }
        if self.wide.is_empty() {
            return None;
        }
        let boxes = RayBoxes::new(ray);
        let ray4 = Ray4::new(ray);
        STACK.with_borrow_mut(|stack| {
            stack.clear();
            let mut index = 0u32;
            loop {
                let node = &self.wide[index as usize];
                count!(NODES, 1);
                let (_, mut mask) = slabs.entries(node, &boxes, t_max, f32::INFINITY);
                let mut next = None;
                while mask != 0 {
                    let lane = mask.trailing_zeros() as usize;
                    mask &= mask - 1;
                    let count = node.count[lane] as usize;
                    if count == 0 {
                        // Go straight on to the first child entered, stack the others.
                        match next {
                            None => next = Some(node.child[lane]),
                            Some(_) => stack.push((node.child[lane], 0.0)),
                        }
                        continue;
                    }
                    let first = node.child[lane] as usize;
                    if count & TRI4_LEAF != 0 {
                        let blocks = &self.tri4[first..first + (count & !TRI4_LEAF)];
                        count!(PRIMS, blocks.len() * LANES);
                        if let Some(p) = blocks.iter().find_map(|b| b.any_hit(&ray4, t_max)) {
                            return Some(p);
                        }
                        continue;
                    }
                    let leaf = &self.primitives[first..first + count];
                    count!(PRIMS, count);
                    if let Some(k) = leaf
                        .iter()
                        .position(|p| p.intersect(ray, t_max, &self.data).is_some())
                    {
                        return Some((first + k) as u32);
                    }
                }
                match next.or_else(|| stack.pop().map(|(node, _)| node)) {
                    Some(n) => index = n,
                    None => return None,
                }
            }
        })
    }

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

    /// Checks the structural invariants: every bounded primitive in exactly one leaf,
    /// every child box inside its parent, every primitive box inside its leaf, depth
    /// within the traversal stack. Returns a description of the first violation.
    pub fn validate(&self) -> Result<(), String> {
        if self.depth as usize >= MAX_DEPTH {
            return Err(format!("depth {} exceeds the stack", self.depth));
        }
        let mut seen = vec![0u8; self.bounded];
        if self.bounded > 0 {
            self.validate_node(0, &mut seen)?;
        }
        match seen.iter().position(|&c| c != 1) {
            Some(i) => Err(format!("primitive {i} is reached {} times", seen[i])),
            None => Ok(()),
        }
    }

    fn validate_node(&self, index: usize, seen: &mut [u8]) -> Result<(), String> {
        let node = &self.nodes[index];
        let b = node.bounds();
        if node.is_leaf() {
            let first = node.first as usize;
            let leaf = first..first + node.count as usize;
            for (i, (p, count)) in self.primitives[leaf.clone()]
                .iter()
                .zip(&mut seen[leaf])
                .enumerate()
            {
                let pb = p.bounds(&self.data).ok_or("unbounded primitive in a leaf")?;
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
            primitives: self.bounded,
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
                let unpackable = leaf
                    .iter()
                    .filter(|p| !matches!(p.shape, Shape::Triangle(_)))
                    .count();
                s.sah_cost += rel * build::leaf_cost(n.count, unpackable as u32) as f64;
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
