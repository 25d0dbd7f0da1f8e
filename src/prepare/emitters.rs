//! What the path tracer samples lights from: the scene's point and quad lights and
//! its emissive primitives, each with a chance proportional to its power.
//!
//! - A point light shines its intensity `I` equally in every direction.
//! - A quad light (P3F `light quad`, `al`) is, as in the Whitted integrator, points
//!   spread over its parallelogram that shine equally in every direction, `I` in
//!   all: a sample is one of them, shining `I`. Neither can be hit by a ray.
//! - An emissive primitive (a material with emission `Le`) emits the radiance `Le`
//!   from the side its own normal points to (one-sided, as Mitsuba 3's area
//!   emitters): triangles (of polygons, patches and meshes), spheres and boxes are
//!   sampled by area; other shapes emit when a ray meets them but are not sampled.
//!
//! Powers (the choice weights): `4 pi mean(I)` for point and quad lights,
//! `pi mean(Le) area` for emissive primitives.

use std::f32::consts::PI;

use super::lighting::LightSource;
use crate::accel::Bvh;
use crate::geometry::{Primitive, Shape};
use crate::math::Vec3;
use crate::scene::Material;

/// One source of light for next-event estimation.
#[derive(Clone, Copy, Debug)]
pub enum Emitter {
    /// A point light of intensity `intensity`.
    Point {
        /// Where it is.
        position: Vec3,
        /// Its intensity.
        intensity: Vec3,
    },
    /// A quad light: the points `corner + u edge1 + v edge2`, `intensity` in all.
    Quad {
        /// A corner.
        corner: Vec3,
        /// First edge from the corner.
        edge1: Vec3,
        /// Second edge from the corner.
        edge2: Vec3,
        /// The total intensity of its points.
        intensity: Vec3,
    },
    /// An emissive triangle (of a polygon, patch or mesh), with what sampling it
    /// needs worked out once (its primitive's index maps to it through
    /// [`Emitters::of_primitive`]).
    Triangle {
        /// The radiance it emits on the side of its own normal.
        radiance: Vec3,
        /// Its area.
        area: f32,
        /// Its first vertex.
        v0: Vec3,
        /// Its edges from `v0` to the second and third vertices.
        edges: (Vec3, Vec3),
        /// Its own unit normal.
        normal: Vec3,
    },
    /// Emissive primitive `primitive` (as the acceleration structure numbers it),
    /// other than a triangle.
    Surface {
        /// The primitive.
        primitive: u32,
        /// The radiance it emits on the side of its own normal.
        radiance: Vec3,
        /// Its area.
        area: f32,
    },
}

/// A point drawn on an emitter, seen from a point of the scene.
#[derive(Clone, Copy, Debug)]
pub struct LightSample {
    /// The point.
    pub point: Vec3,
    /// What arrives from it, before the surface's `f cos`: `I / d^2` for a point or
    /// quad light, `Le cos_light / (d^2 p_area)` for a surface.
    pub incoming: Vec3,
    /// The density of the direction to it, per solid angle, times the emitter's
    /// choice probability; `None` for a point or quad light (it cannot be hit, so no
    /// other strategy competes).
    pub pdf: Option<f32>,
}

/// The scene's emitters and the table to choose among them.
#[derive(Clone, Debug, Default)]
pub struct Emitters {
    list: Vec<Emitter>,
    /// Cumulative choice probabilities (the last is 1).
    cdf: Vec<f32>,
    /// Per primitive index, the emitter it is, or `u32::MAX` (empty without emissive
    /// primitives).
    of_primitive: Vec<u32>,
}

/// The mean of a colour's channels.
fn mean(c: Vec3) -> f32 {
    (c.x + c.y + c.z) / 3.0
}

