//! AVX versions of the traversal kernels, chosen at run time.
//!
//! The release build targets baseline x86_64 (SSE2), where `wide::f32x8` is two SSE
//! registers. On a CPU with AVX2 (detected once per BVH), [`Bvh::closest_hit`],
//! [`Bvh::occluded`], [`Bvh::closest_hits8`] and [`Bvh::occluded8`] run copies of themselves compiled
//! for AVX2, whose eight-lane slab test (and the eight-lane watertight triangle tests: two blocks
//! against a ray, one triangle against a packet's rays) is one AVX register wide (7 % off whole renders, 2 to 9 % more rays per second
//! in `nffrt bench`; BENCHMARKS.md). The arithmetic is the portable test's, operation
//! for operation and operand for operand (no fused multiply-add), so every answer and
//! every image is bit-identical whichever version runs. `NFFRT_SIMD=portable` in the
//! environment turns them off, to measure or check the portable kernels (`accel::simd`).
//!
//! This is the crate's only `unsafe` code: calling functions compiled for a CPU
//! feature, which is sound because an [`Avx`] value exists only once the features
//! have been detected, and the loads and stores of `load8`/`store8`, which stay
//! within arrays of exactly their width.
#![allow(unsafe_code)]

use std::arch::x86_64::{
    __m256, _mm256_add_ps, _mm256_and_ps, _mm256_blendv_ps, _mm256_castps256_ps128, _mm256_cmp_ps,
    _mm256_div_ps, _mm256_extractf128_ps, _mm256_loadu2_m128, _mm256_loadu_ps, _mm256_max_ps, _mm256_min_ps,
    _mm256_movemask_ps, _mm256_mul_ps, _mm256_or_ps, _mm256_set1_ps, _mm256_setzero_ps, _mm256_sub_ps,
    _mm_storeu_ps, _CMP_EQ_OQ, _CMP_GE_OQ, _CMP_GT_OQ, _CMP_LE_OQ, _CMP_LT_OQ,
};

use super::octant::{least, Frustum, PacketBoxes};
use super::packet::Coherence;
use super::wide::{Kernels, Node8, RayBoxes, FAR_SCALE, MAX, MIN, WIDTH};
use crate::accel::bvh::Bvh;
use crate::accel::leaf::pack::{leaf_kinds, with_kinds};
use crate::accel::leaf::ray8::{Hits8, Ray8, RAYS};
use crate::accel::leaf::tri4::{Ray4, Tri4};
use crate::accel::simd::{self, SimdLevel};
use crate::geometry::watertight::exact_lanes;
use crate::geometry::Hit;
use crate::math::Ray;

/// Proof that the CPU runs AVX2 code (and the BMI and LZCNT instructions that come
/// with it): only [`Avx::detect`] makes one.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Avx(());

impl Avx {
    /// `Some` when the queries run the AVX2 kernels: this CPU has the features they
    /// are compiled for and `NFFRT_SIMD` does not ask for the portable ones
    /// (`accel::simd`).
    pub fn detect() -> Option<Avx> {
        (simd::level() == SimdLevel::Avx2).then_some(Avx(()))
    }

    /// [`Bvh::closest_hit`], compiled for AVX2.
    #[inline]
    pub fn closest_hit(self, bvh: &Bvh, ray: &Ray, t_max: f32) -> Option<(Hit, u32)> {
        // SAFETY: `self` proves the CPU has the features `closest_hit_avx` needs.
        unsafe { closest_hit_avx(self, bvh, ray, t_max) }
    }

    /// [`Bvh::closest_hits8`], compiled for AVX2.
    #[inline]
    pub fn closest_hits8(
        self,
        bvh: &Bvh,
        rays: &Ray8,
        t_max: f32,
        active: u32,
        coherence: Coherence,
        out: &mut [Option<(Hit, u32)>; RAYS],
    ) {
        // SAFETY: as in `closest_hit`.
        unsafe { closest_hits8_avx(self, bvh, rays, t_max, active, coherence, out) }
    }

    /// [`Bvh::occluded8`], compiled for AVX2.
    #[inline]
    pub fn occluded8(
        self,
        bvh: &Bvh,
        rays: &Ray8,
        t_max: &[f32; RAYS],
        active: u32,
        coherence: Coherence,
    ) -> u32 {
        // SAFETY: as in `closest_hit`.
        unsafe { occluded8_avx(self, bvh, rays, t_max, active, coherence) }
    }

    /// `Bvh::occluder`, compiled for AVX2.
    #[inline]
    pub fn occluder(self, bvh: &Bvh, ray: &Ray, t_max: f32) -> Option<u32> {
        // SAFETY: as in `closest_hit`.
        unsafe { occluder_avx(self, bvh, ray, t_max) }
    }
}

