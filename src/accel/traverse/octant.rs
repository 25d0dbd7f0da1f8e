//! A packet of eight rays split by direction octant, and the two box tests of a
//! coherent walk: one conservative test of a whole octant's rays against a node's
//! eight boxes (the frustum, [`Frustum::entries`]), then one eight-ray slab test per
//! box it lets through ([`PacketBoxes::entered`]).
//!
//! Rays whose directions agree in sign on every axis enter a box through the same
//! three planes, so one walk serves them all (Wald, Boulos and Shirley 2007, "Ray
//! tracing deformable scenes using dynamic bounding volume hierarchies"; Embree's
//! coherent packets). A packet whose rays differ in sign is walked once per octant
//! present, each walk with the mask of its rays, rather than ray by ray.

use wide::f32x8;

use super::wide::{Node8, FAR_SCALE, MAX, MIN, WIDTH};
use crate::accel::leaf::ray8::{Ray8, RAYS};
use crate::math::TINY_DIR;

/// All eight lanes, as bits.
pub const ALL: u32 = (1 << RAYS) - 1;

/// The rays of a packet prepared for the slab test, as `RayBoxes` prepares one ray
/// (an infinite inverse on an axis a ray runs parallel to), side by side.
#[derive(Clone, Copy)]
pub struct PacketBoxes {
    pub(in crate::accel) origin: [[f32; RAYS]; 3],
    pub(in crate::accel) inv: [[f32; RAYS]; 3],
}

impl PacketBoxes {
    /// Prepares `rays`.
    #[inline(always)]
    pub fn new(rays: &Ray8) -> PacketBoxes {
        // (Arrays written out rather than `std::array::from_fn`, which the compiler
        // left as a call per packet.)
        let prepare = |axis: usize| {
            let inv = f32x8::from(rays.inv[axis]);
            let parallel = f32x8::from(rays.dir[axis]).abs().simd_lt(f32x8::splat(TINY_DIR));
            // (`Ray::inv_dir` keeps the sign of a zero direction component.)
            let infinite = inv
                .simd_lt(f32x8::ZERO)
                .bitselect(f32x8::splat(f32::NEG_INFINITY), f32x8::splat(f32::INFINITY));
            parallel.bitselect(infinite, inv).to_array()
        };
        let inv = [prepare(0), prepare(1), prepare(2)];
        PacketBoxes {
            origin: rays.origin,
            inv,
        }
    }

    /// The rays (as bits) that enter lane `lane`'s box of `node` within `[0, limits[k]]`
    /// with an entry nearer than `limits[k]`: per ray, the arithmetic of `Node8::entries`
    /// for that lane, operation for operation, so a ray enters exactly the boxes its
    /// single-ray walk enters. `near` holds the octant's entry sides (see
    /// [`Octant::near`]); the answer for rays of other octants means nothing.
    #[inline(always)]
    pub fn entered(&self, node: &Node8, lane: usize, near: &[usize; 3], limits: &[f32; RAYS]) -> u32 {
        let limit = f32x8::from(*limits);
        let mut t_near = f32x8::ZERO;
        let mut t_far = limit;
        for (axis, &side) in near.iter().enumerate() {
            let side = side & 1;
            let lo = f32x8::splat(node.bounds[side][axis][lane]);
            let hi = f32x8::splat(node.bounds[side ^ 1][axis][lane]);
            let (o, inv) = (f32x8::from(self.origin[axis]), f32x8::from(self.inv[axis]));
            t_near = ((lo - o) * inv).fast_max(t_near);
            t_far = ((hi - o) * inv).fast_min(t_far);
        }
        let hit = t_near.simd_le(t_far * f32x8::splat(FAR_SCALE)) & t_near.simd_lt(limit);
        hit.to_bitmask()
    }
}

