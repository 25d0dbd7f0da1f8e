//! The occlusion query of eight rays at once ([`Bvh::occluded8`]): the packet walk of
//! `packet` (octants, one frustum test per node, one eight-ray slab test per box it
//! lets through) stopping for each ray at its first blocker, and for the packet once
//! every ray is blocked.

use super::octant::ALL;
use super::packet::{single_ray, Coherence, PacketQuery, TOGETHER};
use super::wide::{Kernels, Portable, RayBoxes};
use crate::accel::bvh::Bvh;
use crate::accel::leaf::pack::{leaf_kinds, TRI4_LEAF};
use crate::accel::leaf::ray8::{Ray8, RAYS};
use crate::math::lanes;

/// An occlusion packet query under way.
struct Shadow<'a> {
    rays: &'a Ray8,
    t_max: &'a [f32; RAYS],
    /// The rays found blocked, as bits.
    blocked: u32,
}

impl PacketQuery for Shadow<'_> {
    const ANY_HIT: bool = true;

    #[inline(always)]
    fn limits(&self) -> &[f32; RAYS] {
        self.t_max
    }

    /// The rays not found blocked yet.
    #[inline(always)]
    fn looking(&self, rays: u32, _near: f32) -> u32 {
        rays & !self.blocked
    }

    /// The rays the leaf blocks, recorded.
    #[inline(always)]
    fn leaf<S: Kernels>(&mut self, bvh: &Bvh, kernels: S, first: usize, count: usize, entering: u32) -> u32 {
        let blocked = bvh.leaf_any8(kernels, first, count, entering, self);
        self.blocked |= blocked;
        blocked
    }

    #[inline(always)]
    fn solo<S: Kernels>(&mut self, bvh: &Bvh, kernels: S, start: u32, rays: u32) {
        bvh.solo_any(kernels, start, rays, self);
    }
}

impl Bvh {
    /// [`Bvh::occluded`] for the rays of `rays` whose bits are set in `active`: the
    /// bits of those with anything on them with `0 < t < t_max[k]` (ray by ray what
    /// `occluded` answers). The walk suits rays as `coherence` says they go.
    pub fn occluded8(&self, rays: &Ray8, t_max: &[f32; 8], active: u32, coherence: Coherence) -> u32 {
        #[cfg(target_arch = "x86_64")]
        if let Some(avx) = self.avx {
            return avx.occluded8(self, rays, t_max, active, coherence);
        }
        self.occluded8_with(Portable, rays, t_max, active, coherence)
    }

    /// [`Bvh::occluded8`] with the kernels `kernels` (see `closest_hit_with`).
    #[inline(always)]
    pub(in crate::accel) fn occluded8_with<S: Kernels>(
        &self,
        kernels: S,
        rays: &Ray8,
        t_max: &[f32; RAYS],
        active: u32,
        coherence: Coherence,
    ) -> u32 {
        let active = active & ALL;
        if active == 0 {
            return 0;
        }
        let mut q = Shadow {
            rays,
            t_max,
            blocked: 0,
        };
        self.unbounded_any8(&mut q, active);
        let left = active & !q.blocked;
        self.walk_packet(kernels, rays, &mut q, left, coherence);
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
            if unbounded.iter().any(|p| p.occludes(&ray, q.t_max[k], &self.data)) {
                q.blocked |= 1 << k;
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
