//! No acceleration: every primitive tested for every ray (`--accel none`), over the
//! primitives of a [`Bvh`] in its leaf order (each split cone once), so that the
//! answers, ties included ([`Nearest`]), are the BVH's. Also the unbounded primitives
//! (planes), which every structure tests this way.

use super::bvh::Bvh;
use super::tally::Tally;
use super::traverse::nearest::Nearest;
use crate::geometry::Hit;
use crate::math::Ray;

impl Bvh {
    /// Offers `nearest` the hits of the unbounded primitives.
    #[inline]
    pub(super) fn unbounded_closest<T: Tally>(&self, ray: &Ray, nearest: &mut Nearest, tally: &mut T) {
        // (Without this, the compiler prepared the ray for every kind of primitive
        // ahead of the loop, also when it has nothing to do: most scenes have no
        // unbounded primitives.)
        if self.bounded == self.primitives.len() {
            return;
        }
        tally.prims(self.primitives.len() - self.bounded);
        for (i, p) in self.primitives.iter().enumerate().skip(self.bounded) {
            if let Some(h) = p.intersect(ray, nearest.limit, &self.data) {
                nearest.offer(h, i as u32);
            }
        }
    }

    /// True when an unbounded primitive lies on the ray with `0 < t < t_max`.
    #[inline]
    pub(super) fn unbounded_occluded<T: Tally>(&self, ray: &Ray, t_max: f32, tally: &mut T) -> bool {
        if self.bounded == self.primitives.len() {
            return false;
        }
        self.primitives[self.bounded..].iter().any(|p| {
            tally.prims(1);
            p.occludes(ray, t_max, &self.data)
        })
    }

    /// The nearest hit with `0 < t < t_max`, every primitive tested.
    pub fn scan_closest<T: Tally>(&self, ray: &Ray, t_max: f32, tally: &mut T) -> Option<(Hit, u32)> {
        let mut nearest = Nearest::new(t_max, &self.ranks);
        for i in self.distinct_bounded() {
            tally.prims(1);
            if let Some(h) = self.primitives[i as usize].intersect(ray, nearest.limit, &self.data) {
                nearest.offer(h, i);
            }
        }
        self.unbounded_closest(ray, &mut nearest, tally);
        nearest.best
    }

    /// True when a primitive lies on the ray with `0 < t < t_max`, every primitive
    /// tested until one does.
    pub fn scan_occluded<T: Tally>(&self, ray: &Ray, t_max: f32, tally: &mut T) -> bool {
        self.distinct_bounded().any(|i| {
            tally.prims(1);
            self.primitives[i as usize].occludes(ray, t_max, &self.data)
        }) || self.unbounded_occluded(ray, t_max, tally)
    }

    /// The leaf-order indices of the bounded primitives, each split cone once.
    fn distinct_bounded(&self) -> impl Iterator<Item = u32> + '_ {
        (0..self.bounded as u32).filter(move |&i| self.canonical(i as usize) == i)
    }
}
