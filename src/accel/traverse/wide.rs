//! The 8-wide BVH used for traversal, collapsed from the binary SAH tree.
//!
//! Each [`Node8`] holds its eight children's boxes in structure-of-arrays form, so one
//! slab test over eight lanes compiles to packed SIMD instructions (`wide::f32x8`: two
//! SSE registers on the x86_64 baseline; `accel::traverse::avx` has the same test in one AVX
//! register, chosen at run time). Eight lanes rather than four halve the levels a ray descends,
//! each a dependent memory access: on this project's benchmarks that made random rays
//! 8 to 14 % faster (BENCHMARKS.md). `accel::build::collapse` makes them from the binary
//! tree.

use wide::{f32x8, u32x8};

use super::octant::{Frustum, PacketBoxes};
use crate::accel::leaf::ray8::{pair_hits, Hits8, Ray8, RAYS};
use crate::accel::leaf::tri4::{Ray4, Tri4};
use crate::math::{Aabb, Ray, Vec3, TINY_DIR};

/// Lanes per wide node.
pub const WIDTH: usize = 8;

/// A node with up to eight children. Lane `i` is empty when `count[i] == 0` and
/// `child[i] == u32::MAX` (its box is inside out, lower corner +∞ and upper −∞, so
/// every slab test misses it, whatever its `t_max`), a
/// leaf with primitives `child[i] .. child[i] + count[i]` when `count[i] > 0`, and an
/// interior node `child[i]` otherwise.
#[derive(Clone, Copy, Debug, PartialEq)]
#[repr(C, align(64))]
pub struct Node8 {
    /// Box corners, `[side][axis][lane]`: side `MIN` (0) the lower corners, `MAX` (1)
    /// the upper ones.
    pub bounds: [[[f32; WIDTH]; 3]; 2],
    /// Child node index or first primitive, per lane.
    pub child: [u32; WIDTH],
    /// Primitive count per lane (0: interior or empty).
    pub count: [u32; WIDTH],
}

const _: () = assert!(std::mem::size_of::<Node8>() == 256);

/// The side of [`Node8::bounds`] holding the lower corners.
pub const MIN: usize = 0;
/// The side of [`Node8::bounds`] holding the upper corners.
pub const MAX: usize = 1;

pub(in crate::accel) const EMPTY: Node8 = Node8 {
    bounds: [[[f32::INFINITY; WIDTH]; 3], [[f32::NEG_INFINITY; WIDTH]; 3]],
    child: [u32::MAX; WIDTH],
    count: [0; WIDTH],
};

pub(in crate::accel) use crate::math::FAR_SCALE;

/// A ray prepared for the wide slab test.
#[derive(Clone, Copy)]
pub struct RayBoxes {
    pub(in crate::accel) origin: [f32; 3],
    /// `Ray::inv_dir`, except on an axis the ray runs parallel to (a zero direction
    /// component), where it is an infinity of the zero's sign. A ray lying exactly in
    /// a box's plane then computes `0 · ∞ = NaN` for it, which the slab test ignores
    /// (the box stays open on that axis, as the primitive tests in that face see it);
    /// with `Ray::inv_dir`'s huge finite value it would compute 0 and close the box at
    /// t = 0, missing the primitives in the face.
    pub(in crate::accel) inv: [f32; 3],
    /// Per axis, the side of [`Node8::bounds`] the ray enters boxes through: [`MIN`]
    /// for a positive `inv`, else [`MAX`] (it leaves through the other). Chosen once
    /// per ray rather than at every node: the sign test there was a branch the
    /// processor mispredicted on random rays (7 to 11 % of their time, BENCHMARKS.md).
    pub(in crate::accel) near: [usize; 3],
}

impl RayBoxes {
    /// Prepares `ray`.
    #[inline(always)]
    pub fn new(ray: &Ray) -> Self {
        let dir = ray.dir.to_array();
        let inv_dir = ray.inv_dir.to_array();
        let inv: [f32; 3] = std::array::from_fn(|a| {
            if dir[a].abs() < TINY_DIR {
                f32::INFINITY.copysign(inv_dir[a])
            } else {
                inv_dir[a]
            }
        });
        RayBoxes {
            origin: ray.origin.to_array(),
            inv,
            near: inv.map(|i| if i < 0.0 { MAX } else { MIN }),
        }
    }

