//! The Whitted recursion: closest hit, shadows, reflection and refraction.

use super::shade::{reflect, refract, Lighting};
use super::stats::Stats;
use crate::accel::Bvh;
use crate::math::{Ray, Vec3};
use crate::scene::{Material, Scene};

/// Secondary-ray origins are pushed off the surface by this fraction of the
/// magnitude of the coordinates involved (see [`offset_scale`]).
const OFFSET_REL: f32 = 4e-6;

/// Everything needed to trace rays through one scene.
pub struct Tracer<'a> {
    bvh: &'a Bvh,
    materials: &'a [Material],
    lighting: Lighting,
    background: Vec3,
    max_depth: u32,
}

/// How far to push a secondary ray's origin off the surface at `p`, hit by `ray`
/// at distance `t`: proportional to the floating-point error of `p = o + t d`, so it
/// works for tiny and huge scenes alike (no global epsilon).
#[inline]
fn offset_scale(p: Vec3, ray: &Ray, t: f32) -> f32 {
    OFFSET_REL * (p.abs().max_elem() + ray.origin.abs().max_elem() + t) + f32::MIN_POSITIVE
}

impl<'a> Tracer<'a> {
    /// Prepares lighting for `scene`, traced through `bvh`.
    pub fn new(scene: &'a Scene, bvh: &'a Bvh, max_depth: u32) -> Self {
        Tracer {
            bvh,
            materials: &scene.materials,
            lighting: Lighting::new(scene),
            background: scene.background,
            max_depth,
        }
    }

    /// Traces an eye ray (depth 1), counting it.
    #[inline]
    pub fn trace_eye(&self, ray: &Ray, stats: &mut Stats) -> Vec3 {
        stats.eye_rays += 1;
        let c = self.trace(ray, 1, stats);
        // A NaN or infinity never reaches the image.
        if c.is_finite() {
            c
        } else {
            Vec3::ZERO
        }
    }

    /// The colour seen along `ray` at ray-tree depth `depth`.
    fn trace(&self, ray: &Ray, depth: u32, stats: &mut Stats) -> Vec3 {
        let Some((hit, index)) = self.bvh.closest_hit(ray, f32::INFINITY) else {
            return self.background;
        };
        if depth == 1 {
            stats.eye_hits += 1;
        } else {
            stats.secondary_hits += 1;
        }
        let prim = self.bvh.primitive(index);
        let surface = prim.surface(ray, &hit, self.bvh.data());
        let m = &self.materials[prim.material as usize];
        let p = surface.point;
        // Turn the normals to face the incoming ray; `entering` says whether the ray
        // crosses the surface against the primitive's own normal (into the object).
        let entering = surface.normal.dot(ray.dir) < 0.0;
        let (n, ns) = if entering {
            (surface.normal, surface.shading_normal)
        } else {
            (-surface.normal, -surface.shading_normal)
        };
        let eps = offset_scale(p, ray, hit.t);
        let above = p + n * eps;
        let view = -ray.dir;

        let diffuse = m.color * m.kd;
        let mut color = self.lighting.ambient.mul_elem(diffuse);
        for &(light_pos, intensity) in &self.lighting.lights {
            let to_light = light_pos - above;
            // No shadow ray when the light is behind the surface (SPD rule 6).
            if n.dot(to_light) <= 0.0 {
                continue;
            }
            let dist = to_light.length();
            let l = to_light / dist;
            stats.shadow_rays += 1;
            if self.bvh.occluded(&Ray::new(above, l), dist) {
                stats.shadow_blocked += 1;
                continue;
            }
            let lambert = ns.dot(l).max(0.0);
            let h = (l + view).normalize();
            // A negative exponent would turn a zero cosine into infinity.
            let phong = if m.ks > 0.0 {
                m.ks * ns.dot(h).max(0.0).powf(m.shine.max(0.0))
            } else {
                0.0
            };
            color += intensity.mul_elem(diffuse * lambert + Vec3::splat(phong));
        }

        if depth >= self.max_depth || (m.ks <= 0.0 && m.t <= 0.0) {
            return color;
        }
        let mut reflect_weight = m.ks;
        if m.t > 0.0 {
            // Indices of refraction of 0 or less (seen on opaque materials) mean 1.
            let ior = if m.ior > 0.0 { m.ior } else { 1.0 };
            let eta = if entering { 1.0 / ior } else { ior };
            match refract(ray.dir, n, eta) {
                Some(dir) => {
                    stats.refraction_rays += 1;
                    let below = p - n * eps;
                    color += self.trace(&Ray::new(below, dir), depth + 1, stats) * m.t;
                }
                // Total internal reflection: the transmitted share goes to the mirror ray.
                None => reflect_weight += m.t,
            }
        }
        stats.reflection_rays += 1;
        let r = Ray::new(above, reflect(ray.dir, n));
        color + self.trace(&r, depth + 1, stats) * reflect_weight
    }
}
