//! The single-ray closest-hit query: a walk of the 8-wide tree that goes straight on
//! to the nearest child entered and stacks the others, testing leaves as their
//! boxes are entered.

use std::cell::RefCell;
use std::thread::LocalKey;

use super::nearest::Nearest;
use super::wide::{Kernels, Portable, RayBoxes, WIDTH};
use crate::accel::bvh::Bvh;
use crate::accel::leaf::pack::{leaf_kinds, marked, with_kinds, CONE4_LEAF, SPHERE4_LEAF, TRI4_LEAF};
use crate::accel::leaf::tri4::{nearest_lane, Block, Ray4, Tri4, LANES};
use crate::accel::tally::{QueryCounts, Tally};
use crate::geometry::Hit;
use crate::math::{lanes, Ray};

thread_local! {
    /// Each thread's traversal stacks of (wide node, entry distance), reused across
    /// queries so that no query pays for allocating or clearing one: one for a
    /// scene's trees, one for the prototypes its instances place, whose queries run
    /// inside the scene's (`Bvh::level`).
    static STACK: RefCell<Vec<(u32, f32)>> = RefCell::new(Vec::with_capacity(256));
    static PROTOTYPE_STACK: RefCell<Vec<(u32, f32)>> = RefCell::new(Vec::with_capacity(256));
}

/// Insertion sort by decreasing distance (at most `WIDTH` entries).
#[inline(always)]
pub(in crate::accel) fn sort_descending(v: &mut [(u32, f32)]) {
    for i in 1..v.len() {
        let mut j = i;
        while j > 0 && v[j - 1].1 < v[j].1 {
            v.swap(j - 1, j);
            j -= 1;
        }
    }
}

/// Offers to `nearest` the hits of `ray4` in `blocks`, a block at a time.
#[inline(always)]
pub(in crate::accel) fn blocks_closest<B: Block>(blocks: &[B], ray4: &Ray4, nearest: &mut Nearest) {
    for block in blocks {
        if let Some((h, prim)) = block.closest_hit(ray4, nearest.limit, nearest.ranks()) {
            nearest.offer(h, prim);
        }
    }
}

impl Bvh {
    /// The nearest hit with `0 < t < t_max`, and the index of the primitive hit.
    #[inline]
    pub fn closest_hit(&self, ray: &Ray, t_max: f32) -> Option<(Hit, u32)> {
        #[cfg(target_arch = "x86_64")]
        if let Some(avx) = self.avx {
            return avx.closest_hit(self, ray, t_max);
        }
        with_kinds!(self.kinds, K => self.closest_hit_with::<_, K, _>(Portable, ray, t_max, &mut ()))
    }

    /// [`Bvh::closest_hit`] counting the nodes it visits and the primitives it tests
    /// into `tally` (the portable kernels: the same answer, the same walk).
    pub fn closest_hit_counted(&self, ray: &Ray, t_max: f32, tally: &mut QueryCounts) -> Option<(Hit, u32)> {
        with_kinds!(self.kinds, K => self.closest_hit_with::<_, K, _>(Portable, ray, t_max, tally))
    }

    /// [`Bvh::closest_hit`] with the slab test `kernels` (inlined into each caller, so
    /// that an AVX caller compiles all of it for AVX), for trees whose leaves are of the
    /// kinds `KINDS` (see [`Bvh::kinds`]).
    #[inline(always)]
    pub(in crate::accel) fn closest_hit_with<S: Kernels, const KINDS: u32, T: Tally>(
        &self,
        kernels: S,
        ray: &Ray,
        t_max: f32,
        tally: &mut T,
    ) -> Option<(Hit, u32)> {
        let mut nearest = Nearest::new(t_max, &self.ranks);
        self.unbounded_closest(ray, &mut nearest, tally);
        if self.wide.is_empty() {
            return nearest.best;
        }
        let boxes = RayBoxes::new(ray);
        let ray4 = Ray4::new(ray);
        self.walk_closest::<S, KINDS, T>(kernels, 0, ray, &boxes, &ray4, &mut nearest, tally);
        nearest.best
    }

