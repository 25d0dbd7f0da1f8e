//! Packets of up to eight coherent rays (neighbouring camera rays) traced together:
//! the closest-hit query of eight rays at once ([`Bvh::closest_hits8`]) and its
//! wrappers over slices of rays, and the walk of the tree it shares with the
//! packets' occlusion query (`packet_occlusion`), over a [`PacketQuery`].
//!
//! The packet is split by direction octant (`octant`), and each octant's rays share
//! one walk of the tree: at each node one conservative frustum test of all of them
//! against the eight boxes, then one eight-ray slab test per box it lets through,
//! which gives exactly the rays that enter the box (the single-ray test's arithmetic,
//! lane by lane). Children are visited nearest first by the frustum's entry bound,
//! and a child is skipped once every ray entering it has found something nearer. A
//! subtree left to [`SOLO`] rays or fewer is walked by each of them alone with
//! [`Bvh::closest_hit`]'s traversal, cheaper per node. A triangle leaf entered by
//! [`TOGETHER`] rays or more has each triangle tested against all eight rays at once
//! (`leaf::ray8`), other leaves are tested ray by ray, always with the single-ray
//! arithmetic, so every ray gets the hit `closest_hit` gives it, ties included
//! (`Nearest`).

use std::cell::RefCell;

use wide::f32x8;

use super::nearest::Nearest;
use super::octant::{farthest, Octant, Octants, PacketBoxes, ALL};
use super::wide::{Kernels, Portable, RayBoxes, WIDTH};
use crate::accel::build::sah::MAX_QUERY_DEPTH;
use crate::accel::bvh::Bvh;
use crate::accel::leaf::pack::{leaf_kinds, TRI4_LEAF};
use crate::accel::leaf::ray8::{Ray8, RAYS};
use crate::accel::leaf::tri4::Ray4;
use crate::geometry::Hit;
use crate::math::{lanes, Ray};

/// Rays per packet.
pub const PACKET: usize = RAYS;

/// How the rays of a packet go: the walk a packet query takes.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Coherence {
    /// Neighbouring camera rays, shadow rays towards one light: split by direction
    /// octant, each octant's rays walked together behind one frustum test per node.
    Coherent,
    /// Rays of any directions (a path tracer's bounces): walked together, each box
    /// tested against every ray with its own entry sides, no frustum.
    Mixed,
}

/// A triangle leaf entered by at least this many rays of a packet is tested against
/// all of them at once (eight rays, one triangle) rather than ray by ray.
pub(super) const TOGETHER: u32 = 4;

/// A subtree entered by at most this many of a packet's rays is walked by each of
/// them alone, with the single-ray traversal (cheaper per node than the packet's).
/// Measured on 600 000 small spheres (`nffrt gen balls --size 6`, primary rays,
/// packets against single rays in the same run, medians of three): none handed over
/// 1.31x, at most 2 rays 1.45x, 4 rays 1.18x, 6 rays 1.35x.
pub(super) const SOLO: u32 = 2;

/// A node to visit: its index, the rays entering it (as bits), and a lower bound of
/// their entries.
#[derive(Clone, Copy)]
pub(super) struct Entry {
    pub node: u32,
    pub rays: u32,
    pub near: f32,
}

/// The most entries a packet walk stacks: fewer than [`WIDTH`] per level of the
/// deepest tree queried (a node stacks its children, the walk goes on
/// with one of them and comes back to a level only once everything deeper is done).
const STACK_ENTRIES: usize = WIDTH * (MAX_QUERY_DEPTH as usize + 1);

/// A packet walk's fixed-size stack.
pub(super) struct PacketStack(pub [Entry; STACK_ENTRIES]);

thread_local! {
    /// Each thread's packet stack, reused by its queries (never grown: its size
    /// bounds every tree's depth).
    pub(super) static PACKET_STACK: RefCell<PacketStack> = const {
        RefCell::new(PacketStack([Entry { node: 0, rays: 0, near: 0.0 }; STACK_ENTRIES]))
    };
}

/// Ray `k` of `rays` prepared for the single-ray leaf test (made when needed rather
/// than for every ray up front: camera packets often go through the tree and their
/// triangle leaves eight rays at a time).
#[inline(always)]
pub(super) fn single_ray(rays: &Ray8, k: usize) -> (Ray, Ray4) {
    let ray = rays.ray(k);
    let ray4 = Ray4::with_sheared(&ray, rays.sheared(k));
    (ray, ray4)
}

/// Insertion sort of stack entries by decreasing entry (at most [`WIDTH`] of them),
/// so that the nearest is popped first.
#[inline(always)]
pub(super) fn sort_descending(v: &mut [Entry]) {
    for i in 1..v.len() {
        let mut j = i;
        while j > 0 && v[j - 1].near < v[j].near {
            v.swap(j - 1, j);
            j -= 1;
        }
    }
}

