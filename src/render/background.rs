//! What a ray that leaves the scene sees: the background colour, or a skybox
//! ([`crate::image::skybox`], looked up as the P3F course's template does).

use std::sync::Arc;

use crate::image::skybox::{SkyTexel, Skybox};
use crate::math::Vec3;
use crate::scene::Scene;

/// What rays that leave the scene see.
#[derive(Clone, Debug, PartialEq)]
pub enum Background {
    /// One colour in every direction.
    Color(Vec3),
    /// A cube map.
    Skybox(Arc<Skybox>),
}

impl Background {
    /// The scene's background: its skybox when one was loaded, else its colour.
    pub fn of(scene: &Scene) -> Background {
        match scene.environment.as_ref().and_then(|e| e.skybox.clone()) {
            Some(sky) => Background::Skybox(sky),
            None => Background::Color(scene.background),
        }
    }

    /// The colour seen along direction `d`.
    #[inline(always)]
    pub fn color(&self, d: Vec3) -> Vec3 {
        match self {
            Background::Color(c) => *c,
            Background::Skybox(sky) => sky.color(&sky.texel(d)),
        }
    }

    /// The colour seen along direction `d`, and the skybox texel it came from.
    #[inline]
    pub fn look(&self, d: Vec3) -> (Vec3, Option<SkyTexel>) {
        match self {
            Background::Color(c) => (*c, None),
            Background::Skybox(sky) => {
                let t = sky.texel(d);
                (sky.color(&t), Some(t))
            }
        }
    }
}
