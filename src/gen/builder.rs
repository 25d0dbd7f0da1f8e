//! What every SPD generator shares: the sky-blue background, the camera block, the
//! lights, the SPD's material convention, and the bookkeeping of output lines.
//!
//! The SPD prints every number with C's `%g` (six significant digits). The camera,
//! lights, background and materials are given that same rounding here, so they equal
//! the SPD's files exactly; geometry keeps full `f32` precision.
//!
//! Each primitive's `line` is the line it will occupy when [`crate::nff::write_nff`]
//! writes the scene: the writer emits primitives in `line` order, which reproduces
//! the SPD's interleaving of kinds (a cylinder, then its sphere, ...), and parsing
//! that output gives back exactly the generated scene.

use super::dvec::D3;
use crate::math::Vec3;
use crate::scene::{Cone, Light, Material, Patch, Polygon, Scene, Sphere, View};

/// The background of every SPD scene ("UNC sky blue").
const SKY_BLUE: [f64; 3] = [0.078, 0.361, 0.753];

/// Lines the writer spends on `b` and the `v` block before the first light.
const HEADER_LINES: u32 = 8;

/// Rounds like C's `printf("%g")`: six significant digits.
pub(crate) fn spd_round(x: f64) -> f32 {
    format!("{x:.5e}").parse().unwrap_or(x as f32)
}

fn spd_round3(v: D3) -> Vec3 {
    Vec3::new(spd_round(v.x), spd_round(v.y), spd_round(v.z))
}

/// The camera of an SPD scene: always 45 degrees and 512 x 512; only the hither
/// distance varies.
pub(crate) struct Camera {
    pub from: D3,
    pub at: D3,
    pub up: D3,
    pub hither: f64,
}

/// A surface as the SPD describes it (the arguments of its `lib_output_color`
/// that NFF keeps). The ambient and highlight-strength arguments have no NFF field.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Surface {
    pub color: [f64; 3],
    pub kd: f64,
    pub ks: f64,
    /// Half-angle in degrees at which the highlight falls to half strength.
    pub highlight_deg: f64,
    pub t: f64,
    pub ior: f64,
}

impl Surface {
    /// The NFF material: the Phong exponent is the power at which `cos(angle)`
    /// falls to one half, `ln 0.5 / ln cos(angle)`; a zero angle means a
    /// (practically invisible) exponent of 100000 and a right angle or more means 1.
    fn material(&self) -> Material {
        let a = self.highlight_deg.to_radians();
        let shine = if a <= 0.0 {
            100000.0
        } else if a >= std::f64::consts::FRAC_PI_2 {
            1.0
        } else {
            0.5f64.ln() / a.cos().ln()
        };
        let [r, g, b] = self.color;
        Material {
            color: Vec3::new(spd_round(r), spd_round(g), spd_round(b)),
            kd: spd_round(self.kd),
            specular: Vec3::ONE,
            ks: spd_round(self.ks),
            shine: spd_round(shine),
            t: spd_round(self.t),
            ior: spd_round(self.ior),
            ..Material::DEFAULT
        }
    }
}

/// Collects a generated scene.
pub(crate) struct Builder {
    scene: Scene,
    /// The line the next written item will occupy.
    line: u32,
    /// The material set by the last [`Builder::surface`].
    pending: Material,
    /// The material index of the last primitive.
    current: Option<u32>,
}

impl Builder {
    /// Starts a scene with the SPD's background, `camera` and white point lights.
    pub fn new(camera: Camera, lights: &[D3]) -> Self {
        let [r, g, b] = SKY_BLUE.map(spd_round);
        let view = View {
            from: spd_round3(camera.from),
            at: spd_round3(camera.at),
            up: spd_round3(camera.up),
            angle: 45.0,
            hither: spd_round(camera.hither),
            width: 512,
            height: 512,
            ..View::default()
        };
        let lights = lights
            .iter()
            .map(|&p| Light::point(spd_round3(p), None))
            .collect();
        let scene = Scene {
            view,
            background: Vec3::new(r, g, b),
            lights,
            ..Scene::default()
        };
        Builder {
            line: HEADER_LINES + 1 + scene.lights.len() as u32,
            scene,
            pending: Material::DEFAULT,
            current: None,
        }
    }

    /// Reserves room for the primitives to come (a hint; counts may be off).
    pub fn reserve(&mut self, spheres: usize, cones: usize, polygon_vertices: usize, patch_vertices: usize) {
        let s = &mut self.scene;
        s.spheres.reserve(spheres);
        s.cones.reserve(cones);
        s.polygons.reserve(polygon_vertices / 3);
        s.polygon_vertices.reserve(polygon_vertices);
        s.patches.reserve(patch_vertices / 3);
        s.patch_vertices.reserve(patch_vertices);
        s.patch_normals.reserve(patch_vertices);
    }