impl PacketBoxes {
    /// [`PacketBoxes::entered`] for rays of any directions: each ray enters the box
    /// through the sides its own signs give (`negative`, per axis the rays' lanes
    /// all ones where the direction is negative), so that each gets exactly its
    /// single-ray answer; with the least entry among the rays that enter.
    #[inline(always)]
    pub fn entered_mixed(
        &self,
        node: &Node8,
        lane: usize,
        negative: &[[f32; RAYS]; 3],
        limits: &[f32; RAYS],
    ) -> (u32, f32) {
        let limit = f32x8::from(*limits);
        let mut t_near = f32x8::ZERO;
        let mut t_far = limit;
        for (axis, neg) in negative.iter().enumerate() {
            let neg = f32x8::from(*neg);
            let (min, max) = (
                f32x8::splat(node.bounds[MIN][axis][lane]),
                f32x8::splat(node.bounds[MAX][axis][lane]),
            );
            let (lo, hi) = (neg.bitselect(max, min), neg.bitselect(min, max));
            let (o, inv) = (f32x8::from(self.origin[axis]), f32x8::from(self.inv[axis]));
            t_near = ((lo - o) * inv).fast_max(t_near);
            t_far = ((hi - o) * inv).fast_min(t_far);
        }
        let hit = t_near.simd_le(t_far * f32x8::splat(FAR_SCALE)) & t_near.simd_lt(limit);
        let near = hit.bitselect(t_near, f32x8::splat(f32::INFINITY));
        (hit.to_bitmask(), least(near.to_array()))
    }

    /// Per axis, the lanes of rays with a negative direction, as all-ones lanes (for
    /// [`PacketBoxes::entered_mixed`]).
    #[inline(always)]
    pub fn negative(&self) -> [[f32; RAYS]; 3] {
        self.inv
            .map(|inv| f32x8::from(inv).simd_lt(f32x8::ZERO).to_array())
    }
}

/// The least of eight lanes (by plain comparison).
#[inline(always)]
pub fn least(v: [f32; RAYS]) -> f32 {
    v.into_iter()
        .fold(f32::INFINITY, |m, x| if x < m { x } else { m })
}

/// The rays of one octant of a packet, or of a packet of mixed directions walked
/// together.
#[derive(Clone, Copy)]
pub struct Octant {
    /// The rays, as bits.
    pub lanes: u32,
    /// Per axis, the side of `Node8::bounds` the rays enter boxes through ([`MIN`]
    /// for positive directions).
    pub near: [usize; 3],
    /// The frustum test of the rays, unless one of them runs parallel to an axis (an
    /// infinite inverse direction, which interval arithmetic cannot bound).
    pub frustum: Option<Frustum>,
    /// For rays of mixed directions ([`Octant::mixed`]): per axis, the lanes of rays
    /// with negative directions ([`PacketBoxes::negative`]); each ray enters boxes
    /// through its own sides, and `near` and `frustum` mean nothing.
    pub mixed: Option<[[f32; RAYS]; 3]>,
}

impl Octant {
    /// The rays `active` of `boxes`, whatever their directions, as one group: no
    /// frustum, each box tested against every ray with its own entry sides.
    #[inline(always)]
    pub fn mixed(boxes: &PacketBoxes, active: u32) -> Octant {
        Octant {
            lanes: active & ALL,
            near: [MIN; 3],
            frustum: None,
            mixed: Some(boxes.negative()),
        }
    }
}

/// The signs of a packet's rays, from which its octants are taken one by one.
pub struct Octants {
    /// Per axis, the rays with a negative direction, as bits.
    negative: [u32; 3],
    /// The rays parallel to some axis, as bits.
    parallel: u32,
    /// The rays not yet in an octant taken.
    left: u32,
}

impl Octants {
    /// The octants of the `active` rays of `boxes` (rays parallel to an axis in their
    /// own octants, apart from the others of their signs).
    #[inline(always)]
    pub fn new(boxes: &PacketBoxes, active: u32) -> Octants {
        let mut negative = [0u32; 3];
        let mut parallel = 0u32;
        for (negative, inv) in negative.iter_mut().zip(&boxes.inv) {
            let inv = f32x8::from(*inv);
            *negative = inv.simd_lt(f32x8::ZERO).to_bitmask();
            parallel |= inv.abs().simd_eq(f32x8::splat(f32::INFINITY)).to_bitmask();
        }
        Octants {
            negative,
            parallel,
            left: active & ALL,
        }
    }

