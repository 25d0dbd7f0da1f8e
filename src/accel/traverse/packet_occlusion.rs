//! The occlusion query of eight rays at once ([`Bvh::occluded8`]): the packet walk of
//! `packet` (octants, one frustum test per node, one eight-ray slab test per box it
//! lets through) stopping for each ray at its first blocker, and for the packet once
//! every ray is blocked.

use super::octant::{farthest, Octant, Octants, PacketBoxes, ALL};
use super::packet::{single_ray, Entry, PACKET_STACK, SOLO, TOGETHER};
use super::wide::RayBoxes;
use super::wide::{Kernels, Portable};
use crate::accel::bvh::Bvh;
use crate::accel::leaf::pack::{leaf_kinds, TRI4_LEAF};
use crate::accel::leaf::ray8::{Ray8, RAYS};
use crate::math::lanes;

/// An occlusion packet query under way.
struct Shadow<'a> {
    rays: &'a Ray8,
    boxes: PacketBoxes,
    t_max: &'a [f32; RAYS],
    /// The rays found blocked, as bits.
    blocked: u32,
}

impl Bvh {
    /// [`Bvh::occluded`] for the rays of `rays` whose bits are set in `active`: the
    /// bits of those with anything on them with `0 < t < t_max[k]` (ray by ray what
    /// `occluded` answers).
    pub fn occluded8(&self, rays: &Ray8, t_max: &[f32; 8], active: u32) -> u32 {
        #[cfg(target_arch = "x86_64")]
        if let Some(avx) = self.avx {
            return avx.occluded8(self, rays, t_max, active);
        }
        self.occluded8_with(Portable, rays, t_max, active)
    }

    /// [`Bvh::occluded8`] with the kernels `kernels` (see `closest_hit_with`).
    #[inline(always)]
    pub(in crate::accel) fn occluded8_with<S: Kernels>(
        &self,
        kernels: S,
        rays: &Ray8,
        t_max: &[f32; RAYS],
        active: u32,
    ) -> u32 {
        let active = active & ALL;
        if active == 0 {
            return 0;
        }
        let mut q = Shadow {
            rays,
            boxes: PacketBoxes::new(rays),
            t_max,
            blocked: 0,
        };
        self.unbounded_any8(&mut q, active);
        let left = active & !q.blocked;
        if left != 0 && !self.wide.is_empty() {
            let mut octants = Octants::new(&q.boxes, left);
            PACKET_STACK.with_borrow_mut(|stack| {
                while let Some(octant) = octants.next(&q.boxes) {
                    self.walk_octant_any(kernels, &octant, &mut q, &mut stack.0);
                }
            });
        }
        q.blocked
    }

    /// The unbounded primitives (planes) against the rays `active` of `q`.
    #[inline(always)]
    fn unbounded_any8(&self, q: &mut Shadow, active: u32) {
        let unbounded = &self.primitives[self.bounded..];
        if unbounded.is_empty() {
            return;
        }
        for k in lanes(active) {
            let ray = q.rays.ray(k);
            if unbounded
                .iter()
                .any(|p| p.intersect(&ray, q.t_max[k], &self.data).is_some())
            {
                q.blocked |= 1 << k;
            }
        }
    }

    /// The tree walk of the rays of `octant`, until each is blocked or has seen
    /// every box it enters.
    #[inline(always)]
    fn walk_octant_any<S: Kernels>(&self, kernels: S, octant: &Octant, q: &mut Shadow, stack: &mut [Entry]) {
        let mut sp = 0usize;
        let mut index = 0u32;
        let mut active = octant.lanes;
        loop {
            let node = &self.wide[index as usize];
            count!(NODES, 1);
            let through = match &octant.frustum {
                Some(f) => kernels.frustum(node, f, farthest(q.t_max, active)).1,
                None => ALL,
            };
            for lane in lanes(through) {
                let entering = kernels.entered8(node, lane, &q.boxes, &octant.near, q.t_max) & active;
                if entering == 0 {
                    continue;
                }
                let count = node.count[lane] as usize;
                if count == 0 {
                    stack[sp] = Entry {
                        node: node.child[lane],
                        rays: entering,
                        near: 0.0,
                    };
                    sp += 1;
                    continue;
                }
                let blocked = self.leaf_any8(kernels, node.child[lane] as usize, count, entering, q);
                q.blocked |= blocked;
                active &= !blocked;
                if active == 0 {
                    // (Entries stacked for these rays only are skipped below.)
                    break;
                }
            }
            loop {
                if sp == 0 {
                    return;
                }
                sp -= 1;
                let e = stack[sp];
                let entering = e.rays & !q.blocked;
                if entering == 0 {
                    continue;
                }
                if entering.count_ones() <= SOLO {
                    self.solo_any(kernels, e.node, entering, q);
                    continue;
                }
                index = e.node;
                active = entering;
                break;
            }
        }
    }

    /// The subtree of wide node `start` walked by each of the rays `rays` alone.
    #[inline(always)]
    fn solo_any<S: Kernels>(&self, kernels: S, start: u32, rays: u32, q: &mut Shadow) {
        for k in lanes(rays) {
            let (ray, ray4) = single_ray(q.rays, k);
            let boxes = RayBoxes::new(&ray);
            let found =
                self.walk_any::<S, { leaf_kinds::ALL }>(kernels, start, &ray, &boxes, &ray4, q.t_max[k]);
            if found.is_some() {
                q.blocked |= 1 << k;
            }
        }
    }

    /// The rays of `entering` (as bits) that the leaf lane (`first`, `count`, as in
    /// `Bvh::leaf_closest`) blocks.
    #[inline(always)]
    fn leaf_any8<S: Kernels>(
        &self,
        kernels: S,
        first: usize,
        count: usize,
        entering: u32,
        q: &mut Shadow,
    ) -> u32 {
        if count & TRI4_LEAF != 0 && entering.count_ones() >= TOGETHER {
            // Each triangle against all the packet's rays at once.
            let mut left = entering;
            for block in &self.tri4[first..first + (count & !TRI4_LEAF)] {
                for (j, &prim) in block.prim.iter().enumerate() {
                    if prim == u32::MAX {
                        break;
                    }
                    left &= !kernels.hits8(block, j, q.rays, q.t_max).3;
                    if left == 0 {
                        return entering;
                    }
                }
            }
            return entering & !left;
        }
        let mut blocked = 0;
        for k in lanes(entering) {
            let (ray, ray4) = single_ray(q.rays, k);
            let found =
                self.leaf_any::<S, { leaf_kinds::ALL }>(kernels, first, count, &ray, &ray4, q.t_max[k]);
            if found.is_some() {
                blocked |= 1 << k;
            }
        }
        blocked
    }
}
