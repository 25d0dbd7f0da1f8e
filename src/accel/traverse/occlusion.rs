//! The occlusion query (anything on the ray before a distance?), its walk stopping at
//! the first blocker, and the shadow cache that tests last time's blocker first.

use std::cell::Cell;

use super::wide::{Kernels, Portable, RayBoxes};
use crate::accel::bvh::Bvh;
use crate::accel::leaf::pack::{leaf_kinds, marked, with_kinds, CONE4_LEAF, SPHERE4_LEAF};
use crate::accel::leaf::tri4::{Block, Ray4, Tri4, LANES};
use crate::math::{lanes, Ray};

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

impl Bvh {
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
                .is_some_and(|p| p.occludes(ray, t_max, &self.data)),
            hint_bits::TRI4 => self.tri4.get(index).is_some_and(|b| b.any_hit(ray4, t_max)),
            hint_bits::SPHERE4 => self.sphere4.get(index).is_some_and(|b| b.any_hit(ray4, t_max)),
            _ => self.cone4.get(index).is_some_and(|b| b.any_hit(ray4, t_max)),
        }
    }

    /// The primitives that shadow-cache value `hint` names (for tests).
    #[cfg(test)]
    pub(in crate::accel) fn hint_primitives(&self, hint: u32) -> Vec<u32> {
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
    pub(super) fn leaf_any<S: Kernels, const KINDS: u32>(
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
            let k = self.tri4_any(kernels, blocks, ray4, t_max)?;
            return Some(hint_bits::TRI4 | (first + k) as u32);
        }
        count!(PRIMS, count);
        let leaf = &self.primitives[first..first + count];
        let k = leaf.iter().position(|p| p.occludes(ray, t_max, &self.data))?;
        Some(hint_bits::PRIMITIVE | (first + k) as u32)
    }

    /// The position in `blocks` of a triangle block lying on `ray4` with
    /// `0 < t < t_max`.
    #[inline(always)]
    fn tri4_any<S: Kernels>(&self, kernels: S, blocks: &[Tri4], ray4: &Ray4, t_max: f32) -> Option<usize> {
        let mut pairs = blocks.chunks_exact(2);
        for (k, pair) in (&mut pairs).enumerate() {
            let mask = kernels.pair(&pair[0], &pair[1], ray4, t_max).3;
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
    pub(in crate::accel) fn occluder_with<S: Kernels, const KINDS: u32>(
        &self,
        kernels: S,
        ray: &Ray,
        t_max: f32,
    ) -> Option<u32> {
        let unbounded = &self.primitives[self.bounded..];
        // (Tested for emptiness first: see `Bvh::unbounded_closest`.)
        if !unbounded.is_empty() {
            if let Some(i) = unbounded.iter().position(|p| p.occludes(ray, t_max, &self.data)) {
                return Some(hint_bits::PRIMITIVE | (self.bounded + i) as u32);
            }
        }
        if self.wide.is_empty() {
            return None;
        }
        let boxes = RayBoxes::new(ray);
        let ray4 = Ray4::new(ray);
        self.walk_any::<S, KINDS>(kernels, 0, ray, &boxes, &ray4, t_max)
    }

    /// The tree walk of [`Bvh::occluder`] through the subtree of the wide node
    /// `start` (the root: the whole tree); `boxes` and `ray4` are `ray` prepared for
    /// the slab and leaf tests. The packets hand a subtree over to it once only a few
    /// of their rays go on into it.
    #[inline(always)]
    pub(super) fn walk_any<S: Kernels, const KINDS: u32>(
        &self,
        kernels: S,
        start: u32,
        ray: &Ray,
        boxes: &RayBoxes,
        ray4: &Ray4,
        t_max: f32,
    ) -> Option<u32> {
        self.stack_key().with_borrow_mut(|buffer| {
            let stack = self.stack_of(buffer);
            let mut sp = 0usize;
            let mut index = start;
            loop {
                let node = &self.wide[index as usize];
                count!(NODES, 1);
                let mut next = None;
                for lane in lanes(kernels.entered(node, boxes, t_max)) {
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
                    if let Some(blocker) = self.leaf_any::<S, KINDS>(kernels, first, count, ray, ray4, t_max)
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