#[target_feature(enable = "avx,avx2,bmi1,bmi2,lzcnt")]
fn closest_hit_avx(avx: Avx, bvh: &Bvh, ray: &Ray, t_max: f32) -> Option<(Hit, u32)> {
    with_kinds!(bvh.kinds, K => bvh.closest_hit_with::<_, K, _>(avx, ray, t_max, &mut ()))
}

#[target_feature(enable = "avx,avx2,bmi1,bmi2,lzcnt")]
fn closest_hits8_avx(
    avx: Avx,
    bvh: &Bvh,
    rays: &Ray8,
    t_max: f32,
    active: u32,
    coherence: Coherence,
    out: &mut [Option<(Hit, u32)>; RAYS],
) {
    bvh.closest_hits8_with(avx, rays, t_max, active, coherence, out)
}

#[target_feature(enable = "avx,avx2,bmi1,bmi2,lzcnt")]
fn occluded8_avx(
    avx: Avx,
    bvh: &Bvh,
    rays: &Ray8,
    t_max: &[f32; RAYS],
    active: u32,
    coherence: Coherence,
) -> u32 {
    bvh.occluded8_with(avx, rays, t_max, active, coherence)
}

#[target_feature(enable = "avx,avx2,bmi1,bmi2,lzcnt")]
fn occluder_avx(avx: Avx, bvh: &Bvh, ray: &Ray, t_max: f32) -> Option<u32> {
    with_kinds!(bvh.kinds, K => bvh.occluder_with::<_, K>(avx, ray, t_max))
}

impl Kernels for Avx {
    #[inline(always)]
    fn entries(self, node: &Node8, r: &RayBoxes, t_max: f32) -> ([f32; WIDTH], u32) {
        // SAFETY: `self` proves the CPU has AVX.
        unsafe { entries_avx(node, r, t_max) }
    }

    #[inline(always)]
    fn entered(self, node: &Node8, r: &RayBoxes, t_max: f32) -> u32 {
        // SAFETY: as in `entries`.
        unsafe { entered_avx(node, r, t_max) }
    }

    #[inline(always)]
    fn hits8(self, block: &Tri4, lane: usize, rays: &Ray8, limits: &[f32; RAYS]) -> Hits8 {
        // SAFETY: as in `entries`.
        unsafe { hits8_avx(block, lane, rays, limits) }
    }

    #[inline(always)]
    fn pair(self, first: &Tri4, second: &Tri4, ray: &Ray4, t_max: f32) -> Hits8 {
        // SAFETY: as in `entries`.
        unsafe { pair_avx(first, second, ray, t_max) }
    }

    #[inline(always)]
    fn frustum(self, node: &Node8, frustum: &Frustum, t_limit: f32) -> ([f32; WIDTH], u32) {
        // SAFETY: as in `entries`.
        unsafe { frustum_avx(node, frustum, t_limit) }
    }

    #[inline(always)]
    fn entered8(
        self,
        node: &Node8,
        lane: usize,
        rays: &PacketBoxes,
        near: &[usize; 3],
        limits: &[f32; RAYS],
    ) -> u32 {
        // SAFETY: as in `entries`.
        unsafe { entered8_avx(node, lane, rays, near, limits) }
    }

    #[inline(always)]
    fn entered8_mixed(
        self,
        node: &Node8,
        lane: usize,
        rays: &PacketBoxes,
        negative: &[[f32; RAYS]; 3],
        limits: &[f32; RAYS],
    ) -> (u32, f32) {
        // SAFETY: as in `entries`.
        unsafe { entered8_mixed_avx(node, lane, rays, negative, limits) }
    }
}

/// `Frustum::entries` in AVX registers.
#[target_feature(enable = "avx")]
#[inline]
fn frustum_avx(node: &Node8, f: &Frustum, t_limit: f32) -> ([f32; WIDTH], u32) {
    let (mul, sub, min, max) = (_mm256_mul_ps, _mm256_sub_ps, _mm256_min_ps, _mm256_max_ps);
    let mut near = _mm256_setzero_ps();
    let mut far = _mm256_set1_ps(t_limit);
    for axis in 0..3 {
        let [o_lo, o_hi] = f.origin[axis];
        let (inv_lo, inv_hi) = (_mm256_set1_ps(f.inv[axis][0]), _mm256_set1_ps(f.inv[axis][1]));
        let side = f.near[axis] & 1;
        let (o_entry, o_exit) = if side == MAX { (o_lo, o_hi) } else { (o_hi, o_lo) };
        let d_entry = sub(load8(&node.bounds[side][axis]), _mm256_set1_ps(o_entry));
        let d_exit = sub(load8(&node.bounds[side ^ 1][axis]), _mm256_set1_ps(o_exit));
        near = max(near, min(mul(d_entry, inv_lo), mul(d_entry, inv_hi)));
        far = min(far, max(mul(d_exit, inv_lo), mul(d_exit, inv_hi)));
    }
    let hit = _mm256_cmp_ps::<_CMP_LE_OQ>(near, mul(far, _mm256_set1_ps(FAR_SCALE)));
    (store8(near), _mm256_movemask_ps(hit) as u32)
}

