//! Acceleration: a bounding volume hierarchy over the bounded primitives, built with
//! the binned surface area heuristic as a binary tree of 32-byte nodes, then
//! collapsed at the least SAH cost into the 8-wide nodes the queries traverse;
//! unbounded primitives (planes) are tested beside it.
//!
//! Three rooms, one per stage a reader may look for:
//! - `build/`: the binned SAH builder (`sah`, with its working types in `binning`),
//!   long cones split into pieces (`split`), the binary nodes (`node`) and their
//!   collapse into wide ones (`collapse`);
//! - `leaf/`: the leaf blocks of four triangles, spheres or cones (`tri4`, `sphere4`,
//!   `cone4`), the eight-lane triangle tests (`ray8`), and how leaves are packed into
//!   blocks (`pack`);
//! - `traverse/`: the wide nodes and their slab test (`wide`), the AVX kernels chosen
//!   at run time (`avx`), the single-ray walks (`single` for the closest hit,
//!   `occlusion`), the packets (`packet`) and the rule for ties (`nearest`).
//!
//! `bvh.rs` holds the structure and puts the stages together; `graft.rs` puts two
//! built trees under one root (an animation's fixed part, built once, the
//! [`Rootstock`], and each frame's moving part); `check.rs` validates it and
//! measures it. The big arrays of the build and of the tree are allocated by
//! `crate::pages`, on huge pages where the system offers them.
//!
//! Beside the BVH, for the course's comparison of structures (`--accel`): a uniform
//! grid (`grid`), a scan of every primitive (`linear`), and the choice between the
//! three (`aggregate`), whose queries the renderer calls; `tally` counts a query's
//! work when asked.

/// Traversal counters (feature `counters`): wide nodes visited, primitives tested.
#[cfg(feature = "counters")]
pub mod counters {
    use std::sync::atomic::{AtomicU64, Ordering};
    /// Wide nodes visited.
    pub static NODES: AtomicU64 = AtomicU64::new(0);
    /// Primitive intersection tests.
    pub static PRIMS: AtomicU64 = AtomicU64::new(0);
    /// Adds to a counter.
    #[inline(always)]
    pub fn add(c: &AtomicU64, n: u64) {
        c.fetch_add(n, Ordering::Relaxed);
    }
}

macro_rules! count {
    ($c:ident, $n:expr) => {
        #[cfg(feature = "counters")]
        $crate::accel::counters::add(&$crate::accel::counters::$c, $n as u64);
    };
}

mod aggregate;
mod build;
mod bvh;
mod check;
mod graft;
mod grid;
mod leaf;
mod linear;
mod prototype;
pub mod simd;
mod tally;
mod traverse;

pub use aggregate::Aggregate;
pub use build::node::BvhNode;
pub use bvh::Bvh;
pub use check::BvhStats;
pub use graft::Rootstock;
pub use grid::{Grid, MAX_CELLS_PER_AXIS};
pub use leaf::ray8::{Ray8, RayLanes};
pub use tally::{QueryCounts, Tally};
pub use traverse::occlusion::NO_HINT;
pub use traverse::packet::{Coherence, PACKET};
pub use traverse::wide::Node8;

#[cfg(test)]
mod tests;
