//! The end of a scene's parse: names joined up once every file is read (keyframe
//! blocks may come after the transforms they move, or in another file), and the
//! scene's closing warnings.

use super::parser::Builder;
use super::scene::{AffScene, Location, NodeTransform};
use crate::nff::EntityState;

impl Builder<'_> {
    /// The scene, from the state the last file left.
    pub fn finish(mut self, state: EntityState) -> AffScene {
        if !state.saw_view() {
            let message =
                "no 'v' block: using the default camera (from 0 0 10, at 0 0 0, up 0 1 0, angle 45, 512x512)";
            self.warn(Location::default(), message.into());
        }
        self.scene.nff = state.scene;
        self.scene.fills.resize(self.scene.nff.materials.len(), None);
        self.link_tracks();
        self.scene.files = std::mem::take(&mut self.sources.files);
        self.scene.inclusions = self.sources.inclusions;
        if self.warnings_left_out > 0 {
            let n = self.warnings_left_out;
            self.scene.warnings.push(super::scene::AffWarning {
                at: Location::default(),
                message: format!("... and {n} more warnings"),
            });
        }
        self.scene
    }

    /// Gives each keyframed transform, the camera and each `la` light its keyframe
    /// block, warning of a transform without one (it stays the identity, as the
    /// original's `GetMatrix` gives for a name it does not find) and of a block
    /// nothing uses.
    fn link_tracks(&mut self) {
        let mut used = vec![false; self.scene.tracks.len()];
        let mut orphans = Vec::new();
        for node in &mut self.scene.nodes {
            if let NodeTransform::Animated { name, track } = &mut node.transform {
                *track = self.track_names.get(name.as_str()).copied();
                match *track {
                    Some(i) => used[i as usize] = true,
                    None => orphans.push((node.at, name.clone())),
                }
            }
        }
        for place in &mut self.scene.light_places {
            place.track = place.name.as_ref().and_then(|n| self.track_names.get(n).copied());
            if let Some(i) = place.track {
                used[i as usize] = true;
            }
        }
        self.scene.camera_track = self.track_names.get("camera").copied();
        if let Some(i) = self.scene.camera_track {
            used[i as usize] = true;
        }
        for (at, name) in orphans {
            let message =
                format!("no keyframe block 'k {name}': the transform 'x {name}' stays the identity");
            self.warn(at, message);
        }
        let unused: Vec<(Location, String)> = (self.scene.tracks.iter().zip(&used))
            .filter(|(_, &u)| !u)
            .map(|(k, _)| (k.at, k.name.clone()))
            .collect();
        for (at, name) in unused {
            let message =
                format!("no transform, camera or light is named '{name}': its keyframes move nothing");
            self.warn(at, message);
        }
    }
}
