//! The nearest hit of a closest-hit query, with its rule for ties.

use crate::geometry::Hit;

/// The nearest hit found so far. Ties in distance go to the lowest primitive index,
/// as in a scan of the primitives in order, so the answer does not depend on the
/// order leaves are met in (single rays, packets and image regions all agree).
#[derive(Clone, Copy, Debug)]
pub struct Nearest {
    /// The hit and its primitive index.
    pub best: Option<(Hit, u32)>,
    /// The bound to pass to an exclusive test (`t < limit`): the query's `t_max` at
    /// first, then the next float above the best distance, so that an equally near
    /// hit still comes to [`Nearest::offer`].
    pub limit: f32,
}

impl Nearest {
    /// Nothing found yet, below `t_max`.
    #[inline(always)]
    pub fn new(t_max: f32) -> Nearest {
        Nearest {
            best: None,
            limit: t_max,
        }
    }

    /// Keeps `hit` of primitive `prim` (found below [`Nearest::limit`]) if it is
    /// nearer, or as near with a lower index.
    #[inline(always)]
    pub fn offer(&mut self, hit: Hit, prim: u32) {
        if let Some((best, p)) = self.best {
            if hit.t > best.t || (hit.t == best.t && prim >= p) {
                return;
            }
        }
        self.limit = hit.t.next_up();
        self.best = Some((hit, prim));
    }
}