/// `PacketBoxes::entered` in AVX registers: per ray the operations of
/// [`entries_avx`] on the same operands in the same order.
#[target_feature(enable = "avx")]
#[inline]
fn entered8_avx(
    node: &Node8,
    lane: usize,
    rays: &PacketBoxes,
    near: &[usize; 3],
    limits: &[f32; RAYS],
) -> u32 {
    let (mul, sub) = (_mm256_mul_ps, _mm256_sub_ps);
    let limit = load8(limits);
    let mut t_near = _mm256_setzero_ps();
    let mut t_far = limit;
    for (axis, &side) in near.iter().enumerate() {
        let side = side & 1;
        let lo = _mm256_set1_ps(node.bounds[side][axis][lane]);
        let hi = _mm256_set1_ps(node.bounds[side ^ 1][axis][lane]);
        let (o, inv) = (load8(&rays.origin[axis]), load8(&rays.inv[axis]));
        t_near = _mm256_max_ps(mul(sub(lo, o), inv), t_near);
        t_far = _mm256_min_ps(mul(sub(hi, o), inv), t_far);
    }
    let entered = _mm256_cmp_ps::<_CMP_LE_OQ>(t_near, mul(t_far, _mm256_set1_ps(FAR_SCALE)));
    let before = _mm256_cmp_ps::<_CMP_LT_OQ>(t_near, limit);
    _mm256_movemask_ps(_mm256_and_ps(entered, before)) as u32
}

/// `PacketBoxes::entered_mixed` in AVX registers: per ray the operations of
/// [`entries_avx`] on the same operands in the same order, each ray's entry sides
/// chosen by its signs.
#[target_feature(enable = "avx")]
#[inline]
fn entered8_mixed_avx(
    node: &Node8,
    lane: usize,
    rays: &PacketBoxes,
    negative: &[[f32; RAYS]; 3],
    limits: &[f32; RAYS],
) -> (u32, f32) {
    let (mul, sub) = (_mm256_mul_ps, _mm256_sub_ps);
    let limit = load8(limits);
    let mut t_near = _mm256_setzero_ps();
    let mut t_far = limit;
    for (axis, neg) in negative.iter().enumerate() {
        let neg = load8(neg);
        let min = _mm256_set1_ps(node.bounds[MIN][axis][lane]);
        let max = _mm256_set1_ps(node.bounds[MAX][axis][lane]);
        let (lo, hi) = (_mm256_blendv_ps(min, max, neg), _mm256_blendv_ps(max, min, neg));
        let (o, inv) = (load8(&rays.origin[axis]), load8(&rays.inv[axis]));
        t_near = _mm256_max_ps(mul(sub(lo, o), inv), t_near);
        t_far = _mm256_min_ps(mul(sub(hi, o), inv), t_far);
    }
    let entered = _mm256_cmp_ps::<_CMP_LE_OQ>(t_near, mul(t_far, _mm256_set1_ps(FAR_SCALE)));
    let before = _mm256_cmp_ps::<_CMP_LT_OQ>(t_near, limit);
    let hit = _mm256_and_ps(entered, before);
    let near = _mm256_blendv_ps(_mm256_set1_ps(f32::INFINITY), t_near, hit);
    (_mm256_movemask_ps(hit) as u32, least(store8(near)))
}

/// Eight lanes as an AVX register.
#[target_feature(enable = "avx")]
#[inline]
fn load8(lanes: &[f32; 8]) -> __m256 {
    // SAFETY: `lanes` holds eight f32, the width of one load.
    unsafe { _mm256_loadu_ps(lanes.as_ptr()) }
}

/// An AVX register as eight lanes, by two 128-bit stores: the single-lane loads that
/// follow are forwarded from them (not always from the upper half of a 256-bit store).
#[target_feature(enable = "avx")]
#[inline]
fn store8(v: __m256) -> [f32; 8] {
    let mut lanes = [0.0f32; 8];
    let (low, high) = lanes.split_at_mut(4);
    // SAFETY: `low` and `high` hold four f32 each, the width of one store.
    unsafe {
        _mm_storeu_ps(low.as_mut_ptr(), _mm256_castps256_ps128(v));
        _mm_storeu_ps(high.as_mut_ptr(), _mm256_extractf128_ps::<1>(v));
    }
    lanes
}

