//! Axis-aligned bounding boxes and the slab test.

use super::{Ray, Vec3};

/// The factor a box's computed exit distance is stretched by before it is compared
/// with the entry, so that rounding never closes a box the ray enters. The computed
/// entry and exit each lie within three roundings of the exact ones, and a ray
/// through a box's edge or corner (where the two are equal, as on the shared edges
/// of a mesh whose triangles bound the boxes) could otherwise miss the box, and the
/// triangle in it: a hole in the mesh (Ize 2013, "Robust BVH ray traversal"; 2^-20
/// is 16 units in the last place, above the 6 needed).
pub const FAR_SCALE: f32 = 1.0 + 1.0 / (1u32 << 20) as f32;

/// An axis-aligned box `[min, max]`. The empty box has `min > max`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Aabb {
    /// Lower corner.
    pub min: Vec3,
    /// Upper corner.
    pub max: Vec3,
}

impl Default for Aabb {
    fn default() -> Self {
        Aabb::EMPTY
    }
}

impl Aabb {
    /// The empty box: the identity of [`Aabb::union`].
    pub const EMPTY: Aabb = Aabb {
        min: Vec3::splat(f32::INFINITY),
        max: Vec3::splat(f32::NEG_INFINITY),
    };

    /// Builds a box from its corners.
    #[inline]
    pub fn new(min: Vec3, max: Vec3) -> Aabb {
        Aabb { min, max }
    }

    /// The smallest box holding both points.
    #[inline]
    pub fn from_points(a: Vec3, b: Vec3) -> Aabb {
        Aabb::new(a.min(b), a.max(b))
    }

    /// True when the box holds no point.
    #[inline]
    pub fn is_empty(&self) -> bool {
        self.min.x > self.max.x || self.min.y > self.max.y || self.min.z > self.max.z
    }

    /// The box of a disc of radius `r` centred at `centre` in the plane perpendicular
    /// to the unit vector `axis`: along coordinate i the disc reaches
    /// r·√(1 − axis_i²) (a zero `axis` gives the box of the sphere of radius `r`).
    pub fn of_disc(centre: Vec3, axis: Vec3, r: f32) -> Aabb {
        let reach = |a: f32| r * (1.0 - a * a).max(0.0).sqrt();
        let reach = Vec3::new(reach(axis.x), reach(axis.y), reach(axis.z));
        Aabb::new(centre - reach, centre + reach)
    }

    /// The smallest box holding both boxes.
    #[inline]
    pub fn union(self, o: Aabb) -> Aabb {
        Aabb::new(self.min.min(o.min), self.max.max(o.max))
    }

    /// The smallest box holding this box and a point.
    #[inline]
    pub fn grow(self, p: Vec3) -> Aabb {
        Aabb::new(self.min.min(p), self.max.max(p))
    }

    /// Edge lengths (negative for an empty box).
    #[inline]
    pub fn extent(&self) -> Vec3 {
        self.max - self.min
    }

    /// The centre point.
    #[inline]
    pub fn centroid(&self) -> Vec3 {
        (self.min + self.max) * 0.5
    }

    /// Surface area; zero for an empty box.
    #[inline]
    pub fn surface_area(&self) -> f32 {
        if self.is_empty() {
            return 0.0;
        }
        let e = self.extent();
        2.0 * (e.x * e.y + e.y * e.z + e.z * e.x)
    }

