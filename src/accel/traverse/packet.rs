//! Packets of up to eight coherent rays (neighbouring camera rays) traced together.
//!
//! The packet shares one walk of the tree: one stack, one fetch of each node, one
//! ordering decision per node. When its rays' directions agree in sign on every axis
//! (neighbouring camera rays nearly always do), a node's eight boxes are tested once
//! for the whole packet with interval arithmetic over the rays' origins and inverse
//! directions (Wald, Boulos and Shirley 2007, "Ray tracing deformable scenes using
//! dynamic bounding volume hierarchies"): a conservative test, since correctly
//! rounded arithmetic is monotonic, so a box any ray enters is entered. Otherwise,
//! and below boxes smaller than half the packet's footprint (where the rays go
//! separate ways and the interval test would let every ray into every box any of them
//! enters: 600 000 spheres, each a few pixels wide, ran at half the single-ray speed),
//! each ray runs the slab test of [`Bvh::closest_hit`] and the walk follows the
//! union. A subtree left to six rays or fewer is walked by each of them alone with
//! [`Bvh::closest_hit`]'s traversal, cheaper per node (among 600 000 spheres the
//! rays soon part: packets +16 %). A triangle leaf entered by four rays or more has
//! each triangle tested against all eight rays at once (`leaf::ray8`), other leaves
//! are tested ray by ray, always with the single-ray arithmetic, so every ray gets
//! the hit `closest_hit` gives it, ties included (`Nearest`).

use std::cell::RefCell;

use wide::f32x8;

use super::nearest::Nearest;
use super::single::sort_descending;
use super::wide::{Kernels, Node8, Portable, RayBoxes, FAR_SCALE, MAX, MIN, WIDTH};
use crate::accel::bvh::Bvh;
use crate::accel::leaf::pack::{leaf_kinds, TRI4_LEAF};
use crate::accel::leaf::ray8::{Ray8, RAYS};
use crate::accel::leaf::tri4::Ray4;
use crate::geometry::Hit;
use crate::math::{Ray, TINY_DIR};

/// Rays per packet.
pub const PACKET: usize = 8;

/// A triangle leaf entered by at least this many rays of a packet is tested against
/// all of them at once (eight rays, one triangle) rather than ray by ray.
const TOGETHER: u32 = 4;

/// Boxes at least this many times the packet's footprint get the interval test.
const COHERENCE: f32 = 0.5;

/// A subtree entered by at most this many of a packet's rays is walked by each of
/// them alone, with the single-ray traversal (cheaper per node than the packet's).
/// Measured, 8-ray packets on primary rays against none handed over: at most 1 ray
/// +2 % on 600 000 spheres, 2 rays +5 %, 4 rays +11 %, 6 rays +16 % (mount_very_high
/// +3 %, the SPD scenes within 1.5 %), 7 rays +20 % but teapot and gears −3 %.
const SOLO: u32 = 6;

/// A stack entry: a node, the rays entering it, and the nearest of their entries.
#[derive(Clone, Copy)]
struct Entry {
    node: u32,
    rays: u32,
    near: f32,
    /// Whether the node's boxes are tested with the interval test.
    coherent: bool,
}

/// Per axis, the range of a packet's origins and inverse directions, all of one
/// sign (`negative`).
struct Interval {
    origin: [[f32; 2]; 3],
    inv: [[f32; 2]; 3],
    negative: [bool; 3],
    /// The spread of the origins and of the (unit) directions, largest over the axes:
    /// at distance t the rays lie within about `spread[0] + t · spread[1]` of each
    /// other.
    spread: [f32; 2],
}