/// The inputs of the eight-lane test: the rays' origins and shears in their
/// frames, the vertices, the limits.
type Inputs8 = ([__m256; 3], [__m256; 3], [[__m256; 3]; 3], __m256);

/// `Tri4::hits8` in AVX registers (see [`watertight8`]).
#[target_feature(enable = "avx")]
#[inline]
fn hits8_avx(block: &Tri4, lane: usize, rays: &Ray8, limits: &[f32; RAYS]) -> Hits8 {
    let Some([kx, ky, kz]) = rays.shared_axes else {
        return hits8_avx_gathered(block, lane, rays, limits, false);
    };
    let [kx, ky, kz] = [kx as usize, ky as usize, kz as usize];
    let vertex = |v: &[[f32; 4]; 3]| {
        [
            _mm256_set1_ps(v[kx][lane]),
            _mm256_set1_ps(v[ky][lane]),
            _mm256_set1_ps(v[kz][lane]),
        ]
    };
    let v = [vertex(&block.v0), vertex(&block.v1), vertex(&block.v2)];
    let rows = |a: &[[f32; RAYS]; 3]| [load8(&a[0]), load8(&a[1]), load8(&a[2])];
    match watertight8(rows(&rays.sheared_origin), rows(&rays.shear), v, load8(limits)) {
        Some(found) => found,
        None => hits8_avx_gathered(block, lane, rays, limits, true),
    }
}

/// [`hits8_avx`] for rays that do not share their axes (each vertex permuted for
/// each ray, as `Ray8::gather` does), or with `exact` when an edge function came
/// out zero.
#[target_feature(enable = "avx")]
#[inline(never)]
fn hits8_avx_gathered(block: &Tri4, lane: usize, rays: &Ray8, limits: &[f32; RAYS], exact: bool) -> Hits8 {
    let rows = |a: &[[f32; RAYS]; 3]| [load8(&a[0]), load8(&a[1]), load8(&a[2])];
    let picks = rays.picks.map(|[is_x, is_y]| (load8(&is_x), load8(&is_y)));
    let gather = |v: &[[f32; 4]; 3]| {
        let [x, y, z] = [0, 1, 2].map(|axis| _mm256_set1_ps(v[axis][lane]));
        picks.map(|(is_x, is_y)| _mm256_blendv_ps(_mm256_blendv_ps(z, y, is_y), x, is_x))
    };
    let (origin, shear) = (rows(&rays.sheared_origin), rows(&rays.shear));
    let (v, limit) = (
        [gather(&block.v0), gather(&block.v1), gather(&block.v2)],
        load8(limits),
    );
    if !exact {
        if let Some(found) = watertight8(origin, shear, v, limit) {
            return found;
        }
    }
    watertight8_exact(origin, shear, v, limit)
}

/// `ray8::pair_hits` in AVX registers (see [`watertight8`]).
#[target_feature(enable = "avx")]
fn pair_avx(first: &Tri4, second: &Tri4, ray: &Ray4, t_max: f32) -> Hits8 {
    let (origin, shear, v, limit) = pair_inputs(first, second, ray, t_max);
    match watertight8(origin, shear, v, limit) {
        Some(found) => found,
        None => pair_avx_exact(first, second, ray, t_max),
    }
}

/// [`pair_avx`] when an edge function came out zero.
#[target_feature(enable = "avx")]
#[cold]
#[inline(never)]
fn pair_avx_exact(first: &Tri4, second: &Tri4, ray: &Ray4, t_max: f32) -> Hits8 {
    let (origin, shear, v, limit) = pair_inputs(first, second, ray, t_max);
    watertight8_exact(origin, shear, v, limit)
}

/// The inputs of [`pair_avx`].
#[target_feature(enable = "avx")]
#[inline]
fn pair_inputs(first: &Tri4, second: &Tri4, ray: &Ray4, t_max: f32) -> Inputs8 {
    let s = &ray.sheared;
    let [kx, ky, kz] = [s.axes[0] as usize, s.axes[1] as usize, s.axes[2] as usize];
    // SAFETY: each block row holds four f32, the width of one 128-bit load.
    let row = |a: &[f32; 4], b: &[f32; 4]| unsafe { _mm256_loadu2_m128(b.as_ptr(), a.as_ptr()) };
    let both = |a: &[[f32; 4]; 3], b: &[[f32; 4]; 3]| {
        [row(&a[kx], &b[kx]), row(&a[ky], &b[ky]), row(&a[kz], &b[kz])]
    };
    let splat = |a: &[f32; 3]| [_mm256_set1_ps(a[0]), _mm256_set1_ps(a[1]), _mm256_set1_ps(a[2])];
    (
        splat(&s.origin),
        splat(&s.shear),
        [
            both(&first.v0, &second.v0),
            both(&first.v1, &second.v1),
            both(&first.v2, &second.v2),
        ],
        _mm256_set1_ps(t_max),
    )
}