/// The rays (as bits) still looking past `t`: those with `t < limits[k]`.
#[inline(always)]
fn looking_past(t: f32, limits: &[f32; RAYS]) -> u32 {
    f32x8::splat(t).simd_lt(f32x8::from(*limits)).to_bitmask()
}

/// A packet query under way, as the packet walk (`Bvh::walk_packet`) sees it: the
/// closest hit ([`Closest`]) or occlusion (`packet_occlusion::Shadow`). The walk is
/// compiled for each, the choices below made at compile time.
pub(super) trait PacketQuery {
    /// True for a query that stops at each ray's first hit (occlusion): the walk drops
    /// the rays a leaf is done with and stacks children as they come (no distance
    /// orders them or culls them later). False for the nearest hit: children are
    /// stacked nearest on top with their entry bounds.
    const ANY_HIT: bool;

    /// Each ray's distance limit: a box entered beyond it is not entered.
    fn limits(&self) -> &[f32; RAYS];

    /// Of the rays `rays` of an entry stacked with the entry bound `near`, those
    /// still to walk it.
    fn looking(&self, rays: u32, near: f32) -> u32;

    /// Tests the leaf lane (`first`, `count`, as in `Bvh::leaf_closest`) against the
    /// rays `entering` (at least one): the rays it is done with (`ANY_HIT` only).
    fn leaf<S: Kernels>(&mut self, bvh: &Bvh, kernels: S, first: usize, count: usize, entering: u32) -> u32;

    /// Walks the subtree of the wide node `start` with each of the rays `rays` alone.
    fn solo<S: Kernels>(&mut self, bvh: &Bvh, kernels: S, start: u32, rays: u32);
}

/// A closest-hit packet query under way.
struct Closest<'a> {
    rays: &'a Ray8,
    nearest: [Nearest<'a>; PACKET],
    /// Each ray's `nearest[k].limit`, side by side for the vector tests.
    limits: [f32; PACKET],
}

impl PacketQuery for Closest<'_> {
    const ANY_HIT: bool = false;

    #[inline(always)]
    fn limits(&self) -> &[f32; RAYS] {
        &self.limits
    }

    /// The rays that have found nothing nearer than `near`.
    #[inline(always)]
    fn looking(&self, rays: u32, near: f32) -> u32 {
        rays & looking_past(near, &self.limits)
    }

    #[inline(always)]
    fn leaf<S: Kernels>(&mut self, bvh: &Bvh, kernels: S, first: usize, count: usize, entering: u32) -> u32 {
        bvh.leaf_closest8(kernels, first, count, entering, self);
        0
    }

    #[inline(always)]
    fn solo<S: Kernels>(&mut self, bvh: &Bvh, kernels: S, start: u32, rays: u32) {
        bvh.solo_closest(kernels, start, rays, self);
    }
}

impl Bvh {
    /// [`Bvh::closest_hit`] for every ray of `rays`, [`PACKET`] consecutive rays at a
    /// time: `out[k]` receives the nearest hit of `rays[k]` with `0 < t < t_max`, the
    /// very hit `closest_hit` gives it (ties included). The entry point for streams
    /// of coherent rays, such as a row of camera rays, or one sample of each pixel of
    /// a row: neighbours in the slice should be neighbours in the image.
    ///
    /// # Panics
    /// If `out` has another length than `rays`.
    pub fn closest_hits(&self, rays: &[Ray], t_max: f32, out: &mut [Option<(Hit, u32)>]) {
        assert_eq!(out.len(), rays.len(), "one result per ray");
        for (packet, out) in rays.chunks(PACKET).zip(out.chunks_mut(PACKET)) {
            self.closest_hit_packet(packet, t_max, out);
        }
    }

    /// [`Bvh::closest_hit`] for up to [`PACKET`] rays at once: `out[k]` receives the
    /// nearest hit of `rays[k]` with `0 < t < t_max`. Fastest on coherent rays.
    ///
    /// # Panics
    /// If there are more than [`PACKET`] rays or `out` has another length.
    pub fn closest_hit_packet(&self, rays: &[Ray], t_max: f32, out: &mut [Option<(Hit, u32)>]) {
        #[cfg(target_arch = "x86_64")]
        if let Some(avx) = self.avx {
            return self.closest_hit_packet_by(
                |r, a, o| avx.closest_hits8(self, r, t_max, a, Coherence::Coherent, o),
                rays,
                out,
            );
        }
        self.closest_hit_packet_with(Portable, rays, t_max, out)
    }