    /// The tree walk of [`Bvh::closest_hit`] through the subtree of the wide node
    /// `start` (the root: the whole tree), improving `nearest`; `boxes` and `ray4` are
    /// `ray` prepared for the slab and leaf tests. The packets hand a subtree over to
    /// it once only a few of their rays go on into it (`packet::SOLO`).
    #[inline(always)]
    #[allow(clippy::too_many_arguments)]
    pub(in crate::accel) fn walk_closest<S: Kernels, const KINDS: u32, T: Tally>(
        &self,
        kernels: S,
        start: u32,
        ray: &Ray,
        boxes: &RayBoxes,
        ray4: &Ray4,
        nearest: &mut Nearest,
        tally: &mut T,
    ) {
        self.stack_key().with_borrow_mut(|buffer| {
            let stack = self.stack_of(buffer);
            let mut sp = 0usize;
            let mut index = start;
            loop {
                let node = &self.wide[index as usize];
                count!(NODES, 1);
                tally.nodes(1);
                let limit = nearest.limit;
                let (t, mask) = kernels.entries(node, boxes, limit);
                let leaves = mask & node.leaf_lanes();
                for lane in lanes(leaves) {
                    if t[lane] < nearest.limit {
                        let count = node.count[lane] as usize;
                        self.leaf_closest::<S, KINDS, T>(
                            kernels,
                            node.child[lane] as usize,
                            count,
                            ray,
                            ray4,
                            nearest,
                            tally,
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
                            // (Not `for lane in lanes(inner)`: `inner` is not empty
                            // here, and the loop tested at its end compiles shorter.)
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
    /// when marked [`TRI4_LEAF`], [`Sphere4`](crate::accel::leaf::sphere4::Sphere4) blocks when marked [`SPHERE4_LEAF`],
    /// [`Cone4`](crate::accel::leaf::cone4::Cone4) blocks when marked [`CONE4_LEAF`], else primitives; only the kinds
    /// in `KINDS` (see [`leaf_kinds`]) are looked for, the last one without looking.
    #[inline(always)]
    #[allow(clippy::too_many_arguments)]
    pub(in crate::accel) fn leaf_closest<S: Kernels, const KINDS: u32, T: Tally>(
        &self,
        kernels: S,
        first: usize,
        count: usize,
        ray: &Ray,
        ray4: &Ray4,
        nearest: &mut Nearest,
        tally: &mut T,
    ) {
        if KINDS & leaf_kinds::SPHERES != 0 {
            if let Some(blocks) = marked(&self.sphere4, first, count, SPHERE4_LEAF) {
                tally.prims(blocks.len() * LANES);
                blocks_closest(blocks, ray4, nearest);
                return;
            }
        }
        if KINDS & leaf_kinds::CONES != 0 {
            if let Some(blocks) = marked(&self.cone4, first, count, CONE4_LEAF) {
                tally.prims(blocks.len() * LANES);
                blocks_closest(blocks, ray4, nearest);
                return;
            }
        }
        if let Some(blocks) = self.triangle_blocks::<KINDS>(first, count) {
            tally.prims(blocks.len() * LANES);
            self.tri4_closest(kernels, blocks, ray4, nearest);
            return;
        }
        count!(PRIMS, count);
        tally.prims(count);
        for (k, p) in self.primitives[first..first + count].iter().enumerate() {
            if let Some(h) = p.intersect(ray, nearest.limit, &self.data) {
                nearest.offer(h, self.canonical(first + k));
            }
        }
    }

    /// The triangle blocks of a leaf lane whose other kinds (in `KINDS`) were ruled
    /// out: taken without looking at the mark when nothing but triangle blocks is left.
    #[inline(always)]
    pub(in crate::accel) fn triangle_blocks<const KINDS: u32>(
        &self,
        first: usize,
        count: usize,
    ) -> Option<&[Tri4]> {
        if KINDS & leaf_kinds::PRIMITIVES == 0 {
            let blocks = &self.tri4[first..first + (count & !TRI4_LEAF)];
            count!(PRIMS, blocks.len() * LANES);
            return Some(blocks);
        }
        marked(&self.tri4, first, count, TRI4_LEAF)
    }

    /// Offers to `nearest` the hits of `ray4` in triangle blocks.
    #[inline(always)]
    fn tri4_closest<S: Kernels>(&self, kernels: S, blocks: &[Tri4], ray4: &Ray4, nearest: &mut Nearest) {
        // Blocks two at a time (one eight-lane test), the last one alone.
        let mut pairs = blocks.chunks_exact(2);
        for pair in &mut pairs {
            let (t, u, v, mask) = kernels.pair(&pair[0], &pair[1], ray4, nearest.limit);
            if mask != 0 {
                let lane = nearest_lane(&t, mask, |k| nearest.rank(pair[k / LANES].prim[k % LANES]));
                let hit = Hit {
                    t: t[lane],
                    u: u[lane],
                    v: v[lane],
                    part: 0,
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
    pub(in crate::accel) fn stack_of<'a>(&self, buffer: &'a mut Vec<(u32, f32)>) -> &'a mut [(u32, f32)] {
        let need = WIDTH * (self.depth as usize + 1);
        if buffer.len() < need {
            buffer.resize(need, (0, 0.0));
        }
        buffer
    }

    /// This thread's stack for the tree's level.
    #[inline(always)]
    pub(in crate::accel) fn stack_key(&self) -> &'static LocalKey<RefCell<Vec<(u32, f32)>>> {
        match self.level {
            0 => &STACK,
            _ => &PROTOTYPE_STACK,
        }
    }
}