    /// The rows of `node`'s near and far planes on `axis` (see [`RayBoxes::near`]).
    #[inline(always)]
    pub(in crate::accel) fn planes<'n>(
        &self,
        node: &'n Node8,
        axis: usize,
    ) -> (&'n [f32; WIDTH], &'n [f32; WIDTH]) {
        // `& 1` (a no-op on MIN and MAX) spares the bounds checks.
        let near = self.near[axis] & 1;
        (&node.bounds[near][axis], &node.bounds[near ^ 1][axis])
    }
}

impl Node8 {
    /// The box of lane `lane`.
    pub fn lane_bounds(&self, lane: usize) -> Aabb {
        let corner = |side: usize| {
            Vec3::new(
                self.bounds[side][0][lane],
                self.bounds[side][1][lane],
                self.bounds[side][2][lane],
            )
        };
        Aabb::new(corner(MIN), corner(MAX))
    }

    /// The lanes in use (a child node or a leaf; empty lanes hold `u32::MAX` and no
    /// primitives).
    pub fn used_lanes(&self) -> impl Iterator<Item = usize> + '_ {
        (0..WIDTH).filter(|&lane| self.child[lane] != u32::MAX || self.count[lane] != 0)
    }

    /// The lanes holding leaves, as bits.
    #[inline(always)]
    pub fn leaf_lanes(&self) -> u32 {
        !u32x8::from(self.count).simd_eq(u32x8::ZERO).to_bitmask() & ((1 << WIDTH) - 1)
    }

    /// The entry and exit distances of `r` for the eight boxes within `[0, t_max]`,
    /// the distances to the far planes computed with `r.inv` times `exit_scale` (one
    /// for [`Node8::entries`], which multiplies nothing: `x * 1.0 == x` for every
    /// float; [`FAR_SCALE`] for [`Node8::entered`]).
    #[inline(always)]
    fn slabs(&self, r: &RayBoxes, t_max: f32, exit_scale: f32) -> (f32x8, f32x8) {
        let mut near = f32x8::ZERO;
        let mut far = f32x8::splat(t_max);
        for axis in 0..3 {
            // The near plane is the min plane for a positive direction, else the max.
            // `a.fast_max(b)` is `a > b ? a : b` (one `maxps`), so a NaN `a` (a ray in
            // the plane, see `RayBoxes::inv`) leaves `b`, the bound so far.
            let (lo, hi) = r.planes(self, axis);
            near = ((f32x8::from(*lo) - r.origin[axis]) * r.inv[axis]).fast_max(near);
            far = ((f32x8::from(*hi) - r.origin[axis]) * (r.inv[axis] * exit_scale)).fast_min(far);
        }
        (near, far)
    }

    /// Entry distance of `ray` into each lane's box, and a mask with bit `i` set when
    /// the ray meets lane `i`'s box within `[0, t_max]` (misses and empty lanes have
    /// no bit). The exit, `t_max` included, is stretched by `FAR_SCALE`, so a box
    /// entered that little past `t_max` counts too: the callers cull by distance
    /// again before they test a leaf or visit a child.
    #[inline(always)]
    pub fn entries(&self, r: &RayBoxes, t_max: f32) -> ([f32; WIDTH], u32) {
        let (near, far) = self.slabs(r, t_max, 1.0);
        let hit = near.simd_le(far * f32x8::splat(FAR_SCALE));
        (near.to_array(), hit.to_bitmask())
    }

    /// The lanes whose boxes `ray` enters within `[0, t_max]`, as bits: the test of
    /// [`Node8::entries`] for queries that need no distances, with the exit
    /// stretched by `FAR_SCALE` plane by plane rather than at the end (the same
    /// guarantee), which keeps the multiplication off the test's critical path:
    /// occlusion ran 6–11 % faster so than with [`Node8::entries`]' one
    /// multiplication at the end, while closest hit, which keeps more values in
    /// registers, ran up to 13 % slower so.
    #[inline(always)]
    pub fn entered(&self, r: &RayBoxes, t_max: f32) -> u32 {
        let (near, far) = self.slabs(r, t_max, FAR_SCALE);
        near.simd_le(far).to_bitmask()
    }
}

