//! Acceleration: a bounding volume hierarchy over the bounded primitives, built with
//! the binned surface area heuristic as a binary tree of 32-byte nodes, then
//! collapsed at the least SAH cost into the 8-wide nodes the queries traverse;
//! unbounded primitives (planes) are tested beside it.

#[cfg(target_arch = "x86_64")]
mod avx;
mod binning;
mod build;
mod bvh;
mod check;
mod collapse;
mod cone4;
mod nearest;
mod node;
mod packet;
mod ray8;
mod sphere4;
mod split;
mod tri4;
mod wide;

#[cfg(feature = "counters")]
pub use bvh::counters;
pub use bvh::Bvh;
pub use bvh::NO_HINT;
pub use check::BvhStats;
pub use node::BvhNode;
pub use packet::PACKET;
pub use wide::Node8;

#[cfg(test)]
mod tests;
