//! What a query did, counted when someone asks (`nffrt render --stats`, `nffrt bench`):
//! the queries are generic over a [`Tally`], and the renderer's, compiled with `()`,
//! count nothing at no cost.

/// Receives a query's work as it happens.
pub trait Tally {
    /// `n` more nodes (BVH) or cells (grid) visited.
    fn nodes(&mut self, n: usize);
    /// `n` more primitives tested (a block of four counts four).
    fn prims(&mut self, n: usize);
}

impl Tally for () {
    #[inline(always)]
    fn nodes(&mut self, _n: usize) {}
    #[inline(always)]
    fn prims(&mut self, _n: usize) {}
}

/// The work of one or more queries: wide nodes or grid cells visited, primitives
/// tested.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct QueryCounts {
    /// Wide BVH nodes, or grid cells, visited (0 for a linear scan).
    pub nodes: u64,
    /// Primitive intersection tests (a block of four triangles counts four).
    pub prims: u64,
}

impl Tally for QueryCounts {
    #[inline(always)]
    fn nodes(&mut self, n: usize) {
        self.nodes += n as u64;
    }
    #[inline(always)]
    fn prims(&mut self, n: usize) {
        self.prims += n as u64;
    }
}
