//! A uniform grid over the bounded primitives, traversed by the 3D digital
//! differential analyser of Amanatides and Woo ("A Fast Voxel Traversal Algorithm for
//! Ray Tracing", Eurographics 1987), with mailboxing: a primitive in several cells
//! is tested once per query.
//!
//! The grid indexes the primitives of a [`Bvh`] (its leaf order, each split cone
//! once), so that its queries report the same indices and break ties by the same rule
//! ([`Nearest`], with the BVH's ranks) as the BVH's: the pictures are the same bytes.
//!
//! **Resolution rule** (as pbrt's first edition): `3 ∛N` cells along the longest axis
//! of the primitives' bounds, `N` the number of bounded primitives, and cells as near
//! to cubes as the other axes allow; at least 1 and at most [`MAX_CELLS_PER_AXIS`] per
//! axis.

use std::cell::RefCell;
use std::sync::atomic::{AtomicU64, Ordering};

use super::bvh::Bvh;
use super::tally::Tally;
use super::traverse::nearest::Nearest;
use crate::geometry::Hit;
use crate::math::{Aabb, Ray, Vec3};

/// The most cells along one axis (the grid then holds at most 2^21 cells).
pub const MAX_CELLS_PER_AXIS: usize = 128;

/// Cells along the longest axis per cube root of the primitive count.
const CELLS_PER_CUBE_ROOT: f32 = 3.0;

/// How far, as a fraction of a cell, a primitive's box is widened before it is
/// entered in cells: a hit the traversal computes a rounding error past a cell's
/// boundary is then still found in the cell it is reported from.
const CELL_MARGIN: f32 = 1.0 / 1024.0;

/// A uniform grid (see the module docs).
#[derive(Clone, Debug)]
pub struct Grid {
    bounds: Aabb,
    cells: [usize; 3],
    cell_size: Vec3,
    /// The first entry of each cell in `items`, and one past the last cell's.
    offsets: Vec<u32>,
    /// Leaf-order primitive indices, cell after cell.
    items: Vec<u32>,
    /// Distinguishes this grid's mailbox stamps from another's.
    id: u64,
}

/// Numbers every grid, so that a thread's mailbox knows which grid it stamped for.
static NEXT_GRID: AtomicU64 = AtomicU64::new(1);

/// A thread's mailbox: the query number each primitive was last tested in.
struct Mailbox {
    grid: u64,
    query: u32,
    stamps: Vec<u32>,
}

thread_local! {
    static MAILBOX: RefCell<Mailbox> = const {
        RefCell::new(Mailbox { grid: 0, query: 0, stamps: Vec::new() })
    };
}

impl Mailbox {
    /// Starts a query of `grid` over `n` primitives.
    fn start(&mut self, grid: u64, n: usize) {
        if self.grid != grid || self.stamps.len() != n || self.query == u32::MAX {
            self.grid = grid;
            self.stamps.clear();
            self.stamps.resize(n, 0);
            self.query = 0;
        }
        self.query += 1;
    }

    /// True the first time primitive `i` is offered in this query.
    #[inline]
    fn first_visit(&mut self, i: u32) -> bool {
        let stamp = &mut self.stamps[i as usize];
        let first = *stamp != self.query;
        *stamp = self.query;
        first
    }
}

impl Grid {
    /// Builds the grid over the bounded primitives of `bvh`.
    pub fn new(bvh: &Bvh) -> Grid {
        let entries: Vec<(u32, Aabb)> = (0..bvh.bounded)
            .filter(|&i| bvh.canonical(i) == i as u32)
            .filter_map(|i| Some((i as u32, bvh.primitives[i].bounds(&bvh.data)?)))
            .collect();
        let bounds = entries.iter().fold(Aabb::default(), |b, (_, e)| b.union(*e));
        let cells = resolution(&bounds, entries.len());
        let extent = bounds.extent();
        let cell_size = Vec3::new(
            extent.x / cells[0] as f32,
            extent.y / cells[1] as f32,
            extent.z / cells[2] as f32,
        );
        let mut grid = Grid {
            bounds,
            cells,
            cell_size,
            offsets: Vec::new(),
            items: Vec::new(),
            id: NEXT_GRID.fetch_add(1, Ordering::Relaxed),
        };
        grid.fill(&entries);
        grid
    }