/// `geometry::watertight::frame` in AVX registers.
#[target_feature(enable = "avx")]
#[inline]
fn frame8(
    origin: &[__m256; 3],
    shear: &[__m256; 3],
    [v0, v1, v2]: &[[__m256; 3]; 3],
) -> ([__m256; 6], [__m256; 3]) {
    let (mul, sub) = (_mm256_mul_ps, _mm256_sub_ps);
    let [sx, sy, _] = *shear;
    let [ox, oy, oz] = *origin;
    let (ax, ay, az) = (sub(v0[0], ox), sub(v0[1], oy), sub(v0[2], oz));
    let (bx, by, bz) = (sub(v1[0], ox), sub(v1[1], oy), sub(v1[2], oz));
    let (cx, cy, cz) = (sub(v2[0], ox), sub(v2[1], oy), sub(v2[2], oz));
    (
        [
            sub(ax, mul(sx, az)),
            sub(ay, mul(sy, az)),
            sub(bx, mul(sx, bz)),
            sub(by, mul(sy, bz)),
            sub(cx, mul(sx, cz)),
            sub(cy, mul(sy, cz)),
        ],
        [az, bz, cz],
    )
}

/// `geometry::watertight::edges` in AVX registers.
#[target_feature(enable = "avx")]
#[inline]
fn edges8([ax, ay, bx, by, cx, cy]: [__m256; 6]) -> [__m256; 3] {
    let (mul, sub) = (_mm256_mul_ps, _mm256_sub_ps);
    [
        sub(mul(cx, by), mul(cy, bx)),
        sub(mul(ax, cy), mul(ay, cx)),
        sub(mul(bx, ay), mul(by, ax)),
    ]
}

/// `geometry::watertight::zero_edge` in AVX registers.
#[target_feature(enable = "avx")]
#[inline]
fn zero_edge8([e0, e1, e2]: [__m256; 3]) -> u32 {
    let least = _mm256_min_ps(_mm256_min_ps(e0, e1), e2);
    let greatest = _mm256_max_ps(_mm256_max_ps(e0, e1), e2);
    let product = _mm256_mul_ps(least, greatest);
    _mm256_movemask_ps(_mm256_cmp_ps::<_CMP_EQ_OQ>(product, _mm256_setzero_ps())) as u32
}

/// `geometry::watertight::finish` in AVX registers (the comparisons are ordered,
/// false on NaN, as `simd_ge` and the others; `min` and `max` are `minps` and
/// `maxps`, as `fast_min` and `fast_max`).
#[target_feature(enable = "avx")]
#[inline]
fn finish8([e0, e1, e2]: [__m256; 3], [az, bz, cz]: [__m256; 3], sz: __m256, limit: __m256) -> Hits8 {
    let (mul, add, and, or) = (_mm256_mul_ps, _mm256_add_ps, _mm256_and_ps, _mm256_or_ps);
    let zero = _mm256_setzero_ps();
    let det = add(add(e0, e1), e2);
    let t_unscaled = add(add(mul(e0, az), mul(e1, bz)), mul(e2, cz));
    let inv_det = _mm256_div_ps(_mm256_set1_ps(1.0), det);
    let t = mul(t_unscaled, mul(sz, inv_det));
    let (min, max) = (_mm256_min_ps, _mm256_max_ps);
    let same_sign = or(
        _mm256_cmp_ps::<_CMP_GE_OQ>(min(min(e0, e1), e2), zero),
        _mm256_cmp_ps::<_CMP_LE_OQ>(max(max(e0, e1), e2), zero),
    );
    let ok = and(
        and(same_sign, _mm256_cmp_ps::<_CMP_GT_OQ>(t, zero)),
        _mm256_cmp_ps::<_CMP_LT_OQ>(t, limit),
    );
    (
        store8(t),
        store8(mul(e1, inv_det)),
        store8(mul(e2, inv_det)),
        _mm256_movemask_ps(ok) as u32,
    )
}

/// The watertight test (`geometry::watertight::watertight`) and its acceptance on
/// eight lanes of rays and triangles, below `limit`, in AVX registers, operation for
/// operation; `None` when an edge function came out zero (the caller then runs
/// [`watertight8_exact`] out of line).
#[target_feature(enable = "avx")]
#[inline]
fn watertight8(origin: [__m256; 3], shear: [__m256; 3], v: [[__m256; 3]; 3], limit: __m256) -> Option<Hits8> {
    let (xy, z) = frame8(&origin, &shear, &v);
    let e = edges8(xy);
    if zero_edge8(e) != 0 {
        return None;
    }
    Some(finish8(e, z, shear[2], limit))
}