    /// The next octant: the rays left whose signs (and parallelism) match those of
    /// the first one left.
    #[inline(always)]
    pub fn next(&mut self, boxes: &PacketBoxes) -> Option<Octant> {
        if self.left == 0 {
            return None;
        }
        let first = self.left.trailing_zeros();
        let same = |bits: u32| if bits >> first & 1 != 0 { bits } else { !bits };
        let [nx, ny, nz] = self.negative;
        let lanes = self.left & same(nx) & same(ny) & same(nz) & same(self.parallel);
        self.left &= !lanes;
        let near = self.negative.map(|n| if n & lanes != 0 { MAX } else { MIN });
        let frustum = (self.parallel & lanes == 0).then(|| Frustum::new(boxes, lanes, &near));
        Some(Octant {
            lanes,
            near,
            frustum,
            mixed: None,
        })
    }
}

/// Per axis, the range of an octant's origins and inverse directions: the frustum of
/// its rays, tested against a node's eight boxes at once.
#[derive(Clone, Copy)]
pub struct Frustum {
    /// Per axis, the origins' least and greatest.
    pub(in crate::accel) origin: [[f32; 2]; 3],
    /// Per axis, the inverse directions' least and greatest (all of one sign).
    pub(in crate::accel) inv: [[f32; 2]; 3],
    /// The entry sides, as [`Octant::near`].
    pub(in crate::accel) near: [usize; 3],
}

impl Frustum {
    /// The frustum of the rays `lanes` of `boxes`, whose entry sides are `near`.
    #[inline(always)]
    fn new(boxes: &PacketBoxes, lanes: u32, near: &[usize; 3]) -> Frustum {
        // The rays' lanes as all-ones bits, the others' as zeros.
        let mut on = [0.0; RAYS];
        for (k, on) in on.iter_mut().enumerate() {
            *on = f32::from_bits(0u32.wrapping_sub(lanes >> k & 1));
        }
        let on = f32x8::from(on);
        let range = |v: &[f32; RAYS]| {
            let v = f32x8::from(*v);
            let lo = on.bitselect(v, f32x8::splat(f32::INFINITY)).to_array();
            let hi = on.bitselect(v, f32x8::splat(f32::NEG_INFINITY)).to_array();
            [
                least(lo),
                hi.into_iter()
                    .fold(f32::NEG_INFINITY, |m, x| if x > m { x } else { m }),
            ]
        };
        Frustum {
            origin: [0, 1, 2].map(|axis| range(&boxes.origin[axis])),
            inv: [0, 1, 2].map(|axis| range(&boxes.inv[axis])),
            near: *near,
        }
    }

    /// A lower bound of every ray's entry into each lane's box, and the lanes some ray
    /// may enter before `t_limit` (as bits): conservative, since correctly rounded
    /// arithmetic is monotonic, so a box any of the rays enters is entered.
    ///
    /// Per axis, with `t = (plane − o) · inv`: for positive directions the entry is
    /// least for the greatest origin, the exit greatest for the least origin, and the
    /// other way round for negative ones; the two inverse directions bound the rest.
    #[inline(always)]
    pub fn entries(&self, node: &Node8, t_limit: f32) -> ([f32; WIDTH], u32) {
        let mut near = f32x8::ZERO;
        let mut far = f32x8::splat(t_limit);
        for axis in 0..3 {
            let [o_lo, o_hi] = self.origin[axis];
            let [inv_lo, inv_hi] = self.inv[axis].map(f32x8::splat);
            let side = self.near[axis] & 1;
            let (o_entry, o_exit) = if side == MAX { (o_lo, o_hi) } else { (o_hi, o_lo) };
            let d_entry = f32x8::from(node.bounds[side][axis]) - o_entry;
            let d_exit = f32x8::from(node.bounds[side ^ 1][axis]) - o_exit;
            near = near.fast_max((d_entry * inv_lo).fast_min(d_entry * inv_hi));
            far = far.fast_min((d_exit * inv_lo).fast_max(d_exit * inv_hi));
        }
        // The exit stretched as `Node8::entries` stretches each ray's: after the same
        // monotonic operations, so the test stays conservative.
        let hit = near.simd_le(far * f32x8::splat(FAR_SCALE));
        (near.to_array(), hit.to_bitmask())
    }
}

/// The greatest of `limits` over the lanes `lanes` (−∞ for none): how far any of
/// them still looks.
#[inline(always)]
pub fn farthest(limits: &[f32; RAYS], lanes: u32) -> f32 {
    (0..RAYS)
        .filter(|k| lanes >> k & 1 != 0)
        .fold(f32::NEG_INFINITY, |t, k| t.max(limits[k]))
}