impl Emitters {
    /// The emitters of a scene with these `lights` and the emissive primitives of
    /// `accel` (by `materials`).
    pub fn new(lights: &[LightSource], accel: &Bvh, materials: &[Material]) -> Emitters {
        let mut list: Vec<Emitter> = lights
            .iter()
            .map(|l| match l.area {
                None => Emitter::Point {
                    position: l.position,
                    intensity: l.intensity,
                },
                Some(q) => Emitter::Quad {
                    corner: l.position,
                    edge1: q.edge1,
                    edge2: q.edge2,
                    intensity: l.intensity,
                },
            })
            .collect();
        let mut of_primitive = Vec::new();
        let emissive = |p: &Primitive| {
            materials
                .get(p.material as usize)
                .is_some_and(|m| m.emission != Vec3::ZERO)
        };
        if accel.primitives().iter().any(emissive) {
            of_primitive = vec![u32::MAX; accel.primitives().len()];
            for (i, p) in accel.primitives().iter().enumerate() {
                let Some(area) = emissive(p).then(|| sample_area(p)).flatten() else {
                    continue;
                };
                of_primitive[i] = list.len() as u32;
                let radiance = materials[p.material as usize].emission;
                list.push(match &p.shape {
                    Shape::Triangle(t) => {
                        let edges = t.edges();
                        Emitter::Triangle {
                            radiance,
                            area,
                            v0: t.v0,
                            edges,
                            normal: edges.0.cross(edges.1).normalize(),
                        }
                    }
                    _ => Emitter::Surface {
                        primitive: i as u32,
                        radiance,
                        area,
                    },
                });
            }
        }
        let powers: Vec<f32> = list
            .iter()
            .map(|e| match *e {
                Emitter::Point { intensity, .. } | Emitter::Quad { intensity, .. } => {
                    4.0 * PI * mean(intensity)
                }
                Emitter::Triangle { radiance, area, .. } | Emitter::Surface { radiance, area, .. } => {
                    PI * mean(radiance) * area
                }
            })
            .map(|p| p.max(0.0))
            .collect();
        let total: f32 = powers.iter().sum();
        let mut cdf = Vec::with_capacity(powers.len());
        let mut acc = 0.0;
        for p in &powers {
            acc += if total > 0.0 {
                p / total
            } else {
                1.0 / powers.len() as f32
            };
            cdf.push(acc);
        }
        if let Some(last) = cdf.last_mut() {
            *last = 1.0;
        }
        Emitters {
            list,
            cdf,
            of_primitive,
        }
    }

    /// True if there is nothing to sample.
    pub fn is_empty(&self) -> bool {
        self.list.is_empty()
    }

    /// The emitter the number `u` chooses, and its choice probability.
    pub fn choose(&self, u: f32) -> Option<(&Emitter, f32)> {
        let k = self
            .cdf
            .partition_point(|&c| c <= u)
            .min(self.list.len().checked_sub(1)?);
        Some((&self.list[k], self.pmf(k)))
    }

    fn pmf(&self, k: usize) -> f32 {
        self.cdf[k] - if k == 0 { 0.0 } else { self.cdf[k - 1] }
    }

    /// For an emissive primitive that is sampled, its choice probability and area.
    pub fn of_primitive(&self, primitive: u32) -> Option<(f32, f32)> {
        let k = *self.of_primitive.get(primitive as usize)?;
        match self.list.get(k as usize)? {
            Emitter::Triangle { area, .. } | Emitter::Surface { area, .. } => {
                Some((self.pmf(k as usize), *area))
            }
            _ => None,
        }
    }

    /// A point of `emitter` (chosen with probability `pmf`) for the numbers `u`, as
    /// seen from `from`; `None` if it sends nothing there (its back, say).
    pub fn sample(
        &self,
        emitter: &Emitter,
        pmf: f32,
        accel: &Bvh,
        from: Vec3,
        u: (f32, f32),
    ) -> Option<LightSample> {
        match *emitter {
            Emitter::Point { position, intensity } => Some(isotropic(position, intensity, from, pmf)),
            Emitter::Quad {
                corner,
                edge1,
                edge2,
                intensity,
            } => Some(isotropic(
                corner + edge1 * u.0 + edge2 * u.1,
                intensity,
                from,
                pmf,
            )),
            Emitter::Triangle {
                radiance,
                area,
                v0,
                edges,
                normal,
            } => area_sample(triangle_point(v0, edges, u), normal, radiance, area, from, pmf),
            Emitter::Surface {
                primitive,
                radiance,
                area,
            } => {
                let (point, normal) = sample_point(accel.primitive(primitive), u)?;
                area_sample(point, normal, radiance, area, from, pmf)
            }
        }
    }
}