impl Interval {
    /// The interval of `rays`, if their directions agree in sign on every axis.
    #[inline(always)]
    fn of(rays: &Ray8) -> Option<Interval> {
        let mut iv = Interval {
            origin: [[0.0; 2]; 3],
            inv: [[0.0; 2]; 3],
            negative: [false; 3],
            spread: [0.0; 2],
        };
        let range = |v: &[f32; RAYS]| {
            let lo = v.iter().fold(f32::INFINITY, |a, &b| a.min(b));
            let hi = v.iter().fold(f32::NEG_INFINITY, |a, &b| a.max(b));
            [lo, hi]
        };
        for axis in 0..3 {
            let negative = f32x8::from(rays.inv[axis]).simd_lt(f32x8::ZERO).to_bitmask();
            // Rays parallel to an axis take the ray-by-ray test (see `RayBoxes`).
            let parallel = f32x8::from(rays.dir[axis])
                .abs()
                .simd_lt(f32x8::splat(TINY_DIR))
                .to_bitmask();
            if (negative != 0 && negative != (1 << RAYS) - 1) || parallel != 0 {
                return None;
            }
            iv.negative[axis] = negative != 0;
            iv.origin[axis] = range(&rays.origin[axis]);
            iv.inv[axis] = range(&rays.inv[axis]);
            // The directions' range from the inverses' (same sign, so 1/x is monotonic).
            let [inv_lo, inv_hi] = iv.inv[axis];
            iv.spread[0] = iv.spread[0].max(iv.origin[axis][1] - iv.origin[axis][0]);
            iv.spread[1] = iv.spread[1].max((1.0 / inv_lo - 1.0 / inv_hi).abs());
        }
        Some(iv)
    }

    /// Whether a box of extent `size` entered at `t` is still large against the
    /// packet's footprint there, so that one interval test beats one per ray (in
    /// boxes much smaller than the footprint the rays go separate ways, and the
    /// interval test would let every ray into every box any of them enters).
    #[inline(always)]
    fn worth_it(&self, size: f32, t: f32) -> bool {
        size >= COHERENCE * (self.spread[0] + t * self.spread[1])
    }

    /// A lower bound of every ray's entry into each lane's box and the lanes some ray
    /// may enter before `t_limit` (as bits).
    ///
    /// Per axis, with `t = (plane − o) · inv`: for positive directions the entry is
    /// least for the greatest origin, the exit greatest for the least origin, and the
    /// other way round for negative ones; the two inverse directions bound the rest.
    #[inline(always)]
    fn entries(&self, node: &Node8, t_limit: f32) -> ([f32; WIDTH], u32) {
        let mut near = f32x8::ZERO;
        let mut far = f32x8::splat(t_limit);
        for axis in 0..3 {
            let [o_lo, o_hi] = self.origin[axis];
            let [inv_lo, inv_hi] = self.inv[axis].map(f32x8::splat);
            let (entry, exit, o_entry, o_exit) = if self.negative[axis] {
                (&node.bounds[MAX][axis], &node.bounds[MIN][axis], o_lo, o_hi)
            } else {
                (&node.bounds[MIN][axis], &node.bounds[MAX][axis], o_hi, o_lo)
            };
            let d_entry = f32x8::from(*entry) - o_entry;
            let d_exit = f32x8::from(*exit) - o_exit;
            near = near.fast_max((d_entry * inv_lo).fast_min(d_entry * inv_hi));
            far = far.fast_min((d_exit * inv_lo).fast_max(d_exit * inv_hi));
        }
        // The exit stretched as `Node8::entries` stretches each ray's: after the
        // same monotonic operations, so the test stays conservative. (The exit
        // starts at `t_limit`, so no lane entered past it is kept either.)
        let hit = near.simd_le(far * f32x8::splat(FAR_SCALE));
        (near.to_array(), hit.to_bitmask())
    }
}

/// The packet's rays prepared for the single-ray tests (`RayBoxes` for the slab test,
/// `Ray4` for the leaf blocks), each only once some test needs it: camera packets
/// often go through the tree on the interval test alone and test their leaves eight
/// rays at a time, and preparing all eight rays up front cost tetra's packets 12 % of
/// their instructions.
struct SingleRays {
    boxes: [RayBoxes; PACKET],
    ray4: [Ray4; PACKET],
    /// The rays prepared, as bits.
    ready: u32,
}

impl SingleRays {
    /// Ray 0 prepared (the others hold copies of it until they are); `rays8` holds
    /// the rays' triangle test frames.
    #[inline(always)]
    fn new(rays: &[Ray], rays8: &Ray8) -> SingleRays {
        SingleRays {
            boxes: [RayBoxes::new(&rays[0]); PACKET],
            ray4: [Ray4::with_sheared(&rays[0], rays8.sheared(0)); PACKET],
            ready: 1,
        }
    }