    /// Cells along x, y and z.
    pub fn cells(&self) -> [usize; 3] {
        self.cells
    }

    /// Entries of all cells (a primitive counts once per cell it is in).
    pub fn entries(&self) -> usize {
        self.items.len()
    }

    /// Enters each primitive in the cells its (slightly widened) box overlaps.
    fn fill(&mut self, entries: &[(u32, Aabb)]) {
        let n_cells = self.cells.iter().product::<usize>();
        let ranges: Vec<[std::ops::Range<usize>; 3]> =
            entries.iter().map(|(_, b)| self.cell_range(b)).collect();
        let mut counts = vec![0u32; n_cells + 1];
        for r in &ranges {
            self.for_cells(r, |c| counts[c + 1] += 1);
        }
        for c in 0..n_cells {
            counts[c + 1] += counts[c];
        }
        let mut next = counts.clone();
        let mut items = vec![0u32; counts[n_cells] as usize];
        for ((i, _), r) in entries.iter().zip(&ranges) {
            self.for_cells(r, |c| {
                items[next[c] as usize] = *i;
                next[c] += 1;
            });
        }
        self.offsets = counts;
        self.items = items;
    }

    /// The cells a box overlaps along each axis, the box widened by [`CELL_MARGIN`].
    fn cell_range(&self, b: &Aabb) -> [std::ops::Range<usize>; 3] {
        std::array::from_fn(|a| {
            let lo = self.cell_coordinate(b.min[a], a, -CELL_MARGIN);
            let hi = self.cell_coordinate(b.max[a], a, CELL_MARGIN);
            lo..hi + 1
        })
    }

    /// The cell along axis `a` holding coordinate `x` moved by `margin` cells,
    /// clamped to the grid.
    fn cell_coordinate(&self, x: f32, a: usize, margin: f32) -> usize {
        let size = self.cell_size[a];
        if size <= 0.0 {
            return 0;
        }
        let c = ((x - self.bounds.min[a]) / size + margin).floor();
        (c.max(0.0) as usize).min(self.cells[a] - 1)
    }

    fn for_cells(&self, r: &[std::ops::Range<usize>; 3], mut f: impl FnMut(usize)) {
        for z in r[2].clone() {
            for y in r[1].clone() {
                for x in r[0].clone() {
                    f(self.cell_index([x, y, z]));
                }
            }
        }
    }

    #[inline]
    fn cell_index(&self, c: [usize; 3]) -> usize {
        (c[2] * self.cells[1] + c[1]) * self.cells[0] + c[0]
    }

    #[inline]
    fn cell_items(&self, cell: usize) -> &[u32] {
        &self.items[self.offsets[cell] as usize..self.offsets[cell + 1] as usize]
    }

    /// The nearest hit among `bvh`'s primitives with `0 < t < t_max` (the unbounded
    /// ones tested first, as the BVH does), the BVH's tie rule.
    pub fn closest_hit<T: Tally>(
        &self,
        bvh: &Bvh,
        ray: &Ray,
        t_max: f32,
        tally: &mut T,
    ) -> Option<(Hit, u32)> {
        let mut nearest = Nearest::new(t_max, &bvh.ranks);
        bvh.unbounded_closest(ray, &mut nearest, tally);
        MAILBOX.with_borrow_mut(|mailbox| {
            mailbox.start(self.id, bvh.bounded);
            self.walk(ray, t_max, tally, |items, exit, tally| {
                for &i in items {
                    if mailbox.first_visit(i) {
                        tally.prims(1);
                        if let Some(h) = bvh.primitives[i as usize].intersect(ray, nearest.limit, &bvh.data) {
                            nearest.offer(h, i);
                        }
                    }
                }
                // Anything nearer than the limit lies in a cell already visited.
                nearest.limit <= exit
            });
        });
        nearest.best
    }