    /// [`Bvh::closest_hit_packet`] with the kernels `kernels` (see `closest_hit_with`).
    pub(in crate::accel) fn closest_hit_packet_with<S: Kernels>(
        &self,
        kernels: S,
        rays: &[Ray],
        t_max: f32,
        out: &mut [Option<(Hit, u32)>],
    ) {
        self.closest_hit_packet_by(
            |r, a, o| self.closest_hits8_with(kernels, r, t_max, a, Coherence::Coherent, o),
            rays,
            out,
        )
    }

    /// [`Bvh::closest_hit_packet`] through `hits8`, a closest-hit query of a
    /// [`Ray8`] and the mask of its rays.
    #[inline(always)]
    fn closest_hit_packet_by(
        &self,
        hits8: impl FnOnce(&Ray8, u32, &mut [Option<(Hit, u32)>; PACKET]),
        rays: &[Ray],
        out: &mut [Option<(Hit, u32)>],
    ) {
        let n = rays.len();
        assert!(n <= PACKET, "at most {PACKET} rays per packet");
        assert_eq!(out.len(), n, "one result per ray");
        if n == 0 {
            return;
        }
        let mut all = [None; PACKET];
        hits8(&Ray8::new(rays), (1 << n) - 1, &mut all);
        out.copy_from_slice(&all[..n]);
    }

    /// [`Bvh::closest_hit`] for the rays of `rays` whose bits are set in `active`:
    /// `out[k]` receives the nearest hit of ray `k` with `0 < t < t_max`, the very
    /// hit `closest_hit` gives it (ties included); `None` for the other lanes. The
    /// walk suits rays as `coherence` says they go ([`Coherence`]).
    pub fn closest_hits8(
        &self,
        rays: &Ray8,
        t_max: f32,
        active: u32,
        coherence: Coherence,
        out: &mut [Option<(Hit, u32)>; PACKET],
    ) {
        #[cfg(target_arch = "x86_64")]
        if let Some(avx) = self.avx {
            return avx.closest_hits8(self, rays, t_max, active, coherence, out);
        }
        self.closest_hits8_with(Portable, rays, t_max, active, coherence, out)
    }

    /// [`Bvh::closest_hits8`] with the kernels `kernels` (see `closest_hit_with`).
    #[inline(always)]
    pub(in crate::accel) fn closest_hits8_with<S: Kernels>(
        &self,
        kernels: S,
        rays: &Ray8,
        t_max: f32,
        active: u32,
        coherence: Coherence,
        out: &mut [Option<(Hit, u32)>; PACKET],
    ) {
        *out = [None; PACKET];
        let active = active & ALL;
        if active == 0 {
            return;
        }
        let mut q = Closest {
            rays,
            nearest: [Nearest::new(t_max, &self.ranks); PACKET],
            limits: [t_max; PACKET],
        };
        self.unbounded_closest8(&mut q, active);
        self.walk_packet(kernels, rays, &mut q, active, coherence);
        for (k, (out, nearest)) in out.iter_mut().zip(&q.nearest).enumerate() {
            if active >> k & 1 != 0 {
                *out = nearest.best;
            }
        }
    }

    /// The tree walks of the rays `active` of `rays` for the query `q`: an octant at
    /// a time for coherent rays, or all together, each box tested against every ray
    /// with its own entry sides ([`Coherence::Mixed`]).
    #[inline(always)]
    pub(super) fn walk_packet<S: Kernels, Q: PacketQuery>(
        &self,
        kernels: S,
        rays: &Ray8,
        q: &mut Q,
        active: u32,
        coherence: Coherence,
    ) {
        if active == 0 || self.wide.is_empty() {
            return;
        }
        let boxes = PacketBoxes::new(rays);
        PACKET_STACK.with_borrow_mut(|stack| {
            if coherence == Coherence::Mixed {
                let all = Octant::mixed(&boxes, active);
                return self.walk_octant(kernels, &boxes, &all, q, &mut stack.0);
            }
            let mut octants = Octants::new(&boxes, active);
            while let Some(octant) = octants.next(&boxes) {
                self.walk_octant(kernels, &boxes, &octant, q, &mut stack.0);
            }
        });
    }

    /// The unbounded primitives (planes) against the rays `active` of `q`.
    #[inline(always)]
    fn unbounded_closest8(&self, q: &mut Closest, active: u32) {
        let unbounded = &self.primitives[self.bounded..];
        // (Tested for emptiness first: see `Bvh::unbounded_closest`.)
        if unbounded.is_empty() {
            return;
        }
        for k in lanes(active) {
            let ray = q.rays.ray(k);
            for (i, p) in unbounded.iter().enumerate() {
                if let Some(h) = p.intersect(&ray, q.nearest[k].limit, &self.data) {
                    q.nearest[k].offer(h, (self.bounded + i) as u32);
                }
            }
            q.limits[k] = q.nearest[k].limit;
        }
    }