    /// The box around this box's corners under the affine map `m` (rows of the
    /// linear part with the translation as a fourth column), computed in f64 and
    /// widened by a relative 1e-6, so that it holds the corners' images however f32
    /// arithmetic rounds them; the empty box for an empty box.
    pub fn placed(&self, m: &[[f64; 4]; 3]) -> Aabb {
        if self.is_empty() {
            return Aabb::EMPTY;
        }
        let (lo, hi) = (self.min.to_array(), self.max.to_array());
        let mut min = [f64::INFINITY; 3];
        let mut max = [f64::NEG_INFINITY; 3];
        for corner in 0..8 {
            let p: [f64; 3] =
                std::array::from_fn(|k| f64::from(if corner >> k & 1 == 0 { lo[k] } else { hi[k] }));
            for (i, r) in m.iter().enumerate() {
                let v = r[0] * p[0] + r[1] * p[1] + r[2] * p[2] + r[3];
                min[i] = min[i].min(v);
                max[i] = max[i].max(v);
            }
        }
        let pad = |i: usize| 1e-6 * min[i].abs().max(max[i].abs()) + f64::from(f32::MIN_POSITIVE);
        Aabb::new(
            Vec3::from_array(std::array::from_fn(|i| (min[i] - pad(i)) as f32)),
            Vec3::from_array(std::array::from_fn(|i| (max[i] + pad(i)) as f32)),
        )
    }

    /// True when `o` lies inside this box (boundaries included).
    pub fn contains(&self, o: &Aabb) -> bool {
        o.min.x >= self.min.x
            && o.min.y >= self.min.y
            && o.min.z >= self.min.z
            && o.max.x <= self.max.x
            && o.max.y <= self.max.y
            && o.max.z <= self.max.z
    }

    /// True if `ray` may meet the box within `[0, t_max]`: the slab test with the
    /// exit stretched by [`FAR_SCALE`], so that rounding never closes a box the ray
    /// enters.
    #[inline]
    pub fn may_hit(&self, ray: &Ray, t_max: f32) -> bool {
        let t0 = (self.min - ray.origin).mul_elem(ray.inv_dir);
        let t1 = (self.max - ray.origin).mul_elem(ray.inv_dir);
        let near = t0.min(t1);
        let far = t0.max(t1) * FAR_SCALE;
        near.x.max(near.y).max(near.z).max(0.0) <= far.x.min(far.y).min(far.z).min(t_max)
    }

    /// Slab test: the entry distance if the ray meets the box within `[0, t_max]`.
    #[inline]
    pub fn hit(&self, ray: &Ray, t_max: f32) -> Option<f32> {
        let t0 = (self.min - ray.origin).mul_elem(ray.inv_dir);
        let t1 = (self.max - ray.origin).mul_elem(ray.inv_dir);
        let near = t0.min(t1);
        let far = t0.max(t1);
        let t_enter = near.x.max(near.y).max(near.z).max(0.0);
        let t_exit = far.x.min(far.y).min(far.z).min(t_max);
        (t_enter <= t_exit).then_some(t_enter)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn union_contains_both() {
        let a = Aabb::new(Vec3::ZERO, Vec3::ONE);
        let b = Aabb::new(Vec3::splat(-1.0), Vec3::splat(0.5));
        let u = a.union(b);
        assert!(u.contains(&a) && u.contains(&b));
        assert_eq!(Aabb::EMPTY.union(a), a);
    }

    #[test]
    fn slab_test_hits_and_misses() {
        let b = Aabb::new(Vec3::splat(-1.0), Vec3::ONE);
        let r = Ray::new(Vec3::new(0.0, 0.0, -5.0), Vec3::new(0.0, 0.0, 1.0));
        assert_eq!(b.hit(&r, f32::INFINITY), Some(4.0));
        assert_eq!(b.hit(&r, 3.0), None);
        let miss = Ray::new(Vec3::new(2.0, 0.0, -5.0), Vec3::new(0.0, 0.0, 1.0));
        assert_eq!(b.hit(&miss, f32::INFINITY), None);
        let inside = Ray::new(Vec3::ZERO, Vec3::new(1.0, 0.0, 0.0));
        assert_eq!(b.hit(&inside, f32::INFINITY), Some(0.0));
    }

    #[test]
    fn surface_area_of_unit_cube() {
        assert_eq!(Aabb::new(Vec3::ZERO, Vec3::ONE).surface_area(), 6.0);
        assert_eq!(Aabb::EMPTY.surface_area(), 0.0);
    }
}