/// The SIMD kernels of traversal (a ray against a node's eight boxes, a triangle
/// against eight rays, eight triangles against a ray): [`Portable`] on any CPU, or the AVX ones (`accel::traverse::avx`) with
/// the very same arithmetic. The traversal functions are generic over them so that
/// each instruction set gets its own copy.
pub trait Kernels: Copy {
    /// As [`Node8::entries`].
    fn entries(self, node: &Node8, r: &RayBoxes, t_max: f32) -> ([f32; WIDTH], u32);
    /// As [`Node8::entered`].
    fn entered(self, node: &Node8, r: &RayBoxes, t_max: f32) -> u32;
    /// As `Tri4::hits8` (one triangle against eight rays).
    fn hits8(self, block: &Tri4, lane: usize, rays: &Ray8, limits: &[f32; RAYS]) -> Hits8;
    /// As `ray8::pair_hits` (two blocks of triangles against one ray).
    fn pair(self, first: &Tri4, second: &Tri4, ray: &Ray4, t_max: f32) -> Hits8;
    /// As [`Frustum::entries`] (an octant of a packet against eight boxes).
    fn frustum(self, node: &Node8, frustum: &Frustum, t_limit: f32) -> ([f32; WIDTH], u32);
    /// As [`PacketBoxes::entered`] (eight rays against one box).
    fn entered8(
        self,
        node: &Node8,
        lane: usize,
        rays: &PacketBoxes,
        near: &[usize; 3],
        limits: &[f32; RAYS],
    ) -> u32;
    /// As [`PacketBoxes::entered_mixed`] (eight rays of any directions against one
    /// box).
    fn entered8_mixed(
        self,
        node: &Node8,
        lane: usize,
        rays: &PacketBoxes,
        negative: &[[f32; RAYS]; 3],
        limits: &[f32; RAYS],
    ) -> (u32, f32);
}

/// The kernels as the `wide` crate compiles them for the build target.
#[derive(Clone, Copy, Debug)]
pub struct Portable;

impl Kernels for Portable {
    #[inline(always)]
    fn entries(self, node: &Node8, r: &RayBoxes, t_max: f32) -> ([f32; WIDTH], u32) {
        node.entries(r, t_max)
    }

    #[inline(always)]
    fn entered(self, node: &Node8, r: &RayBoxes, t_max: f32) -> u32 {
        node.entered(r, t_max)
    }

    #[inline(always)]
    fn hits8(self, block: &Tri4, lane: usize, rays: &Ray8, limits: &[f32; RAYS]) -> Hits8 {
        block.hits8(lane, rays, limits)
    }

    #[inline(always)]
    fn pair(self, first: &Tri4, second: &Tri4, ray: &Ray4, t_max: f32) -> Hits8 {
        pair_hits(first, second, ray, t_max)
    }

    #[inline(always)]
    fn frustum(self, node: &Node8, frustum: &Frustum, t_limit: f32) -> ([f32; WIDTH], u32) {
        frustum.entries(node, t_limit)
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
        rays.entered(node, lane, near, limits)
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
        rays.entered_mixed(node, lane, negative, limits)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// By hand: `inv` is `1 / dir` per axis, an infinity of the direction's sign on an
    /// axis it runs parallel to (a component below `TINY_DIR`, zero included, `-0.0`
    /// negative), and the near side is the upper one where `inv` is negative.
    #[test]
    fn ray_boxes_take_the_inverse_direction_and_its_signs() {
        let inf = f32::INFINITY;
        for (dir, inv, near) in [
            (Vec3::new(2.0, -4.0, 0.5), [0.5, -0.25, 2.0], [MIN, MAX, MIN]),
            (Vec3::new(0.0, -1.0, 1.0), [inf, -1.0, 1.0], [MIN, MAX, MIN]),
            (Vec3::new(-0.0, 1e-31, -1e-31), [-inf, inf, -inf], [MAX, MIN, MAX]),
            (Vec3::new(-1.0, 0.0, -0.0), [-1.0, inf, -inf], [MAX, MIN, MAX]),
        ] {
            let r = RayBoxes::new(&Ray::new(Vec3::new(1.0, 2.0, 3.0), dir));
            assert_eq!(r.origin, [1.0, 2.0, 3.0]);
            assert_eq!(r.inv, inv, "{dir:?}");
            assert_eq!(r.near, near, "{dir:?}");
        }
    }
}