    /// The tree walk of the rays of `octant` (whose boxes are in `boxes`) for the
    /// query `q`: at each node one frustum test of them all against the eight boxes,
    /// then one eight-ray test of each box it lets through; leaves tested as they
    /// are entered, inner children stacked (the nearest on top when `q` looks for
    /// the nearest hit).
    #[inline(always)]
    fn walk_octant<S: Kernels, Q: PacketQuery>(
        &self,
        kernels: S,
        boxes: &PacketBoxes,
        octant: &Octant,
        q: &mut Q,
        stack: &mut [Entry],
    ) {
        let mut sp = 0usize;
        let mut index = 0u32;
        let mut active = octant.lanes;
        loop {
            let node = &self.wide[index as usize];
            count!(NODES, 1);
            let (near, through) = match &octant.frustum {
                Some(f) => kernels.frustum(node, f, farthest(q.limits(), active)),
                None => ([0.0; WIDTH], ALL),
            };
            let base = sp;
            for lane in lanes(through) {
                let (entering, entry) = match &octant.mixed {
                    None => (
                        kernels.entered8(node, lane, boxes, &octant.near, q.limits()),
                        near[lane],
                    ),
                    Some(negative) => kernels.entered8_mixed(node, lane, boxes, negative, q.limits()),
                };
                let entering = entering & active;
                if entering == 0 {
                    continue;
                }
                let count = node.count[lane] as usize;
                if count == 0 {
                    stack[sp] = Entry {
                        node: node.child[lane],
                        rays: entering,
                        near: if Q::ANY_HIT { 0.0 } else { entry },
                    };
                    sp += 1;
                    continue;
                }
                let done = q.leaf(self, kernels, node.child[lane] as usize, count, entering);
                if Q::ANY_HIT {
                    active &= !done;
                    if active == 0 {
                        // (Entries stacked for these rays only are skipped below.)
                        break;
                    }
                }
            }
            if !Q::ANY_HIT {
                sort_descending(&mut stack[base..sp]);
            }
            // The top entry next, with those of its rays still looking (for the
            // nearest hit: those that have found nothing nearer than its bound); an
            // entry left to [`SOLO`] rays or fewer is walked by each of them alone.
            loop {
                if sp == 0 {
                    return;
                }
                sp -= 1;
                let e = stack[sp];
                let entering = q.looking(e.rays, e.near);
                if entering == 0 {
                    continue;
                }
                if entering.count_ones() <= SOLO {
                    q.solo(self, kernels, e.node, entering);
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
    fn solo_closest<S: Kernels>(&self, kernels: S, start: u32, rays: u32, q: &mut Closest) {
        for k in lanes(rays) {
            let (ray, ray4) = single_ray(q.rays, k);
            self.walk_closest::<S, { leaf_kinds::ALL }, ()>(
                kernels,
                start,
                &ray,
                &RayBoxes::new(&ray),
                &ray4,
                &mut q.nearest[k],
                &mut (),
            );
            q.limits[k] = q.nearest[k].limit;
        }
    }

    /// The leaf lane (`first`, `count`, as in `Bvh::leaf_closest`) against the rays
    /// `entering` of `q`.
    #[inline(always)]
    fn leaf_closest8<S: Kernels>(
        &self,
        kernels: S,
        first: usize,
        count: usize,
        entering: u32,
        q: &mut Closest,
    ) {
        if count & TRI4_LEAF != 0 && entering.count_ones() >= TOGETHER {
            // Each triangle against all the packet's rays at once.
            for block in &self.tri4[first..first + (count & !TRI4_LEAF)] {
                for (j, &prim) in block.prim.iter().enumerate() {
                    if prim == u32::MAX {
                        break;
                    }
                    let (t, u, v, hit) = kernels.hits8(block, j, q.rays, &q.limits);
                    for k in lanes(hit & entering) {
                        q.nearest[k].offer(
                            Hit {
                                t: t[k],
                                u: u[k],
                                v: v[k],
                                part: 0,
                            },
                            prim,
                        );
                        q.limits[k] = q.nearest[k].limit;
                    }
                }
            }
            return;
        }
        for k in lanes(entering) {
            let (ray, ray4) = single_ray(q.rays, k);
            self.leaf_closest::<S, { leaf_kinds::ALL }, ()>(
                kernels,
                first,
                count,
                &ray,
                &ray4,
                &mut q.nearest[k],
                &mut (),
            );
            q.limits[k] = q.nearest[k].limit;
        }
    }
}