    /// True when a primitive of `bvh` lies on the ray with `0 < t < t_max`.
    pub fn occluded<T: Tally>(&self, bvh: &Bvh, ray: &Ray, t_max: f32, tally: &mut T) -> bool {
        if bvh.unbounded_occluded(ray, t_max, tally) {
            return true;
        }
        let mut blocked = false;
        MAILBOX.with_borrow_mut(|mailbox| {
            mailbox.start(self.id, bvh.bounded);
            self.walk(ray, t_max, tally, |items, _, tally| {
                blocked = items.iter().any(|&i| {
                    mailbox.first_visit(i) && {
                        tally.prims(1);
                        bvh.primitives[i as usize].occludes(ray, t_max, &bvh.data)
                    }
                });
                blocked
            });
        });
        blocked
    }

    /// Visits the cells the ray crosses within `[0, t_max]`, near to far, handing
    /// `visit` each one's primitives and the distance at which the ray leaves it,
    /// until `visit` says to stop.
    fn walk<T: Tally>(
        &self,
        ray: &Ray,
        t_max: f32,
        tally: &mut T,
        mut visit: impl FnMut(&[u32], f32, &mut T) -> bool,
    ) {
        if self.items.is_empty() {
            return;
        }
        let t0 = (self.bounds.min - ray.origin).mul_elem(ray.inv_dir);
        let t1 = (self.bounds.max - ray.origin).mul_elem(ray.inv_dir);
        let (near, far) = (t0.min(t1), t0.max(t1));
        let t_enter = near.x.max(near.y).max(near.z).max(0.0);
        let t_exit = far.x.min(far.y).min(far.z).min(t_max);
        // (Not `t_enter > t_exit`: a NaN is not entered either.)
        let entered = t_enter <= t_exit;
        if !entered {
            return;
        }
        let start = ray.at(t_enter);
        let mut cell = [0usize; 3];
        let mut step = [0isize; 3];
        let mut next = [0f32; 3];
        let mut delta = [0f32; 3];
        for a in 0..3 {
            cell[a] = self.cell_coordinate(start[a], a, 0.0);
            let size = self.cell_size[a];
            let inv = ray.inv_dir[a];
            let lower = self.bounds.min[a] + cell[a] as f32 * size;
            if ray.dir[a] > 0.0 {
                step[a] = 1;
                next[a] = (lower + size - ray.origin[a]) * inv;
                delta[a] = size * inv;
            } else if ray.dir[a] < 0.0 {
                step[a] = -1;
                next[a] = (lower - ray.origin[a]) * inv;
                delta[a] = -size * inv;
            } else {
                next[a] = f32::INFINITY;
            }
        }
        loop {
            tally.nodes(1);
            let a = if next[0] < next[1] {
                if next[0] < next[2] {
                    0
                } else {
                    2
                }
            } else if next[1] < next[2] {
                1
            } else {
                2
            };
            let exit = next[a].min(t_exit);
            if visit(self.cell_items(self.cell_index(cell)), exit, tally) || next[a] > t_exit {
                return;
            }
            let c = cell[a] as isize + step[a];
            if c < 0 || c as usize >= self.cells[a] {
                return;
            }
            cell[a] = c as usize;
            next[a] += delta[a];
        }
    }
}

/// Cells along each axis for `n` primitives within `bounds` (the module's rule).
fn resolution(bounds: &Aabb, n: usize) -> [usize; 3] {
    let extent = bounds.extent();
    let longest = extent.x.max(extent.y).max(extent.z);
    // (Not `longest <= 0.0`: a NaN extent gets one cell too.)
    let positive = longest > 0.0;
    if !positive || n == 0 {
        return [1, 1, 1];
    }
    let per_unit = CELLS_PER_CUBE_ROOT * (n as f32).cbrt() / longest;
    std::array::from_fn(|a| ((extent[a] * per_unit).round() as usize).clamp(1, MAX_CELLS_PER_AXIS))
}