/// `point` of an emitter of radiance `radiance` and area `area` (chosen with
/// probability `pmf`), where its own unit normal is `normal`, as seen from `from`;
/// `None` if `from` is behind it.
#[inline(always)]
fn area_sample(
    point: Vec3,
    normal: Vec3,
    radiance: Vec3,
    area: f32,
    from: Vec3,
    pmf: f32,
) -> Option<LightSample> {
    let to = point - from;
    let d2 = to.length_squared();
    let cos_light = -normal.dot(to) / d2.sqrt();
    if cos_light <= 0.0 || d2 == 0.0 {
        return None;
    }
    // Area density 1 / area, per solid angle: d^2 / (cos_light area).
    let pdf = pmf * d2 / (cos_light * area);
    Some(LightSample {
        point,
        incoming: radiance * (1.0 / pdf),
        pdf: Some(pdf),
    })
}

/// The point of the triangle of first vertex `v0` and edges `(e1, e2)` from it for
/// the numbers `u`, uniform on the triangle: barycentrics (1 - sqrt(u1),
/// sqrt(u1) (1 - u2), sqrt(u1) u2).
#[inline(always)]
fn triangle_point(v0: Vec3, (e1, e2): (Vec3, Vec3), (u1, u2): (f32, f32)) -> Vec3 {
    let s = u1.sqrt();
    v0 + e1 * (s * (1.0 - u2)) + e2 * (s * u2)
}

/// A point that shines `intensity` in every direction, seen from `from`.
fn isotropic(point: Vec3, intensity: Vec3, from: Vec3, pmf: f32) -> LightSample {
    let d2 = (point - from).length_squared().max(f32::MIN_POSITIVE);
    LightSample {
        point,
        incoming: intensity * (1.0 / (d2 * pmf)),
        pdf: None,
    }
}

/// The area of a primitive that is sampled by area, `None` for the others.
fn sample_area(p: &Primitive) -> Option<f32> {
    match &p.shape {
        Shape::Triangle(t) => {
            let (e1, e2) = t.edges();
            Some(e1.cross(e2).length() * 0.5).filter(|&a| a > 0.0)
        }
        Shape::Sphere(s) => Some(4.0 * PI * s.radius2).filter(|&a| a > 0.0),
        Shape::Box(b) => {
            let d = b.max - b.min;
            Some(2.0 * (d.x * d.y + d.y * d.z + d.z * d.x)).filter(|&a| a > 0.0)
        }
        _ => None,
    }
}

/// A point of a sphere or box sampled by area, uniformly, for the numbers `u`, and
/// the primitive's own unit normal there (triangles are [`Emitter::Triangle`]s,
/// sampled by [`triangle_point`]).
fn sample_point(p: &Primitive, (u1, u2): (f32, f32)) -> Option<(Vec3, Vec3)> {
    match &p.shape {
        Shape::Sphere(s) => {
            let z = 1.0 - 2.0 * u1;
            let r = (1.0 - z * z).max(0.0).sqrt();
            let phi = 2.0 * PI * u2;
            let out = Vec3::new(r * phi.cos(), r * phi.sin(), z);
            let radius = s.radius2.sqrt();
            let normal = if s.inside { -out } else { out };
            Some((s.center + out * radius, normal))
        }
        Shape::Box(b) => {
            let d = b.max - b.min;
            let faces = [d.y * d.z, d.y * d.z, d.z * d.x, d.z * d.x, d.x * d.y, d.x * d.y];
            let total: f32 = faces.iter().sum();
            let mut pick = u1 * total;
            let mut face = 5;
            for (k, a) in faces.iter().enumerate() {
                if pick < *a {
                    face = k;
                    break;
                }
                pick -= a;
            }
            // The number left within the face, rescaled to [0, 1).
            let v = (pick / faces[face]).clamp(0.0, 1.0);
            let axis = face / 2;
            let (a1, a2) = ((axis + 1) % 3, (axis + 2) % 3);
            let mut point = b.min.to_array();
            let mut normal = [0.0; 3];
            point[axis] = if face % 2 == 0 { b.min[axis] } else { b.max[axis] };
            normal[axis] = if face % 2 == 0 { -1.0 } else { 1.0 };
            point[a1] = b.min[a1] + v * d[a1];
            point[a2] = b.min[a2] + u2 * d[a2];
            Some((Vec3::from_array(point), Vec3::from_array(normal)))
        }
        _ => None,
    }
}