    /// Prepares the rays of `mask` (bits of indices into `rays`) not prepared yet.
    #[inline(always)]
    fn prepare(&mut self, rays: &[Ray], rays8: &Ray8, mask: u32) {
        let mut todo = mask & !self.ready;
        self.ready |= mask;
        while todo != 0 {
            let k = todo.trailing_zeros() as usize;
            todo &= todo - 1;
            self.boxes[k] = RayBoxes::new(&rays[k]);
            self.ray4[k] = Ray4::with_sheared(&rays[k], rays8.sheared(k));
        }
    }
}

thread_local! {
    /// Each thread's packet traversal stack, reused across queries.
    static PACKET_STACK: RefCell<Vec<Entry>> = RefCell::new(Vec::with_capacity(256));
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
            return avx.closest_hit_packet(self, rays, t_max, out);
        }
        self.closest_hit_packet_with(Portable, rays, t_max, out)
    }

    /// [`Bvh::closest_hit_packet`] with the slab test `kernels` (see `closest_hit_with`).
    #[inline(always)]
    pub(in crate::accel) fn closest_hit_packet_with<S: Kernels>(
        &self,
        kernels: S,
        rays: &[Ray],
        t_max: f32,
        out: &mut [Option<(Hit, u32)>],
    ) {
        let n = rays.len();
        assert!(n <= PACKET, "at most {PACKET} rays per packet");
        assert_eq!(out.len(), n, "one result per ray");
        let mut nearest = [Nearest::new(t_max); PACKET];
        let unbounded = &self.primitives[self.bounded..];
        // (Tested for emptiness first: see `Bvh::unbounded_closest`.)
        for (k, ray) in rays.iter().enumerate().filter(|_| !unbounded.is_empty()) {
            for (i, p) in unbounded.iter().enumerate() {
                if let Some(h) = p.intersect(ray, nearest[k].limit, &self.data) {
                    nearest[k].offer(h, (self.bounded + i) as u32);
                }
            }
        }
        if !self.wide.is_empty() && n > 0 {
            self.walk_packet(kernels, rays, &mut nearest);
        }
        for (o, near) in out.iter_mut().zip(&nearest) {
            *o = near.best;
        }
    }

    /// The tree walk of [`Bvh::closest_hit_packet`] for `rays` (one to [`PACKET`]),
    /// improving `nearest[k]` for ray `k`.
    #[inline(always)]
    fn walk_packet<S: Kernels>(&self, kernels: S, rays: &[Ray], nearest: &mut [Nearest; PACKET]) {
        let n = rays.len();
        let rays8 = Ray8::new(rays);
        let interval = Interval::of(&rays8);
        let mut single = SingleRays::new(rays, &rays8);
        // Each ray's `nearest[k].limit`, side by side for the vector tests.
        let mut limits = nearest.map(|n| n.limit);
        PACKET_STACK.with_borrow_mut(|stack| {
            stack.clear();
            let mut index = 0u32;
            let mut active = (1u32 << n) - 1;
            let mut coherent = interval.is_some();
            loop {
                let node = &self.wide[index as usize];
                // The rays entering each child, and the nearest of their entries.
                let mut lane_rays = [0u32; WIDTH];
                let mut lane_near = [f32::INFINITY; WIDTH];
                if let Some(iv) = interval.as_ref().filter(|_| coherent) {
                    let t_limit = (0..PACKET)
                        .filter(|k| active & (1 << k) != 0)
                        .fold(0.0f32, |t, k| t.max(limits[k]));
                    let (near, mut mask) = iv.entries(node, t_limit);
                    // (Read only in the lanes entered.)
                    lane_near = near;
                    while mask != 0 {
                        let lane = mask.trailing_zeros() as usize;
                        mask &= mask - 1;
                        lane_rays[lane] = active;
                    }
                }
                // (`coherent` holds only with an interval.)
                let mut left = if coherent { 0 } else { active };
                single.prepare(rays, &rays8, left);
                let boxes = &single.boxes;
                while left != 0 {
                    let k = left.trailing_zeros() as usize;
                    left &= left - 1;
                    let limit = limits[k];
                    let (t, mut mask) = kernels.entries(node, &boxes[k], limit);
                    while mask != 0 {
                        let lane = mask.trailing_zeros() as usize;
                        mask &= mask - 1;
                        lane_rays[lane] |= 1 << k;
                        lane_near[lane] = lane_near[lane].min(t[lane]);
                    }
                }
                let mut inner = [(0u32, 0.0f32); WIDTH];
                let mut inner_rays = [0u32; WIDTH];
                let mut inner_coherent = [false; WIDTH];
                let mut n_inner = 0;
                for lane in 0..WIDTH {
                    let entering = lane_rays[lane];
                    if entering == 0 {
                        continue;
                    }
                    let count = node.count[lane] as usize;
                    if count == 0 {
                        // The child's index stays with its rays through the sort.
                        inner[n_inner] = (lane as u32, lane_near[lane]);
                        inner_rays[lane] = entering;
                        inner_coherent[lane] = match &interval {
                            Some(iv) if coherent => {
                                let size = (0..3)
                                    .map(|a| node.bounds[MAX][a][lane] - node.bounds[MIN][a][lane])
                                    .fold(0.0f32, f32::max);
                                iv.worth_it(size, lane_near[lane])
                            }
                            _ => false,
                        };
                        n_inner += 1;
                        continue;
                    }
                    let first = node.child[lane] as usize;
                    if count & TRI4_LEAF != 0 && entering.count_ones() >= TOGETHER {
                        // Each triangle against all the packet's rays at once.
                        for block in &self.tri4[first..first + (count & !TRI4_LEAF)] {
                            for (j, &prim) in block.prim.iter().enumerate() {
                                if prim == u32::MAX {
                                    break;
                                }
                                let (t, u, v, hit) = kernels.hits8(block, j, &rays8, &limits);
                                let mut each = hit & entering;
                                while each != 0 {
                                    let k = each.trailing_zeros() as usize;
                                    each &= each - 1;
                                    nearest[k].offer(
                                        Hit {
                                            t: t[k],
                                            u: u[k],
                                            v: v[k],
                                        },
                                        prim,
                                    );
                                    limits[k] = nearest[k].limit;
                                }
                            }
                        }
                        continue;
                    }
                    single.prepare(rays, &rays8, entering);
                    let mut each = entering;
                    while each != 0 {
                        let k = each.trailing_zeros() as usize;
                        each &= each - 1;
                        self.leaf_closest::<S, { leaf_kinds::ALL }, ()>(
                            kernels,
                            first,
                            count,
                            &rays[k],
                            &single.ray4[k],
                            &mut nearest[k],
                            &mut (),
                        );
                        limits[k] = nearest[k].limit;
                    }
                }
                // Nearest child next, the others stacked far to near.
                let inner = &mut inner[..n_inner];
                sort_descending(inner);
                let mut next = None;
                for (i, &(lane, near)) in inner.iter().enumerate() {
                    let entry = Entry {
                        node: node.child[lane as usize],
                        rays: inner_rays[lane as usize],
                        near,
                        coherent: inner_coherent[lane as usize],
                    };
                    if i + 1 == n_inner {
                        next = Some(entry);
                    } else {
                        stack.push(entry);
                    }
                }
                // The nearest child next, else the stack's top, while one of the
                // entry's rays has found nothing nearer than its nearest entry; an
                // entry left to [`SOLO`] rays or fewer is walked by each of them alone.
                let mut candidate = next;
                loop {
                    let Some(e) = candidate.take().or_else(|| stack.pop()) else {
                        return;
                    };
                    let entering = e.rays & f32x8::splat(e.near).simd_lt(f32x8::from(limits)).to_bitmask();
                    if entering == 0 {
                        continue;
                    }
                    if entering.count_ones() <= SOLO {
                        single.prepare(rays, &rays8, entering);
                        let mut each = entering;
                        while each != 0 {
                            let k = each.trailing_zeros() as usize;
                            each &= each - 1;
                            self.walk_closest::<S, { leaf_kinds::ALL }, ()>(
                                kernels,
                                e.node,
                                &rays[k],
                                &single.boxes[k],
                                &single.ray4[k],
                                &mut nearest[k],
                                &mut (),
                            );
                            limits[k] = nearest[k].limit;
                        }
                        continue;
                    }
                    index = e.node;
                    active = entering;
                    coherent = e.coherent;
                    break;
                }
            }
        });
    }
}
