//! The flattened BVH node.

use crate::math::{Aabb, Vec3};

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

    /// True for a leaf.
    #[inline]
    pub fn is_leaf(&self) -> bool {
        self.count > 0
    }
}