/// [`watertight8`] with the edge functions that came out zero recomputed in `f64`,
/// as `geometry::watertight::watertight_exact`.
#[target_feature(enable = "avx")]
#[inline]
fn watertight8_exact(origin: [__m256; 3], shear: [__m256; 3], v: [[__m256; 3]; 3], limit: __m256) -> Hits8 {
    let (xy, z) = frame8(&origin, &shear, &v);
    let e = edges8(xy);
    let mask = zero_edge8(e);
    let xy = xy.map(|x| store8(x));
    let mut e = e.map(|x| store8(x));
    let [e0, e1, e2] = &mut e;
    exact_lanes(mask, xy.each_ref().map(|a| &a[..]), [e0, e1, e2]);
    finish8(e.each_ref().map(|x| load8(x)), z, shear[2], limit)
}

/// `Node8::slabs` in AVX registers: the entry and exit distances of `r` for
/// `node`'s eight boxes, the far planes' computed with `r.inv` times `exit_scale`.
#[target_feature(enable = "avx")]
#[inline]
fn slabs_avx(node: &Node8, r: &RayBoxes, t_max: f32, exit_scale: f32) -> (__m256, __m256) {
    let mut near = _mm256_setzero_ps();
    let mut far = _mm256_set1_ps(t_max);
    for axis in 0..3 {
        let (lo, hi) = r.planes(node, axis);
        let origin = _mm256_set1_ps(r.origin[axis]);
        let inv = _mm256_set1_ps(r.inv[axis]);
        let inv_far = _mm256_set1_ps(r.inv[axis] * exit_scale);
        let (lo, hi) = (load8(lo), load8(hi));
        near = _mm256_max_ps(_mm256_mul_ps(_mm256_sub_ps(lo, origin), inv), near);
        far = _mm256_min_ps(_mm256_mul_ps(_mm256_sub_ps(hi, origin), inv_far), far);
    }
    (near, far)
}

/// [`Node8::entries`] in AVX registers: the same operations on the same operands in
/// the same order (`max(t, near)`, `min(t, far)`: with equal operands, including
/// `-0.0` against `0.0`, or a NaN `t`, both return the second one, as the SSE
/// version does).
#[target_feature(enable = "avx")]
fn entries_avx(node: &Node8, r: &RayBoxes, t_max: f32) -> ([f32; WIDTH], u32) {
    let (near, far) = slabs_avx(node, r, t_max, 1.0);
    let hit = _mm256_cmp_ps::<_CMP_LE_OQ>(near, _mm256_mul_ps(far, _mm256_set1_ps(FAR_SCALE)));
    (store8(near), _mm256_movemask_ps(hit) as u32)
}

