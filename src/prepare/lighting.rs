//! The scene's lights as every render reads them, resolved once by the prepare
//! step: which shading rules apply ([`Model`], by the scene's dialect), the ambient
//! intensity, and every light with its intensity (the rules of `render/shade.rs`:
//! NFF's uncoloured lights and ambient term `sqrt(n) / (2n)` for n lights, P3F's
//! lights their own colours and no ambient term, AFF's lights their colours (white
//! without one) and the ambient light its `am`). Plain data: the points a hit
//! samples on a light are the renderer's (`render/light.rs`).

use crate::math::Vec3;
use crate::scene::{Dialect, Light, SceneInfo};

/// Which rules shade the scene (see the module docs).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Model {
    /// NFF: the SPD's Whitted rules.
    Spd,
    /// P3F: the course's, with Schlick-Fresnel dielectrics.
    P3f,
    /// AFF: BART's original renderer's, with `fm`'s colours and textures.
    Aff,
}

/// The model's light intensities and ambient term for one scene.
#[derive(Clone, Debug)]
pub struct Lighting {
    /// The rules.
    pub model: Model,
    /// Ambient intensity.
    pub ambient: Vec3,
    /// Every light with its intensity.
    pub lights: Vec<LightSource>,
}

impl Lighting {
    /// Resolves the scene's model and intensities (see the module docs).
    pub fn new(scene: &SceneInfo) -> Lighting {
        if scene.dialect == Dialect::Aff {
            return Lighting {
                model: Model::Aff,
                ambient: scene.ambient_light.unwrap_or(Vec3::ONE),
                lights: LightSource::of(&scene.lights, Vec3::ONE),
            };
        }
        if scene.dialect != Dialect::Nff {
            return Lighting {
                model: Model::P3f,
                ambient: Vec3::ZERO,
                lights: LightSource::of(&scene.lights, Vec3::ONE),
            };
        }
        let n = scene.lights.len();
        let default = if n == 0 {
            1.0
        } else {
            (n as f32).sqrt() / (2.0 * n as f32)
        };
        Lighting {
            model: Model::Spd,
            ambient: Vec3::splat(default),
            lights: LightSource::of(&scene.lights, Vec3::splat(default)),
        }
    }
}

/// One light of the scene with its intensity resolved.
#[derive(Clone, Copy, Debug)]
pub struct LightSource {
    /// The point light's position, or the area light's corner.
    pub position: Vec3,
    /// Intensity (RGB).
    pub intensity: Vec3,
    /// The area light's extent.
    pub area: Option<LightQuad>,
}

/// An area light's parallelogram: the points `position + u edge1 + v edge2`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct LightQuad {
    /// First edge from the corner.
    pub edge1: Vec3,
    /// Second edge from the corner.
    pub edge2: Vec3,
    /// Points per side of its regular grid.
    pub grid: u32,
}

impl LightSource {
    /// The scene's `lights` with the given intensity for those without a colour.
    pub fn of(lights: &[Light], default_intensity: Vec3) -> Vec<LightSource> {
        lights
            .iter()
            .map(|l| LightSource {
                position: l.position,
                intensity: l.color.unwrap_or(default_intensity),
                area: l.area.map(|a| LightQuad {
                    edge1: a.v1 - l.position,
                    edge2: a.v2 - l.position,
                    grid: a.grid,
                }),
            })
            .collect()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn default_intensity_is_sqrt_n_over_2n() {
        let mut scene = crate::scene::Scene::default();
        for _ in 0..4 {
            scene.lights.push(crate::scene::Light::point(Vec3::ZERO, None));
        }
        let l = Lighting::new(&scene.info());
        assert_eq!(l.ambient, Vec3::splat(0.25));
        assert_eq!(l.lights[3].intensity, Vec3::splat(0.25));
    }
}
