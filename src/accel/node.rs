//! The flattened BVH node.

use crate::math::{fast_max, fast_min, Aabb, Ray, Vec3};

/// One node of the flattened BVH: 32 bytes, two per cache line.
///
/// A node is a leaf iff `count > 0`; its primitives are `first .. first + count` in
/// the BVH's leaf-ordered primitive array. An interior node's children are the
/// adjacent nodes `first` and `first + 1`.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
#[repr(C)]
pub struct BvhNode {
    /// Lower corner of the node's box.
    pub min: [f32; 3],
    /// First primitive (leaf) or left child (interior).
    pub first: u32,
    /// Upper corner of the node's box.
    pub max: [f32; 3],
    /// Number of primitives; 0 for an interior node.
    pub count: u32,
}

const _: () = assert!(std::mem::size_of::<BvhNode>() == 32);

impl BvhNode {
    /// The node's box.
    #[inline]
    pub fn bounds(&self) -> Aabb {
        Aabb::new(Vec3::from_array(self.min), Vec3::from_array(self.max))
    }

    /// Slab test: the entry distance if `ray` meets the box within `[0, t_max]`, else
    /// infinity. Relies on [`Ray::inv_dir`] being finite, so no NaN can arise.
    #[inline(always)]
    pub fn entry(&self, ray: &Ray, t_max: f32) -> f32 {
        let (o, inv) = (ray.origin, ray.inv_dir);
        let tx0 = (self.min[0] - o.x) * inv.x;
        let tx1 = (self.max[0] - o.x) * inv.x;
        let ty0 = (self.min[1] - o.y) * inv.y;
        let ty1 = (self.max[1] - o.y) * inv.y;
        let tz0 = (self.min[2] - o.z) * inv.z;
        let tz1 = (self.max[2] - o.z) * inv.z;
        let near = fast_max(
            fast_max(fast_min(tx0, tx1), fast_min(ty0, ty1)),
            fast_max(fast_min(tz0, tz1), 0.0),
        );
        let far = fast_min(
            fast_min(fast_max(tx0, tx1), fast_max(ty0, ty1)),
            fast_min(fast_max(tz0, tz1), t_max),
        );
        if near <= far {
            near
        } else {
            f32::INFINITY
        }
    }

    /// True for a leaf.
    #[inline]
    pub fn is_leaf(&self) -> bool {
        self.count > 0
    }
}
