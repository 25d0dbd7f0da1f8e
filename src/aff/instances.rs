//! Which of an AFF scene's meshes a frame places as instances, and the prototypes
//! they place: one mesh geometry under one material, in its own space, built once
//! (see [`crate::geometry::instance`]) however many objects place it and however
//! their transforms move. The rest are copied into each frame in world space.

use std::collections::HashMap;
use std::sync::{Arc, OnceLock};

use super::scene::{AffScene, Shape};
use super::transform::Affine;
use crate::scene::{Dialect, Scene};

/// Meshes with fewer triangles than this are copied into each frame: entering an
/// instance costs a ray a transform and a walk of its own, which so few triangles
/// do not repay (BENCHMARKS.md, "With instances": a threshold of 8 cost the robots
/// 9 % of their frames per second against 64).
const MIN_INSTANCE_TRIANGLES: u32 = 64;

/// The policy: a mesh of `triangles` triangles, placed by `placings` objects, some
/// of them under a keyframed transform if `moves`, is an instance when it is big
/// enough and building it once saves something: a copy per placing (memory), or a
/// build per frame (the update).
fn is_instance(triangles: u32, placings: u32, moves: bool) -> bool {
    triangles >= MIN_INSTANCE_TRIANGLES && (placings > 1 || moves)
}

/// How a frame places the scene's meshes.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum MeshMode {
    /// The meshes the policy picks as instances of prototypes built once, the
    /// others copied.
    #[default]
    Instanced,
    /// Every mesh copied into world space (what `nffrt convert` writes, and the
    /// comparison `--flatten-meshes` asks for).
    Copied,
}

/// The prototypes of a scene and which object places which.
#[derive(Clone, Debug, PartialEq)]
pub(super) struct Prototypes {
    /// Each one mesh geometry under one material, in its own space.
    pub scenes: Arc<Vec<Scene>>,
    /// Per object of [`AffScene::objects`], the prototype it places, or `None` for
    /// an object copied into each frame.
    pub of_object: Vec<Option<u32>>,
}

/// [`Prototypes`] worked out on first use; derived from the rest of the scene, so
/// two scenes compare equal whatever theirs hold.
#[derive(Clone, Debug, Default)]
pub struct LazyPrototypes(OnceLock<Prototypes>);

impl PartialEq for LazyPrototypes {
    fn eq(&self, _: &LazyPrototypes) -> bool {
        true
    }
}

impl AffScene {
    /// The scene's prototypes, worked out on first use.
    pub(super) fn prototypes(&self) -> &Prototypes {
        self.lazy_prototypes.0.get_or_init(|| self.make_prototypes())
    }

    /// Picks the instanced meshes by the policy and makes a prototype of each
    /// geometry and material they place, in the order objects first place them.
    fn make_prototypes(&self) -> Prototypes {
        let moving = self.moving_nodes();
        let mut placings = vec![0u32; self.meshes.geometries.len()];
        let mut moves = vec![false; self.meshes.geometries.len()];
        for object in &self.objects {
            if let Shape::Mesh(g) = object.shape {
                placings[g as usize] += 1;
                moves[g as usize] |= moving[object.node as usize];
            }
        }
        let mut materials = self.nff.materials.clone();
        let textured = self.textured_materials(&mut materials);
        let mut scenes = Vec::new();
        let mut index: HashMap<(u32, u32), u32> = HashMap::new();
        let of_object = self
            .objects
            .iter()
            .map(|object| {
                let Shape::Mesh(g) = object.shape else {
                    return None;
                };
                let geometry = &self.meshes.geometries[g as usize];
                let i = g as usize;
                if !is_instance(geometry.triangles.count, placings[i], moves[i]) {
                    return None;
                }
                let material = self.mesh_material(geometry, object.material, &textured);
                let prototype = *index.entry((g, material)).or_insert_with(|| {
                    // With the textures named, the mesh keeps its texture
                    // coordinates (`place_mesh`); the prototype needs no more of them.
                    let mut scene = Scene {
                        dialect: Dialect::Aff,
                        textures: self.textures.iter().map(|t| t.image.clone()).collect(),
                        ..Scene::default()
                    };
                    self.place_mesh(geometry, &Affine::IDENTITY, material, object.at.line, &mut scene);
                    scene.textures.clear();
                    scenes.push(scene);
                    (scenes.len() - 1) as u32
                });
                Some(prototype)
            })
            .collect();
        Prototypes {
            scenes: Arc::new(scenes),
            of_object,
        }
    }
}
