//! The scene at a time: each keyframe block's transform (the original's
//! `_GetMatrix`: `T * R * S` from its curves, each missing curve the identity), each
//! node's transform to world space (its parent's times its own), which nodes show
//! (`visibility` keys hide a keyframed node's subtree), the camera (`GetCamera`),
//! the lights and the animated triangles.

use super::scene::{AffScene, AnimatedTriangle, NodeTransform, Track};
use super::transform::{Affine, Quat};
use crate::math::Vec3;
use crate::scene::View;

impl Track {
    /// The transform at time `t`: scale, then rotation, then translation.
    pub fn matrix_at(&self, t: f64) -> Affine {
        let rotation = match &self.rotation {
            // Through angle and axis, as the original: the axis comes out of unit length.
            Some(r) => {
                let (angle, axis) = r.at(t);
                Quat::from_angle_axis(angle, axis).to_matrix()
            }
            None => Affine::IDENTITY.linear(),
        };
        let scale = self.scale.as_ref().map_or([1.0; 3], |s| s.at(t));
        let translation = self.translation.as_ref().map_or([0.0; 3], |p| p.at(t));
        Affine::trs(translation, rotation, scale)
    }

    /// True if the block's transforms show at time `t`: visible until the first
    /// `visibility` key, then as the last key reached says (the original's
    /// `_GetVisibility`, which reads the keys in file order).
    pub fn visible_at(&self, t: f64) -> bool {
        let mut visible = true;
        let mut since = f64::NEG_INFINITY;
        for (q, k) in self.visibility.iter().enumerate() {
            let time = k.time as f64;
            if t >= since && t < time {
                return visible;
            }
            if t >= time && q == self.visibility.len() - 1 {
                return k.visible;
            }
            (visible, since) = (k.visible, time);
        }
        true
    }
}

impl AffScene {
    /// Each node's transform to world space at time `t`, in node order.
    pub fn node_transforms(&self, t: f64) -> Vec<Affine> {
        let mut world: Vec<Affine> = Vec::with_capacity(self.nodes.len());
        for node in &self.nodes {
            let local = match &node.transform {
                NodeTransform::Root => Affine::IDENTITY,
                NodeTransform::Static(m) => *m,
                NodeTransform::Animated { track, .. } => match track {
                    Some(i) => self.tracks[*i as usize].matrix_at(t),
                    None => Affine::IDENTITY,
                },
            };
            // A parent comes before its children.
            world.push(match node.parent {
                Some(p) => world[p as usize] * local,
                None => local,
            });
        }
        world
    }

    /// Whether each node shows at time `t`: not if it or a node above it is hidden
    /// by its keyframe block's `visibility` keys.
    pub fn node_visibility(&self, t: f64) -> Vec<bool> {
        let mut shown: Vec<bool> = Vec::with_capacity(self.nodes.len());
        for node in &self.nodes {
            let own = match &node.transform {
                NodeTransform::Animated { track: Some(i), .. } => self.tracks[*i as usize].visible_at(t),
                _ => true,
            };
            shown.push(own && node.parent.is_none_or(|p| shown[p as usize]));
        }
        shown
    }

    /// The camera at time `t`: the `v` block's, moved by the keyframe block
    /// `camera` if there is one — its translation places the eye, and its matrix's
    /// columns give the view direction (minus the third) and the up vector (the
    /// second): the camera looks down its own -z with +y up. The result may be
    /// degenerate (a zero scale, say): the caller checks it.
    pub fn camera_at(&self, t: f64) -> View {
        let mut view = self.nff.view;
        let Some(track) = self.camera_track.map(|i| &self.tracks[i as usize]) else {
            return view;
        };
        let to_vec3 = |a: [f64; 3]| Vec3::from_array(a.map(|x| x as f32));
        let direction = view.at - view.from;
        if let Some(p) = &track.translation {
            view.from = to_vec3(p.at(t));
            view.at = view.from + direction;
        }
        if track.rotation.is_some() {
            let m = track.matrix_at(t);
            let [x, y, z] = m.column(2);
            view.at = view.from + to_vec3([-x, -y, -z]);
            view.up = to_vec3(m.column(1));
        }
        view
    }

    /// The position of light `i` at time `t`, in world space: as written, or from
    /// the translation of the keyframe block of its `la` name, in its node's space.
    pub fn light_position_at(&self, i: usize, t: f64, world: &[Affine]) -> Vec3 {
        let place = &self.light_places[i];
        let track = place.track.map(|k| &self.tracks[k as usize]);
        let local = match track.and_then(|k| k.translation.as_ref()) {
            Some(p) => Vec3::from_array(p.at(t).map(|x| x as f32)),
            None => self.nff.lights[i].position,
        };
        world[place.node as usize].point(local)
    }
}

impl AnimatedTriangle {
    /// The corners and their normals at time `t`, in its node's space: those of its
    /// first time before it, of its last after, and in between interpolated
    /// linearly between the two times around `t`.
    pub fn at(&self, t: f64) -> ([Vec3; 3], [Vec3; 3]) {
        let keys = &self.keys;
        let first = &keys[0];
        let last = &keys[keys.len() - 1];
        if t <= first.time as f64 {
            return (first.vertices, first.normals);
        }
        if t >= last.time as f64 {
            return (last.vertices, last.normals);
        }
        // The first key after t; the one before it is at or before t, and earlier.
        let j = keys
            .iter()
            .position(|k| t < k.time as f64)
            .unwrap_or(keys.len() - 1);
        let (a, b) = (&keys[j - 1], &keys[j]);
        let u = ((t - a.time as f64) / (b.time as f64 - a.time as f64)) as f32;
        let mix = |p: [Vec3; 3], q: [Vec3; 3]| [0, 1, 2].map(|c| p[c] + (q[c] - p[c]) * u);
        (mix(a.vertices, b.vertices), mix(a.normals, b.normals))
    }
}
