//! What a ray that leaves the scene sees: the background colour, or a skybox
//! ([`crate::image::skybox`], looked up as the P3F course's template does).

use std::sync::Arc;

use crate::image::skybox::{FaceError, SkyTexel, Skybox};
use crate::math::Vec3;

/// What rays that leave the scene see.
#[derive(Clone, Debug)]
pub enum Background {
    /// One colour in every direction.
    Color(Vec3),
    /// A cube map.
    Skybox(Arc<Skybox>),
}

impl Background {
    /// The skybox when there is one, else the background colour.
    pub fn new(color: Vec3, skybox: Option<Arc<Skybox>>) -> Background {
        match skybox {
            Some(sky) => Background::Skybox(sky),
            None => Background::Color(color),
        }
    }

    /// Decodes what is not yet decoded: the first skybox face that could not be
    /// ([`Skybox::decode_all`]).
    pub fn decode_all(&self) -> Result<(), FaceError> {
        match self {
            Background::Color(_) => Ok(()),
            Background::Skybox(sky) => sky.decode_all(),
        }
    }

    /// Seconds spent decoding the skybox's faces so far ([`Skybox::decode_seconds`];
    /// zero without one).
    pub fn decode_seconds(&self) -> f64 {
        match self {
            Background::Color(_) => 0.0,
            Background::Skybox(sky) => sky.decode_seconds(),
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
