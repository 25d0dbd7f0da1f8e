//! A BVH as an instance's prototype ([`Prototype`]): the structure built once over
//! a prototype's primitives in their own space, which every placement of it asks.

use super::Bvh;
use crate::geometry::{Hit, Prototype, Surface};
use crate::math::{Aabb, Ray};

impl Prototype for Bvh {
    fn closest_hit(&self, ray: &Ray, t_max: f32) -> Option<(Hit, u32)> {
        Bvh::closest_hit(self, ray, t_max)
    }

    fn occluded(&self, ray: &Ray, t_max: f32) -> bool {
        Bvh::occluded(self, ray, t_max)
    }

    fn surface(&self, index: u32, ray: &Ray, hit: &Hit) -> Surface {
        self.primitive(index).surface(ray, hit, self.data())
    }

    fn texcoords(&self, index: u32, hit: &Hit) -> Option<[f32; 2]> {
        self.primitive(index).texcoords(hit, self.data())
    }

    /// The union of the boxes two levels down the tree, each placed by `m`: much
    /// tighter than the placed box of the whole when `m` turns the prototype (a
    /// box's corners, turned, span more than what is in it). `None` for a prototype
    /// with an unbounded primitive (a plane), which no placement can bound, and for
    /// an empty one.
    fn placed_bounds(&self, m: &[[f64; 4]; 3]) -> Option<Aabb> {
        if self.bounded < self.primitives.len() || self.wide.is_empty() {
            return None;
        }
        let root = &self.wide[0];
        let mut b = Aabb::EMPTY;
        for lane in root.used_lanes() {
            if root.count[lane] != 0 {
                b = b.union(root.lane_bounds(lane).placed(m));
                continue;
            }
            let child = &self.wide[root.child[lane] as usize];
            for l in child.used_lanes() {
                b = b.union(child.lane_bounds(l).placed(m));
            }
        }
        Some(b)
    }
}
