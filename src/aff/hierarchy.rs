//! The transform blocks: `xs` (static) and `x NAME` (keyframed) open a node whose
//! contents are in its own space, `}` closes it. Blocks nest; a file closes the
//! blocks it opens.

use super::error::Read;
use super::parser::{invalid, loc, FileParser};
use super::scene::{Node, NodeTransform};
use super::transform::{rotation_about, Affine};
use crate::nff::Token;

impl FileParser<'_, '_, '_> {
    /// `xs sx sy sz  rx ry rz degrees  tx ty tz { ... }`: the contents scaled, then
    /// rotated by `degrees` about the axis, then translated (`T * R * S`).
    pub(super) fn static_transform(&mut self, kw: &Token) -> Read {
        let scale = self.p.vec3("'xs' scale x y z")?;
        let axis_at = self.p.peek().map_or(loc(kw), |t| loc(&t));
        let axis = self.p.vec3("'xs' rotation axis x y z")?;
        let degrees = self.p.number("'xs' rotation angle in degrees")?;
        let translation = self.p.vec3("'xs' translation x y z")?;
        if axis.length_squared() == 0.0 && degrees != 0.0 {
            return Err(invalid(axis_at, "a rotation about a zero axis").into());
        }
        let f64s = |v: crate::math::Vec3| [v.x as f64, v.y as f64, v.z as f64];
        let rotation = rotation_about(f64s(axis), (degrees as f64).to_radians());
        let m = Affine::trs(f64s(translation), rotation, f64s(scale));
        self.open_brace("the 'xs' transform")?;
        self.open_node(NodeTransform::Static(m), kw);
        Ok(())
    }

    /// `x NAME { ... }`: the contents moved by the keyframe block `k NAME` (which may
    /// come later, or in another file).
    pub(super) fn animated_transform(&mut self, kw: &Token) -> Read {
        let (name, _) = self.name("the transform's name")?;
        self.open_brace(&format!("'x {name}'"))?;
        self.open_node(NodeTransform::Animated { name, track: None }, kw);
        Ok(())
    }

    /// Opens a node inside the innermost one.
    fn open_node(&mut self, transform: NodeTransform, kw: &Token) {
        let index = self.b.scene.nodes.len() as u32;
        self.b.scene.nodes.push(Node {
            parent: Some(self.b.node()),
            transform,
            objects: Vec::new(),
            at: self.at(kw),
        });
        self.b.stack.push(index);
    }

    /// `}` (one per character of the token): closes the innermost block, which must
    /// have opened in this file.
    pub(super) fn close_blocks(&mut self, kw: &Token) -> Read {
        for _ in kw.text {
            if self.b.stack.len() <= self.open_at_start {
                return Err(invalid(loc(kw), "'}' closes no block opened in this file").into());
            }
            self.b.stack.pop();
        }
        Ok(())
    }
}