    /// Sets the surface of the primitives that follow.
    pub fn surface(&mut self, s: Surface) {
        self.pending = s.material();
    }

    /// The material index for the next primitive, counting the `f` line the writer
    /// will emit when the index changes. Mirrors the parser, which reuses the
    /// previous table entry for an `f` equal to it.
    fn material(&mut self) -> u32 {
        let mats = &mut self.scene.materials;
        if let Some(i) = self.current {
            if mats[i as usize] == self.pending {
                return i;
            }
        }
        if mats.last() != Some(&self.pending) {
            mats.push(self.pending);
        }
        let i = (mats.len() - 1) as u32;
        self.current = Some(i);
        self.line += 1;
        i
    }

    /// The line of the next primitive's keyword; advances past its `extra` lines.
    fn take_line(&mut self, extra: u32) -> u32 {
        let line = self.line;
        self.line += 1 + extra;
        line
    }

    /// A polygon (`p`).
    pub fn polygon(&mut self, pts: &[D3]) {
        let material = self.material();
        let line = self.take_line(pts.len() as u32);
        let first = self.scene.polygon_vertices.len() as u32;
        self.scene.polygon_vertices.extend(pts.iter().map(|p| p.to_f32()));
        self.scene.polygons.push(Polygon {
            first,
            count: pts.len() as u32,
            material,
            line,
        });
    }

    /// A polygonal patch (`pp`), vertices with their normals.
    pub fn patch(&mut self, pts: &[D3], normals: &[D3]) {
        debug_assert_eq!(pts.len(), normals.len());
        let material = self.material();
        let line = self.take_line(pts.len() as u32);
        let first = self.scene.patch_vertices.len() as u32;
        self.scene.patch_vertices.extend(pts.iter().map(|p| p.to_f32()));
        self.scene
            .patch_normals
            .extend(normals.iter().map(|n| n.to_f32()));
        self.scene.patches.push(Patch {
            first,
            count: pts.len() as u32,
            material,
            line,
        });
    }

    /// A sphere (`s`).
    pub fn sphere(&mut self, center: D3, radius: f64) {
        let material = self.material();
        let line = self.take_line(0);
        self.scene.spheres.push(Sphere {
            center: center.to_f32(),
            radius: radius as f32,
            material,
            line,
        });
    }

    /// A cone or cylinder (`c`).
    pub fn cone(&mut self, base: D3, base_radius: f64, apex: D3, apex_radius: f64) {
        let material = self.material();
        let line = self.take_line(0);
        self.scene.cones.push(Cone {
            base: base.to_f32(),
            base_radius: base_radius as f32,
            apex: apex.to_f32(),
            apex_radius: apex_radius as f32,
            material,
            line,
        });
    }

    /// The finished scene.
    pub fn finish(self) -> Scene {
        self.scene
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn rounding_keeps_six_significant_digits() {
        assert_eq!(spd_round(2.613125929752753), 2.61313);
        assert_eq!(spd_round(-0.004103), -0.004103);
        assert_eq!(spd_round(100000.0), 100000.0);
        assert_eq!(spd_round(0.0), 0.0);
    }

    #[test]
    fn highlight_angle_becomes_the_spd_exponent() {
        let s = |deg| Surface {
            color: [1.0; 3],
            kd: 1.0,
            ks: 0.0,
            highlight_deg: deg,
            t: 0.0,
            ior: 1.0,
        };
        assert_eq!(s(37.0).material().shine, 3.0827);
        assert_eq!(s(0.0).material().shine, 100000.0);
        assert_eq!(s(90.0).material().shine, 1.0);
    }

    #[test]
    fn lines_count_header_lights_materials_and_vertices() {
        let cam = Camera {
            from: D3::new(0.0, 0.0, 5.0),
            at: D3::ZERO,
            up: D3::Z,
            hither: 1.0,
        };
        let mut b = Builder::new(cam, &[D3::Z, D3::Z]);
        let red = Surface {
            color: [1.0, 0.0, 0.0],
            kd: 1.0,
            ks: 0.0,
            highlight_deg: 0.0,
            t: 0.0,
            ior: 1.0,
        };
        b.surface(red);
        b.sphere(D3::ZERO, 1.0);
        b.polygon(&[D3::ZERO, D3::Z, D3::new(1.0, 0.0, 0.0)]);
        b.surface(red);
        b.sphere(D3::Z, 0.5);
        let s = b.finish();
        // b, v + 6 view lines, 2 lights = 10 lines; then f on 11.
        assert_eq!(s.spheres[0].line, 12);
        assert_eq!(s.polygons[0].line, 13);
        assert_eq!(s.spheres[1].line, 17);
        assert_eq!(s.materials.len(), 1);
    }
}
