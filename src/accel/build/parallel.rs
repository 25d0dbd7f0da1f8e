//! The two passes of the biggest nodes (binning, partition) split into chunks run on
//! several threads, with results bit-identical to the serial passes of `sah`, so the
//! tree does not depend on the thread count.
//!
//! Binning: each chunk fills bins of its own, merged in chunk order. Partition: the
//! serial one (`sah::partition`) swaps every item going left with the first of those
//! going right met so far, and here each item's place in its result is computed
//! instead (see [`right_source`]), from a prefix count of the items going left; the
//! items are gathered into a scratch buffer and copied back. Bounds are merged in
//! chunk order too. A min/max fold keeps, of equal values, the later one (`fast_min`
//! is `a < b ? a : b`), and a NaN resets it, so the merge of two chunks' folds is the
//! fold of the whole: the later chunk's where it met a NaN (see [`PointFold`]).

use rayon::prelude::*;
use wide::f32x4;

use super::binning::{Binner, Bins, Box4, Item};

/// Chunks a parallel pass cuts a node's items into, at most: enough for the
/// threads to balance, few enough that merging costs nothing.
const CHUNKS: usize = 16;

/// Items per chunk for a node of `n` items.
fn chunk_len(n: usize) -> usize {
    n.div_ceil(CHUNKS).max(1)
}

/// [`Bins::fill`] for `items`, in parallel chunks; `bins` must be empty.
pub fn fill_bins(bins: &mut Bins, items: &[Item], binner: &Binner) {
    let filled: Vec<Box<Bins>> = items
        .par_chunks(chunk_len(items.len()))
        .map(|chunk| {
            let mut b = bins.like();
            b.fill(chunk, binner);
            b
        })
        .collect();
    for b in &filled {
        bins.merge(b);
    }
}

/// A fold of points (centroids) by [`Box4::add_point`] that can be merged with the
/// fold of the points after them: it also marks the lanes where a NaN was met, since
/// from there the fold depends only on what follows.
#[derive(Clone, Copy)]
struct PointFold {
    bounds: Box4,
    nan: f32x4,
}

impl PointFold {
    const EMPTY: PointFold = PointFold {
        bounds: Box4::EMPTY,
        nan: f32x4::ZERO,
    };

    #[inline(always)]
    fn add(&mut self, p: f32x4) {
        self.bounds.add_point(p);
        self.nan |= p.is_nan();
    }

    /// `self` followed by `later`, as if folded in one pass.
    fn then(&self, later: &PointFold) -> PointFold {
        let mut joined = self.bounds;
        joined.add_box(&later.bounds);
        PointFold {
            bounds: Box4 {
                min: later.nan.select(later.bounds.min, joined.min),
                max: later.nan.select(later.bounds.max, joined.max),
            },
            nan: self.nan | later.nan,
        }
    }
}

/// Bounds and centroid bounds of `items` as [`Box4::of`] folds them, in parallel
/// chunks.
pub fn bounds_of(items: &[Item]) -> (Box4, Box4) {
    let folds: Vec<(Box4, PointFold)> = items
        .par_chunks(chunk_len(items.len()))
        .map(|chunk| {
            let (mut b, mut c) = (Box4::EMPTY, PointFold::EMPTY);
            for it in chunk {
                b.add(it);
                c.add(it.centroid());
            }
            (b, c)
        })
        .collect();
    let (mut b, mut c) = (Box4::EMPTY, PointFold::EMPTY);
    for (cb, cc) in &folds {
        b.add_box(cb);
        c = c.then(cc);
    }
    (b, c.bounds)
}

/// One chunk's share of a partition: its items going left, and the bounds and
/// centroid folds of both sides.
#[derive(Clone, Copy)]
struct Side {
    left: usize,
    lb: Box4,
    lc: PointFold,
    rb: Box4,
    rc: PointFold,
}

/// `sah::partition` (by `bin < split_bin` on `axis`) with the same resulting order
/// and bounds, in parallel chunks, using `scratch` (as long as `items`).
pub fn partition(
    items: &mut [Item],
    scratch: &mut [Item],
    binner: &Binner,
    axis: usize,
    split_bin: usize,
) -> (usize, (Box4, Box4), (Box4, Box4)) {
    let n = items.len();
    debug_assert_eq!(scratch.len(), n);
    let chunk = chunk_len(n);
    let goes_left = |it: &Item| (binner.bins(it.centroid())[axis] as usize) < split_bin;
    // Items going left before each one in its chunk.
    let mut local = vec![0u32; n];
    let sides: Vec<Side> = items
        .par_chunks(chunk)
        .zip(local.par_chunks_mut(chunk))
        .map(|(its, before)| {
            let mut s = Side {
                left: 0,
                lb: Box4::EMPTY,
                lc: PointFold::EMPTY,
                rb: Box4::EMPTY,
                rc: PointFold::EMPTY,
            };
            for (it, b) in its.iter().zip(before) {
                *b = s.left as u32;
                let c = it.centroid();
                if goes_left(it) {
                    s.lb.add(it);
                    s.lc.add(c);
                    s.left += 1;
                } else {
                    s.rb.add(it);
                    s.rc.add(c);
                }
            }
            s
        })
        .collect();
    let mut offsets = Vec::with_capacity(sides.len());
    let (mut left, mut lb, mut lc, mut rb, mut rc) =
        (0, Box4::EMPTY, PointFold::EMPTY, Box4::EMPTY, PointFold::EMPTY);
    for s in &sides {
        offsets.push(left as u32);
        left += s.left;
        lb.add_box(&s.lb);
        lc = lc.then(&s.lc);
        rb.add_box(&s.rb);
        rc = rc.then(&s.rc);
    }
    // Items going left among items[..q].
    let before = |q: usize| match q {
        _ if q == n => left as u32,
        _ => local[q] + offsets[q / chunk],
    };
    // The items going left keep their order: each chunk's go to one run.
    let (to_left, to_right) = scratch.split_at_mut(left);
    let mut runs = Vec::with_capacity(sides.len());
    let mut rest = to_left;
    for s in &sides {
        let (run, tail) = rest.split_at_mut(s.left);
        runs.push(run);
        rest = tail;
    }
    // The two sides at once: one synchronisation fewer.
    let items_ref = &*items;
    rayon::join(
        || {
            items_ref.par_chunks(chunk).zip(runs).for_each(|(its, run)| {
                let mut out = run.iter_mut();
                for it in its.iter().filter(|it| goes_left(it)) {
                    *out.next().expect("one place per item going left") = *it;
                }
            })
        },
        || {
            to_right.par_chunks_mut(chunk).enumerate().for_each(|(k, out)| {
                for (i, slot) in out.iter_mut().enumerate() {
                    *slot = items_ref[right_source(before, left + k * chunk + i)];
                }
            })
        },
    );
    items
        .par_chunks_mut(chunk)
        .zip(scratch.par_chunks(chunk))
        .for_each(|(dst, src)| dst.copy_from_slice(src));
    (left, (lb, lc.bounds), (rb, rc.bounds))
}

/// The input index of the item the serial partition leaves at place `p` (at or
/// after the last item going left), `before(q)` counting the items going left among
/// the first `q`. Place `p` is written by the serial loop only at step `p`: it keeps
/// its item if that goes right, else receives the item then at place `before(p)`,
/// which was last written at step `before(p)` — by the same rule.
#[inline]
fn right_source(before: impl Fn(usize) -> u32, mut p: usize) -> usize {
    loop {
        let b = before(p);
        if before(p + 1) == b {
            return p;
        }
        p = b as usize;
    }
}