/// [`Node8::entered`] in AVX registers, as [`entries_avx`] is [`Node8::entries`].
#[target_feature(enable = "avx")]
fn entered_avx(node: &Node8, r: &RayBoxes, t_max: f32) -> u32 {
    let (near, far) = slabs_avx(node, r, t_max, FAR_SCALE);
    _mm256_movemask_ps(_mm256_cmp_ps::<_CMP_LE_OQ>(near, far)) as u32
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::accel::traverse::wide::{Portable, MAX, MIN};
    use crate::math::Vec3;

    /// The AVX slab test gives the portable one's distances and masks bit for bit, on
    /// boxes the ray enters, misses, starts inside, meets edge-on, and empty lanes.
    #[test]
    fn avx_slab_test_equals_the_portable_one_bit_for_bit() {
        let Some(avx) = Avx::detect() else {
            crate::test_skip::skip_unless_required(
                "NFFRT_REQUIRE_AVX2",
                "this CPU has no AVX2 (or NFFRT_SIMD=portable)",
            );
            return;
        };
        // Seven boxes and an empty lane.
        let mut node = crate::accel::traverse::wide::EMPTY;
        let boxes = [
            ([0.0, 0.0, 4.0], [1.0, 1.0, 5.0]),
            ([-1.0, -1.0, -1.0], [1.0, 1.0, 1.0]),
            ([5.0, 5.0, 5.0], [6.0, 6.0, 6.0]),
            ([0.0, -0.0, 2.0], [0.0, 3.0, 2.0]),
            ([-3.0, -3.0, -9.0], [3.0, 3.0, -8.0]),
            ([0.25, 0.5, 1e-3], [0.75, 0.5, 7.0]),
            ([-1e30, -1e30, 3.0], [1e30, 1e30, 3.5]),
        ];
        for (lane, (lo, hi)) in boxes.iter().enumerate() {
            for axis in 0..3 {
                node.bounds[MIN][axis][lane] = lo[axis];
                node.bounds[MAX][axis][lane] = hi[axis];
            }
        }
        let mut entered = 0;
        for i in 0..200 {
            let a = i as f32 * 0.37;
            let origin = Vec3::new(a.sin() * 2.0, a.cos() * 2.0, (i % 7) as f32 - 3.0);
            let dir = Vec3::new((a * 1.3).cos(), (a * 0.7).sin(), 0.5 - (i % 3) as f32 * 0.5);
            let r = RayBoxes::new(&Ray::new(origin, dir.normalize()));
            for t_max in [f32::INFINITY, 10.0, 4.5, 2.0] {
                let (pt, pm) = Portable.entries(&node, &r, t_max);
                let (at, am) = avx.entries(&node, &r, t_max);
                assert_eq!(pm, am, "ray {i}");
                assert_eq!(pm & 1 << 7, 0, "ray {i} entered the empty lane");
                assert_eq!(pt.map(f32::to_bits), at.map(f32::to_bits), "ray {i}");
                assert_eq!(
                    Portable.entered(&node, &r, t_max),
                    avx.entered(&node, &r, t_max),
                    "ray {i}"
                );
                entered += pm.count_ones();
            }
        }
        assert!(entered > 200, "only {entered} boxes entered: too weak a test");
    }

    /// The eight-ray slab test (AVX and portable) gives each ray of an octant the
    /// single-ray test's answer for the box, and the frustum test (AVX and portable)
    /// never culls a box one of them enters, with an entry bound no farther than
    /// theirs.
    #[test]
    fn packet_box_tests_agree_with_the_single_ray_test() {
        use crate::accel::traverse::octant::{Octants, PacketBoxes};
        let Some(avx) = Avx::detect() else {
            crate::test_skip::skip_unless_required(
                "NFFRT_REQUIRE_AVX2",
                "this CPU has no AVX2 (or NFFRT_SIMD=portable)",
            );
            return;
        };
        let mut rnd = crate::accel::tests::uniform(0x2545_f491);
        let mut node = crate::accel::traverse::wide::EMPTY;
        let mut entered = 0;
        for round in 0..800 {
            for lane in 0..7 {
                for axis in 0..3 {
                    let (a, b) = (rnd() * 8.0 - 4.0, rnd() * 8.0 - 4.0);
                    node.bounds[MIN][axis][lane] = a.min(b);
                    node.bounds[MAX][axis][lane] = a.max(b);
                }
            }
            let o = Vec3::new(rnd() - 0.5, rnd() - 0.5, rnd() - 0.5) * 12.0;
            let base = Vec3::new(rnd() - 0.5, rnd() - 0.5, rnd() - 0.5);
            let rays: Vec<Ray> = (0..8)
                .map(|k| {
                    let mut d =
                        base + Vec3::new(rnd() - 0.5, rnd() - 0.5, rnd() - 0.5) * (round % 4) as f32 * 0.2;
                    if (round + k) % 11 == 0 {
                        d = Vec3::new(0.0, d.y, d.z);
                    }
                    Ray::new(
                        o,
                        if d.length() > 1e-3 {
                            d
                        } else {
                            Vec3::new(0.0, 0.0, 1.0)
                        },
                    )
                })
                .collect();
            let r8 = Ray8::new(&rays);
            let boxes = PacketBoxes::new(&r8);
            let limits = std::array::from_fn(|k| [f32::INFINITY, 6.0, 3.0][(k + round) % 3]);
            let mut octants = Octants::new(&boxes, 0xff);
            while let Some(octant) = octants.next(&boxes) {
                let t_limit = (0..8)
                    .filter(|k| octant.lanes >> k & 1 != 0)
                    .fold(0.0f32, |t, k| t.max(limits[k]));
                let frusta = octant.frustum.map(|f| {
                    (
                        Portable.frustum(&node, &f, t_limit),
                        avx.frustum(&node, &f, t_limit),
                    )
                });
                for lane in 0..8 {
                    let got = Portable.entered8(&node, lane, &boxes, &octant.near, &limits) & octant.lanes;
                    let got_avx = avx.entered8(&node, lane, &boxes, &octant.near, &limits) & octant.lanes;
                    assert_eq!(got, got_avx, "round {round} lane {lane}");
                    for k in (0..8).filter(|k| octant.lanes >> k & 1 != 0) {
                        let one = RayBoxes::new(&rays[k]);
                        let (t, mask) = Portable.entries(&node, &one, limits[k]);
                        let want = mask >> lane & 1 != 0 && t[lane] < limits[k];
                        assert_eq!(got >> k & 1 != 0, want, "round {round} lane {lane} ray {k}");
                        if let (true, Some(((near, hit), (near_avx, hit_avx)))) = (want, frusta) {
                            assert!(
                                hit >> lane & 1 != 0 && hit_avx >> lane & 1 != 0,
                                "round {round} lane {lane}"
                            );
                            assert!(near[lane] <= t[lane] && near_avx[lane] <= t[lane]);
                        }
                        entered += u32::from(want);
                    }
                }
            }
        }
        assert!(entered > 1000, "only {entered} boxes entered: too weak a test");
    }

    /// The AVX triangle test of eight rays gives the portable one's results bit for bit.
    #[test]
    fn avx_hits8_equals_the_portable_one_bit_for_bit() {
        let Some(avx) = Avx::detect() else {
            crate::test_skip::skip_unless_required(
                "NFFRT_REQUIRE_AVX2",
                "this CPU has no AVX2 (or NFFRT_SIMD=portable)",
            );
            return;
        };
        let (block, _, packets) = crate::accel::leaf::ray8::tests::cases();
        for (rays, limits) in &packets {
            let rays8 = Ray8::new(rays);
            for lane in 0..4 {
                let (pt, pu, pv, pm) = Portable.hits8(&block, lane, &rays8, limits);
                let (at, au, av, am) = avx.hits8(&block, lane, &rays8, limits);
                assert_eq!(pm, am);
                for k in 0..8 {
                    if pm & (1 << k) != 0 {
                        let bits = |a: [f32; 8]| a[k].to_bits();
                        assert_eq!((bits(pt), bits(pu), bits(pv)), (bits(at), bits(au), bits(av)));
                    }
                }
            }
        }
    }

    #[test]
    fn avx_pair_equals_the_portable_one_bit_for_bit() {
        let Some(avx) = Avx::detect() else {
            crate::test_skip::skip_unless_required(
                "NFFRT_REQUIRE_AVX2",
                "this CPU has no AVX2 (or NFFRT_SIMD=portable)",
            );
            return;
        };
        let (first, tris, packets) = crate::accel::leaf::ray8::tests::cases();
        let second = crate::accel::leaf::ray8::tests::second_block(&tris);
        let mut hits = 0;
        for (rays, limits) in &packets {
            for (r, &t_max) in rays.iter().zip(limits) {
                let r4 = Ray4::new(r);
                let (pt, pu, pv, pm) = Portable.pair(&first, &second, &r4, t_max);
                let (at, au, av, am) = avx.pair(&first, &second, &r4, t_max);
                assert_eq!(pm, am);
                for k in 0..8 {
                    if pm & (1 << k) != 0 {
                        let bits = |a: [f32; 8]| a[k].to_bits();
                        assert_eq!((bits(pt), bits(pu), bits(pv)), (bits(at), bits(au), bits(av)));
                        hits += 1;
                    }
                }
            }
        }
        assert!(hits > 100, "{hits} hits: too few to compare");
    }

    /// The AVX kernels recompute the edge functions rounded to zero as the portable
    /// ones do.
    #[test]
    fn avx_recomputes_zero_edge_functions_as_the_portable_kernels_do() {
        let Some(avx) = Avx::detect() else {
            crate::test_skip::skip_unless_required(
                "NFFRT_REQUIRE_AVX2",
                "this CPU has no AVX2 (or NFFRT_SIMD=portable)",
            );
            return;
        };
        let (ray, hit, missed) = crate::geometry::triangle::tests::split_by_a_near_edge();
        let block = Tri4::new(&[(missed, 0), (hit, 1)]);
        let other = Ray::new(Vec3::new(0.1, -0.3, 0.0), Vec3::new(0.0, 0.0, 1.0));
        let rays8 = Ray8::new(&[ray, other, ray, ray, other, ray, ray, other]);
        let limits = [f32::INFINITY; RAYS];
        let bits = |(t, u, v, m): Hits8| (t.map(f32::to_bits), u.map(f32::to_bits), v.map(f32::to_bits), m);
        for lane in 0..2 {
            let portable = Portable.hits8(&block, lane, &rays8, &limits);
            assert_ne!(portable.3, 0);
            assert_eq!(bits(avx.hits8(&block, lane, &rays8, &limits)), bits(portable));
        }
        let r4 = Ray4::new(&ray);
        let portable = Portable.pair(&block, &block, &r4, f32::INFINITY);
        assert_eq!(portable.3, 0b0010_0010);
        let (t, u, v, m) = avx.pair(&block, &block, &r4, f32::INFINITY);
        assert_eq!(m, portable.3);
        for k in [1, 5] {
            assert_eq!(
                (t[k].to_bits(), u[k].to_bits(), v[k].to_bits()),
                (
                    portable.0[k].to_bits(),
                    portable.1[k].to_bits(),
                    portable.2[k].to_bits()
                )
            );
        }
    }
}
