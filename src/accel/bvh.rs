//! The BVH over a scene's primitives and its two queries, `closest_hit` and `occluded`.

use super::build::{self, Pack};
use std::cell::{Cell, RefCell};

#[cfg(target_arch = "x86_64")]
use super::avx::Avx;
use super::collapse;
use super::cone4::Cone4;
use super::nearest::Nearest;
use super::node::BvhNode;
use super::sphere4::Sphere4;
use super::split::{self, Copies};
use super::tri4::{nearest_lane, Block, Ray4, Tri4, LANES};
use super::wide::{Kernels, Node8, Portable, RayBoxes, WIDTH};
use crate::geometry::{Geometry, GeometryData, Hit, Primitive, Shape};
use crate::math::{Aabb, Ray};
use rayon::prelude::*;

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
pub(super) fn sort_descending(v: &mut [(u32, f32)]) {
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
pub(super) const TRI4_LEAF: usize = 1 << 31;

/// Marks a wide leaf lane whose primitives are all spheres packed in blocks: its
/// `child` is the first of `count & !SPHERE4_LEAF` [`Sphere4`] blocks.
pub(super) const SPHERE4_LEAF: usize = 1 << 30;

/// Marks a wide leaf lane whose primitives are all cones packed in blocks: its
/// `child` is the first of `count & !CONE4_LEAF` [`Cone4`] blocks.
pub(super) const CONE4_LEAF: usize = 1 << 29;

/// The shadow-cache value of [`Bvh::occluded_hinted`] that names nothing.
pub const NO_HINT: u32 = u32::MAX;

/// Shadow-cache values ([`Bvh::occluded_hinted`]): the top two bits say which array
/// the rest indexes (an index past 2^30 would only alias another entry: a hint is
/// only ever tested, so at worst it is useless).
mod hint_bits {
    pub const PRIMITIVE: u32 = 0;
    pub const TRI4: u32 = 1 << 30;
    pub const SPHERE4: u32 = 2 << 30;
    pub const CONE4: u32 = 3 << 30;
    pub const INDEX: u32 = (1 << 30) - 1;
}

/// Sets of leaf kinds, as bits, for the copies of the queries (see [`Bvh::kinds`]).
pub(super) mod leaf_kinds {
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
pub(super) use with_kinds;

/// The kind of block `p` is tested in (see [`build::Pack`]): triangles, and spheres
/// and (non-degenerate) cones visible from outside, pack four to a block; everything
/// else is tested alone.
pub(super) fn pack_of(p: &Primitive) -> Pack {
    match p.shape {
        Shape::Triangle(_) => Pack::Triangle,
        Shape::Sphere(s) if !s.inside => Pack::Sphere,
        Shape::Cone(c) if !c.inside && c.length > 0.0 => Pack::Cone,
        _ => Pack::Alone,
    }
}

/// The blocks of [`pack_leaves`].
#[derive(Default)]
struct Blocks {
    tri4: Vec<Tri4>,
    sphere4: Vec<Sphere4>,
    cone4: Vec<Cone4>,
}

/// Repacks every wide leaf lane made only of triangles into [`Tri4`] blocks (marked
/// with [`TRI4_LEAF`]), every one made only of packable spheres into [`Sphere4`]
/// blocks (marked with [`SPHERE4_LEAF`]) and every one made only of packable cones
/// into [`Cone4`] blocks (marked with [`CONE4_LEAF`]); other leaves keep pointing at
/// `primitives`.
fn pack_leaves(wide: &mut [Node8], primitives: &[Primitive], canonical: Option<&[u32]>) -> Blocks {
    let mut blocks = Blocks::default();
    for node in wide.iter_mut() {
        for lane in 0..WIDTH {
            let (first, count) = (node.child[lane] as usize, node.count[lane] as usize);
            if count == 0 {
                continue;
            }
            let leaf = &primitives[first..first + count];
            let kind = pack_of(&leaf[0]);
            if leaf.iter().any(|p| pack_of(p) != kind) {
                continue;
            }
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
            let (range, mark) = match kind {
                Pack::Alone => continue,
                Pack::Triangle => (
                    pack_into(leaf, first, canonical, triangle, Tri4::new, &mut blocks.tri4),
                    TRI4_LEAF,
                ),
                Pack::Sphere => (
                    pack_into(leaf, first, canonical, sphere, Sphere4::new, &mut blocks.sphere4),
                    SPHERE4_LEAF,
                ),
                Pack::Cone => (
                    pack_into(leaf, first, canonical, cone, Cone4::new, &mut blocks.cone4),
                    CONE4_LEAF,
                ),
            };
            node.child[lane] = range.start as u32;
            node.count[lane] = (mark | range.len()) as u32;
        }
    }
    blocks
}

/// Appends to `out` the blocks (`make`, [`LANES`] shapes at most) of `leaf`, whose
/// primitives are `first, first + 1, …` (reported as `canonical` maps them, if
/// given) and all have the shape `shape` picks out; returns the range of the new
/// blocks.
fn pack_into<T, B>(
    leaf: &[Primitive],
    first: usize,
    canonical: Option<&[u32]>,
    shape: impl Fn(&Shape) -> Option<T>,
    make: impl Fn(&[(T, u32)]) -> B,
    out: &mut Vec<B>,
) -> std::ops::Range<usize> {
    let start = out.len();
    let mut lanes = Vec::with_capacity(LANES);
    for (chunk_index, chunk) in leaf.chunks(LANES).enumerate() {
        lanes.clear();
        for (k, p) in chunk.iter().enumerate() {
            if let Some(t) = shape(&p.shape) {
                let index = first + chunk_index * LANES + k;
                lanes.push((t, canonical.map_or(index as u32, |c| c[index])));
            }
        }
        out.push(make(&lanes));
    }
    start..out.len()
}

/// The blocks of a leaf lane (`first`, `count` as in a [`Node8`]) when its count
/// carries `mark` (blocks of one kind, see [`TRI4_LEAF`] and the others), counted as
/// primitive tests.
#[inline(always)]
pub(super) fn marked<B>(blocks: &[B], first: usize, count: usize, mark: usize) -> Option<&[B]> {
    if count & mark == 0 {
        return None;
    }
    let blocks = &blocks[first..first + (count & !mark)];
    count!(PRIMS, blocks.len() * LANES);
    Some(blocks)
}

/// Offers to `nearest` the hits of `ray4` in `blocks`, a block at a time.
#[inline(always)]
fn blocks_closest<B: Block>(blocks: &[B], ray4: &Ray4, nearest: &mut Nearest) {
    for block in blocks {
        if let Some((h, prim)) = block.closest_hit(ray4, nearest.limit) {
            nearest.offer(h, prim);
        }
    }
}

/// A bounding volume hierarchy over the bounded primitives, with the unbounded ones
/// (planes) kept beside it and tested linearly.
#[derive(Clone, Debug)]
pub struct Bvh {
    /// The binary SAH tree (kept for statistics and validation).
    pub(super) nodes: Vec<BvhNode>,
    /// The same tree collapsed to 8-wide nodes, used by the queries. A leaf lane made
    /// only of triangles refers to [`Tri4`] blocks (see [`TRI4_LEAF`]), one made only of
    /// packable spheres to [`Sphere4`] blocks (see [`SPHERE4_LEAF`]), one made only of
    /// packable cones to [`Cone4`] blocks (see [`CONE4_LEAF`]).
    pub(super) wide: Vec<Node8>,
    /// The triangles of all-triangle leaves, four to a block, in leaf order.
    pub(super) tri4: Vec<Tri4>,
    /// The spheres of all-sphere leaves, four to a block, in leaf order.
    pub(super) sphere4: Vec<Sphere4>,
    /// The cones of all-cone leaves, four to a block, in leaf order.
    pub(super) cone4: Vec<Cone4>,
    /// Bounded primitives in leaf order, then the unbounded ones.
    pub(super) primitives: Vec<Primitive>,
    pub(super) bounded: usize,
    /// With split cones (`accel::split`), which leaf-order entries are copies of one
    /// primitive; `None` when every primitive is in the tree once.
    pub(super) copies: Option<Copies>,
    pub(super) data: GeometryData,
    pub(super) depth: u32,
    /// The kinds of leaf the queries look for (see [`leaf_kinds`]): each set they
    /// dispatch on has a copy of them compiled without the other kinds' tests.
    pub(super) kinds: u32,
    /// The AVX kernels, when the CPU has them (detected once, at build time).
    #[cfg(target_arch = "x86_64")]
    pub(super) avx: Option<Avx>,
}

impl Bvh {
    /// Builds the hierarchy over `geometry`, reordering its bounded primitives into
    /// leaf order.
    pub fn new(geometry: Geometry) -> Bvh {
        let Geometry {
            primitives: mut bounded,
            data,
        } = geometry;
        // Unbounded primitives (planes) set aside in place: with none, as in most
        // scenes, nothing moves. The big arrays below are filled in parallel (their
        // first-touch page faults were a third of building 600 000 spheres).
        let unbounded: Vec<Primitive> = bounded
            .iter()
            .filter(|p| p.bounds(&data).is_none())
            .copied()
            .collect();
        if !unbounded.is_empty() {
            bounded.retain(|p| p.bounds(&data).is_some());
        }
        let bounds: Vec<Aabb> = bounded
            .par_iter()
            .map(|p| p.bounds(&data).expect("unbounded primitives set aside"))
            .collect();
        // Triangles and spheres are intersected several at a time (in blocks), which
        // the SAH knows.
        let packs: Vec<Pack> = bounded.par_iter().map(pack_of).collect();
        // Long oblique cones enter the tree as several pieces (`accel::split`).
        let refs = split::split_long_cones(&bounded, &bounds, &packs);
        let built = match &refs {
            Some(r) => build::build(&r.bounds, &r.packs),
            None => build::build(&bounds, &packs),
        };
        drop(bounds);
        let copies = refs.as_ref().map(|r| Copies::new(r, &built.order, bounded.len()));
        let order: Vec<u32> = match &refs {
            Some(r) => built.order.iter().map(|&i| r.primitive[i as usize]).collect(),
            None => built.order,
        };
        drop(refs);
        let mut ordered: Vec<Primitive> = order.par_iter().map(|&i| bounded[i as usize]).collect();
        drop(bounded);
        let leaf_packs: Vec<Pack> = order.par_iter().map(|&i| packs[i as usize]).collect();
        let n_bounded = ordered.len();
        ordered.extend(unbounded);
        let mut wide = if n_bounded > 0 {
            collapse::collapse(&built.nodes, &leaf_packs).0
        } else {
            Vec::new()
        };
        let canonical = copies.as_ref().map(|c| c.canonical.as_slice());
        let Blocks { tri4, sphere4, cone4 } = pack_leaves(&mut wide, &ordered, canonical);
        let kinds = leaf_kinds::copy_for(&wide);
        Bvh {
            nodes: built.nodes,
            wide,
            tri4,
            sphere4,
            cone4,
            primitives: ordered,
            bounded: n_bounded,
            copies,
            data,
            depth: built.depth,
            kinds,
            #[cfg(target_arch = "x86_64")]
            avx: Avx::detect(),
        }
    }

    /// The index the queries report for leaf-order entry `index`: the first copy's
    /// when the entry is a copy of a split cone (`accel::split`).
    #[inline(always)]
    pub(super) fn canonical(&self, index: usize) -> u32 {
        match &self.copies {
            Some(c) => c.canonical[index],
            None => index as u32,
        }
    }

    /// Primitive `index` as returned by the queries.
    #[inline]
    pub fn primitive(&self, index: u32) -> &Primitive {
        &self.primitives[index as usize]
    }

    /// The number of distinct primitives (a split cone counts once, though
    /// [`Bvh::primitives`] holds it once per piece).
    pub fn primitive_count(&self) -> usize {
        let copies = self.copies.as_ref().map_or(0, |c| self.bounded - c.distinct);
        self.primitives.len() - copies
    }

    /// All primitives: bounded ones in leaf order (a split cone once per piece, see
    /// `accel::split`), then unbounded ones.
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
        with_kinds!(self.kinds, K => self.closest_hit_with::<_, K>(Portable, ray, t_max))
    }

    /// [`Bvh::closest_hit`] with the slab test `kernels` (inlined into each caller, so
    /// that an AVX caller compiles all of it for AVX), for trees whose leaves are of the
    /// kinds `KINDS` (see [`Bvh::kinds`]).
    #[inline(always)]
    pub(super) fn closest_hit_with<S: Kernels, const KINDS: u32>(
        &self,
        kernels: S,
        ray: &Ray,
        t_max: f32,
    ) -> Option<(Hit, u32)> {
        let mut nearest = Nearest::new(t_max);
        for (i, p) in self.primitives[self.bounded..].iter().enumerate() {
            if let Some(h) = p.intersect(ray, nearest.limit, &self.data) {
                nearest.offer(h, (self.bounded + i) as u32);
            }
        }
        if self.wide.is_empty() {
            return nearest.best;
        }
        let boxes = RayBoxes::new(ray);
        let ray4 = Ray4::new(ray);
        self.walk_closest::<S, KINDS>(kernels, 0, ray, &boxes, &ray4, &mut nearest);
        nearest.best
    }

    /// The tree walk of [`Bvh::closest_hit`] through the subtree of the wide node
    /// `start` (the root: the whole tree), improving `nearest`; `boxes` and `ray4` are
    /// `ray` prepared for the slab and leaf tests. The packets hand a subtree over to
    /// it once only a few of their rays go on into it (`packet::SOLO`).
    #[inline(always)]
    pub(super) fn walk_closest<S: Kernels, const KINDS: u32>(
        &self,
        kernels: S,
        start: u32,
        ray: &Ray,
        boxes: &RayBoxes,
        ray4: &Ray4,
        nearest: &mut Nearest,
    ) {
        STACK.with_borrow_mut(|buffer| {
            let stack = self.stack_of(buffer);
            let mut sp = 0usize;
            let mut index = start;
            loop {
                let node = &self.wide[index as usize];
                count!(NODES, 1);
                let limit = nearest.limit;
                let (t, mask) = kernels.entries(node, boxes, limit);
                let leaves = mask & node.leaf_lanes();
                let mut each = leaves;
                while each != 0 {
                    let lane = each.trailing_zeros() as usize;
                    each &= each - 1;
                    if t[lane] < nearest.limit {
                        let count = node.count[lane] as usize;
                        self.leaf_closest::<S, KINDS>(
                            kernels,
                            node.child[lane] as usize,
                            count,
                            ray,
                            ray4,
                            nearest,
                        );
                    }
                }
                // Go straight on to the nearest child; stack the others so that the
                // nearer ones are popped first. One or two children (the common cases)
                // need no sort.
                let mut inner = mask & !leaves;
                let child = |lane: u32| (node.child[lane as usize], t[lane as usize]);
                let next = if inner == 0 {
                    None
                } else {
                    let a = inner.trailing_zeros();
                    inner &= inner - 1;
                    if inner == 0 {
                        Some(child(a))
                    } else {
                        let b = inner.trailing_zeros();
                        inner &= inner - 1;
                        let (near, far) = if t[b as usize] < t[a as usize] {
                            (b, a)
                        } else {
                            (a, b)
                        };
                        stack[sp] = child(far);
                        sp += 1;
                        if inner == 0 {
                            Some(child(near))
                        } else {
                            let base = sp - 1;
                            stack[sp] = child(near);
                            sp += 1;
                            while inner != 0 {
                                stack[sp] = child(inner.trailing_zeros());
                                sp += 1;
                                inner &= inner - 1;
                            }
                            sort_descending(&mut stack[base..sp]);
                            sp -= 1;
                            Some(stack[sp])
                        }
                    }
                };
                // A leaf just tested may have moved the limit in front of a child.
                match next.filter(|&(_, t)| t < nearest.limit) {
                    Some((next, _)) => index = next,
                    None => loop {
                        if sp == 0 {
                            return;
                        }
                        sp -= 1;
                        let (next, t_entry) = stack[sp];
                        if t_entry < nearest.limit {
                            index = next;
                            break;
                        }
                    },
                }
            }
        });
    }

    /// Offers to `nearest` the hits of `ray` (and `ray4`, the same ray broadcast) in
    /// the leaf lane whose child and count are `first` and `count`: [`Tri4`] blocks
    /// when marked [`TRI4_LEAF`], [`Sphere4`] blocks when marked [`SPHERE4_LEAF`],
    /// [`Cone4`] blocks when marked [`CONE4_LEAF`], else primitives; only the kinds
    /// in `KINDS` (see [`leaf_kinds`]) are looked for, the last one without looking.
    #[inline(always)]
    pub(super) fn leaf_closest<S: Kernels, const KINDS: u32>(
        &self,
        kernels: S,
        first: usize,
        count: usize,
        ray: &Ray,
        ray4: &Ray4,
        nearest: &mut Nearest,
    ) {
        if KINDS & leaf_kinds::SPHERES != 0 {
            if let Some(blocks) = marked(&self.sphere4, first, count, SPHERE4_LEAF) {
                blocks_closest(blocks, ray4, nearest);
                return;
            }
        }
        if KINDS & leaf_kinds::CONES != 0 {
            if let Some(blocks) = marked(&self.cone4, first, count, CONE4_LEAF) {
                blocks_closest(blocks, ray4, nearest);
                return;
            }
        }
        if let Some(blocks) = self.triangle_blocks::<KINDS>(first, count) {
            self.tri4_closest(kernels, blocks, ray, ray4, nearest);
            return;
        }
        count!(PRIMS, count);
        for (k, p) in self.primitives[first..first + count].iter().enumerate() {
            if let Some(h) = p.intersect(ray, nearest.limit, &self.data) {
                nearest.offer(h, self.canonical(first + k));
            }
        }
    }

    /// The triangle blocks of a leaf lane whose other kinds (in `KINDS`) were ruled
    /// out: taken without looking at the mark when nothing but triangle blocks is left.
    #[inline(always)]
    fn triangle_blocks<const KINDS: u32>(&self, first: usize, count: usize) -> Option<&[Tri4]> {
        if KINDS & leaf_kinds::PRIMITIVES == 0 {
            let blocks = &self.tri4[first..first + (count & !TRI4_LEAF)];
            count!(PRIMS, blocks.len() * LANES);
            return Some(blocks);
        }
        marked(&self.tri4, first, count, TRI4_LEAF)
    }

    /// Offers to `nearest` the hits of `ray` (and `ray4`) in triangle blocks.
    #[inline(always)]
    fn tri4_closest<S: Kernels>(
        &self,
        kernels: S,
        blocks: &[Tri4],
        ray: &Ray,
        ray4: &Ray4,
        nearest: &mut Nearest,
    ) {
        // Blocks two at a time (one eight-lane test), the last one alone.
        let mut pairs = blocks.chunks_exact(2);
        for pair in &mut pairs {
            let (t, u, v, mask) = kernels.pair(&pair[0], &pair[1], ray, nearest.limit);
            if mask != 0 {
                let lane = nearest_lane(&t, mask);
                let hit = Hit {
                    t: t[lane],
                    u: u[lane],
                    v: v[lane],
                };
                nearest.offer(hit, pair[lane / LANES].prim[lane % LANES]);
            }
        }
        blocks_closest(pairs.remainder(), ray4, nearest);
    }

    /// `buffer` grown to the most entries a traversal stacks: fewer than [`WIDTH`] per
    /// level of the tree (a node stacks at most all its children but the one it
    /// descends into, and pops back to a level only once everything deeper is done).
    #[inline(always)]
    fn stack_of<'a>(&self, buffer: &'a mut Vec<(u32, f32)>) -> &'a mut [(u32, f32)] {
        let need = WIDTH * (self.depth as usize + 1);
        if buffer.len() < need {
            buffer.resize(need, (0, 0.0));
        }
        buffer
    }

    /// True when anything lies on the ray with `0 < t < t_max` (stops at the first hit).
    #[inline]
    pub fn occluded(&self, ray: &Ray, t_max: f32) -> bool {
        self.occluder(ray, t_max).is_some()
    }

    /// [`Bvh::occluded`] that first tests the primitive or block of four named by
    /// `hint` (a value an earlier query left there; any value is safe, [`NO_HINT`] for
    /// none) and leaves in it the one that blocked this ray, or [`NO_HINT`] when
    /// nothing did: neighbouring shadow rays are usually blocked by the same
    /// primitive or one of its neighbours in the block (Haines' shadow cache), or all
    /// lit. The answer is the same as `occluded`'s.
    #[inline]
    pub fn occluded_hinted(&self, ray: &Ray, t_max: f32, hint: &Cell<u32>) -> bool {
        // Tested here, not in the traversal's copies, so `occluded` pays nothing for it.
        if hint.get() != NO_HINT && self.hint_blocks(hint.get(), ray, &Ray4::new(ray), t_max) {
            return true;
        }
        match self.occluder(ray, t_max) {
            Some(blocker) => {
                hint.set(blocker);
                true
            }
            None => {
                // Lit: the next ray (a neighbour) most likely is too, and then skips
                // testing a stale hint.
                hint.set(NO_HINT);
                false
            }
        }
    }

    /// The shadow-cache value (see [`Bvh::occluded_hinted`]) of a primitive or block
    /// lying on the ray with `0 < t < t_max` (the first one found).
    fn occluder(&self, ray: &Ray, t_max: f32) -> Option<u32> {
        #[cfg(target_arch = "x86_64")]
        if let Some(avx) = self.avx {
            return avx.occluder(self, ray, t_max);
        }
        with_kinds!(self.kinds, K => self.occluder_with::<_, K>(Portable, ray, t_max))
    }

    /// True when the primitive or block that shadow-cache value `hint` names lies on
    /// the ray with `0 < t < t_max`; false for values naming nothing.
    #[inline(always)]
    fn hint_blocks(&self, hint: u32, ray: &Ray, ray4: &Ray4, t_max: f32) -> bool {
        let index = (hint & hint_bits::INDEX) as usize;
        match hint & !hint_bits::INDEX {
            hint_bits::PRIMITIVE => self
                .primitives
                .get(index)
                .is_some_and(|p| p.intersect(ray, t_max, &self.data).is_some()),
            hint_bits::TRI4 => self.tri4.get(index).is_some_and(|b| b.any_hit(ray4, t_max)),
            hint_bits::SPHERE4 => self.sphere4.get(index).is_some_and(|b| b.any_hit(ray4, t_max)),
            _ => self.cone4.get(index).is_some_and(|b| b.any_hit(ray4, t_max)),
        }
    }

    /// The primitives that shadow-cache value `hint` names (for tests).
    #[cfg(test)]
    pub(super) fn hint_primitives(&self, hint: u32) -> Vec<u32> {
        let index = (hint & hint_bits::INDEX) as usize;
        let prims = match hint & !hint_bits::INDEX {
            hint_bits::PRIMITIVE => return vec![hint],
            hint_bits::TRI4 => self.tri4.get(index).map(|b| *b.prims()),
            hint_bits::SPHERE4 => self.sphere4.get(index).map(|b| *b.prims()),
            _ => self.cone4.get(index).map(|b| *b.prims()),
        };
        prims.into_iter().flatten().filter(|&p| p != u32::MAX).collect()
    }

    /// The shadow-cache value (see [`Bvh::occluded_hinted`]) of a primitive or block
    /// of the leaf lane (`first`, `count`, as in [`Bvh::leaf_closest`], and `KINDS`
    /// too) lying on `ray` (and `ray4`, the same ray broadcast) with `0 < t < t_max`.
    #[inline(always)]
    fn leaf_any<S: Kernels, const KINDS: u32>(
        &self,
        kernels: S,
        first: usize,
        count: usize,
        ray: &Ray,
        ray4: &Ray4,
        t_max: f32,
    ) -> Option<u32> {
        if KINDS & leaf_kinds::SPHERES != 0 {
            if let Some(blocks) = marked(&self.sphere4, first, count, SPHERE4_LEAF) {
                let k = blocks.iter().position(|b| b.any_hit(ray4, t_max))?;
                return Some(hint_bits::SPHERE4 | (first + k) as u32);
            }
        }
        if KINDS & leaf_kinds::CONES != 0 {
            if let Some(blocks) = marked(&self.cone4, first, count, CONE4_LEAF) {
                let k = blocks.iter().position(|b| b.any_hit(ray4, t_max))?;
                return Some(hint_bits::CONE4 | (first + k) as u32);
            }
        }
        if let Some(blocks) = self.triangle_blocks::<KINDS>(first, count) {
            let k = self.tri4_any(kernels, blocks, ray, ray4, t_max)?;
            return Some(hint_bits::TRI4 | (first + k) as u32);
        }
        count!(PRIMS, count);
        let leaf = &self.primitives[first..first + count];
        let k = leaf
            .iter()
            .position(|p| p.intersect(ray, t_max, &self.data).is_some())?;
        Some(hint_bits::PRIMITIVE | (first + k) as u32)
    }

    /// The position in `blocks` of a triangle block lying on `ray` (and `ray4`) with
    /// `0 < t < t_max`.
    #[inline(always)]
    fn tri4_any<S: Kernels>(
        &self,
        kernels: S,
        blocks: &[Tri4],
        ray: &Ray,
        ray4: &Ray4,
        t_max: f32,
    ) -> Option<usize> {
        let mut pairs = blocks.chunks_exact(2);
        for (k, pair) in (&mut pairs).enumerate() {
            let mask = kernels.pair(&pair[0], &pair[1], ray, t_max).3;
            if mask != 0 {
                return Some(2 * k + (mask.trailing_zeros() as usize) / LANES);
            }
        }
        let rest = pairs.remainder();
        let k = rest.iter().position(|b| b.any_hit(ray4, t_max))?;
        Some(blocks.len() - rest.len() + k)
    }

    /// [`Bvh::occluder`] with the slab test `kernels` (see [`Bvh::closest_hit_with`]).
    #[inline(always)]
    pub(super) fn occluder_with<S: Kernels, const KINDS: u32>(
        &self,
        kernels: S,
        ray: &Ray,
        t_max: f32,
    ) -> Option<u32> {
        let unbounded = &self.primitives[self.bounded..];
        if let Some(i) = unbounded
            .iter()
            .position(|p| p.intersect(ray, t_max, &self.data).is_some())
        {
            return Some(hint_bits::PRIMITIVE | (self.bounded + i) as u32);
        }
        if self.wide.is_empty() {
            return None;
        }
        let boxes = RayBoxes::new(ray);
        let ray4 = Ray4::new(ray);
        STACK.with_borrow_mut(|buffer| {
            let stack = self.stack_of(buffer);
            let mut sp = 0usize;
            let mut index = 0u32;
            loop {
                let node = &self.wide[index as usize];
                count!(NODES, 1);
                let mut mask = kernels.entered(node, &boxes, t_max);
                let mut next = None;
                while mask != 0 {
                    let lane = mask.trailing_zeros() as usize;
                    mask &= mask - 1;
                    let count = node.count[lane] as usize;
                    if count == 0 {
                        // Go straight on to the first child entered, stack the others.
                        match next {
                            None => next = Some(node.child[lane]),
                            Some(_) => {
                                stack[sp] = (node.child[lane], 0.0);
                                sp += 1;
                            }
                        }
                        continue;
                    }
                    let first = node.child[lane] as usize;
                    if let Some(blocker) = self.leaf_any::<S, KINDS>(kernels, first, count, ray, &ray4, t_max)
                    {
                        return Some(blocker);
                    }
                }
                match next {
                    Some(n) => index = n,
                    None if sp > 0 => {
                        sp -= 1;
                        index = stack[sp].0;
                    }
                    None => return None,
                }
            }
        })
    }
}
