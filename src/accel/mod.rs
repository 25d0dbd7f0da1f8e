//! Acceleration: a bounding volume hierarchy over the bounded primitives, built with
//! the binned surface area heuristic and flattened into 32-byte nodes; unbounded
//! primitives (planes) are tested beside it.

#[cfg(target_arch = "x86_64")]
mod avx;
mod binning;
mod build;
mod bvh;
mod node;
mod tri4;
mod wide;

#[cfg(feature = "counters")]
pub use bvh::counters;
pub use bvh::{Bvh, BvhStats};
pub use node::BvhNode;
pub use wide::Node8;

#[cfg(test)]
mod tests;
