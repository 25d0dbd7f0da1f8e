//! The nearest hit of a closest-hit query, with its rule for ties.

use crate::geometry::Hit;

/// How far past the best distance found the search still looks (as a factor): the
/// leaves whose boxes the ray enters up to there are tested too. A primitive hit at
/// exactly the best distance lies in its box, but the box's computed entry may come
/// out a few units in the last place beyond the triangle test's computed distance;
/// without the slack such a leaf was skipped or tested depending on the order the
/// traversal met the leaves in, and single rays and packets could report different
/// primitives of a tie. 2^-20 is 16 units in the last place.
const TIE_SLACK: f32 = 1.0 + 1.0 / (1u32 << 20) as f32;

/// The nearest hit found so far. Ties in distance go to the primitive that comes first
/// in the scene (the lowest rank, `Bvh::ranks`: its line, then its place in the
/// scene's lists), so the answer depends neither on the order leaves are met in
/// (single rays, packets, image regions and the acceleration structures all agree)
/// nor on the order the builder put the leaves in: of coincident surfaces, the one
/// listed first is seen.
#[derive(Clone, Copy, Debug)]
pub struct Nearest<'a> {
    /// The hit and its primitive index.
    pub best: Option<(Hit, u32)>,
    /// The bound to pass to an exclusive test (`t < limit`): the query's `t_max` at
    /// first, then the best distance stretched by [`TIE_SLACK`] (at least the next
    /// float above it, never above the previous limit), so that an equally near hit
    /// still comes to [`Nearest::offer`], which turns away the farther ones.
    pub limit: f32,
    /// Each primitive's rank (by the index the queries report), `Bvh::ranks`.
    ranks: &'a [u64],
}

impl<'a> Nearest<'a> {
    /// Nothing found yet, below `t_max`, among primitives ranked by `ranks`.
    #[inline(always)]
    pub fn new(t_max: f32, ranks: &'a [u64]) -> Nearest<'a> {
        Nearest {
            best: None,
            limit: t_max,
            ranks,
        }
    }

    /// The ranks, by primitive index.
    #[inline(always)]
    pub fn ranks(&self) -> &'a [u64] {
        self.ranks
    }

    /// Primitive `prim`'s rank.
    #[inline(always)]
    pub fn rank(&self, prim: u32) -> u64 {
        self.ranks[prim as usize]
    }

    /// Keeps `hit` of primitive `prim` (found below [`Nearest::limit`]) if it is
    /// nearer, or as near with a lower rank.
    #[inline(always)]
    pub fn offer(&mut self, hit: Hit, prim: u32) {
        if let Some((best, p)) = self.best {
            if hit.t > best.t || (hit.t == best.t && self.rank(prim) >= self.rank(p)) {
                return;
            }
        }
        self.limit = (hit.t * TIE_SLACK).max(hit.t.next_up()).min(self.limit);
        self.best = Some((hit, prim));
    }
}
