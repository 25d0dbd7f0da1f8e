//! NFF's entities read inside the parser of another language: AFF ([`crate::aff`])
//! has NFF's `v b l f s c p pp` among its own keywords, and reads them with this
//! module's readers (the same checks, warnings and messages). Its files include
//! others, each lexed on its own, so what the readers keep between entities — the
//! scene so far and the current material — travels from file to file as an
//! [`EntityState`].

use super::error::ParseError;
use super::keywords;
use super::lexer::{Lexer, Token};
use super::limits::Limits;
use super::parser::{Loc, Parser};
use super::Format;
use crate::math::Vec3;
use crate::scene::{Material, Scene, Warning};

/// What NFF's entity readers keep between entities.
#[derive(Clone, Debug, Default)]
pub(crate) struct EntityState {
    /// The entities read so far, as written: camera, background, lights, materials,
    /// spheres, cones, polygons and patches.
    pub scene: Scene,
    /// The current material, `None` before the first.
    material: Option<u32>,
    saw_view: bool,
    saw_background: bool,
}

impl EntityState {
    /// True once a `v` block was read.
    pub(crate) fn saw_view(&self) -> bool {
        self.saw_view
    }
}

/// One file's tokens, read by another language's parser that hands NFF's entities
/// to NFF's readers.
pub(crate) struct Embedded<'a> {
    parser: Parser<'a>,
}

impl<'a> Embedded<'a> {
    /// A reader of `src` (checked text: [`super::scene_text`]) that goes on from
    /// `state`, within `limits`.
    pub(crate) fn new(src: &'a [u8], state: EntityState, limits: &Limits) -> Self {
        let mut parser = Parser::new(Lexer::new(src), Format::Nff, limits, false);
        parser.scene = state.scene;
        parser.material = state.material;
        parser.saw_view = state.saw_view;
        parser.saw_background = state.saw_background;
        Embedded { parser }
    }

    /// The state to go on from in another file (this reader keeps an empty one).
    pub(crate) fn take_state(&mut self) -> EntityState {
        let p = &mut self.parser;
        EntityState {
            scene: std::mem::take(&mut p.scene),
            material: p.material,
            saw_view: p.saw_view,
            saw_background: p.saw_background,
        }
    }

    /// Goes on from `state`, which another file's reader left.
    pub(crate) fn put_state(&mut self, state: EntityState) {
        let p = &mut self.parser;
        p.scene = state.scene;
        p.material = state.material;
        p.saw_view = state.saw_view;
        p.saw_background = state.saw_background;
    }

    /// The next token.
    pub(crate) fn next_token(&mut self) -> Option<Token<'a>> {
        self.parser.lexer.next()
    }

    /// The next token, left unread.
    pub(crate) fn peek(&self) -> Option<Token<'a>> {
        self.parser.lexer.clone().next()
    }

    /// Reads one finite number; `what` names it in the error message.
    pub(crate) fn number(&mut self, what: &str) -> Result<f32, ParseError> {
        self.parser.number(what)
    }

    /// Reads three finite numbers.
    pub(crate) fn vec3(&mut self, what: &str) -> Result<Vec3, ParseError> {
        self.parser.vec3(what)
    }

    /// Reads a non-negative whole number and where it stands.
    pub(crate) fn count(&mut self, what: &str) -> Result<(u32, Loc), ParseError> {
        self.parser.count(what)
    }

    /// The error for finding `tok` (or the end of the file) where `expected` must be.
    pub(crate) fn expected(&self, tok: Option<Token>, expected: &str) -> ParseError {
        self.parser.expected(tok, expected)
    }

    /// Reads the NFF entity whose keyword `kw` has just been taken; `None` if `kw` is
    /// no NFF keyword.
    pub(crate) fn read_entity(&mut self, kw: &Token<'_>) -> Option<Result<(), ParseError>> {
        let keyword = keywords::find(kw.text, Format::Nff)?;
        Some((keyword.read)(&mut self.parser, kw))
    }

    /// The material for a new object: the current one, or (once, with a warning at
    /// `at`) the default before the first.
    pub(crate) fn current_material(&mut self, at: Loc) -> u32 {
        self.parser.current_material(at)
    }

    /// Adds `m` to the material table and makes it the current material.
    pub(crate) fn set_material(&mut self, m: Material) {
        let materials = &mut self.parser.scene.materials;
        materials.push(m);
        self.parser.material = Some((materials.len() - 1) as u32);
    }

    /// Makes material `index` of the table the current one.
    pub(crate) fn use_material(&mut self, index: u32) {
        self.parser.material = Some(index);
    }

    /// The entities read so far.
    pub(crate) fn scene(&self) -> &Scene {
        &self.parser.scene
    }

    /// The entities read so far, to amend.
    pub(crate) fn scene_mut(&mut self) -> &mut Scene {
        &mut self.parser.scene
    }

    /// The warnings of the entities read since the last call.
    pub(crate) fn take_warnings(&mut self) -> Vec<Warning> {
        std::mem::take(&mut self.parser.scene.warnings)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn state_goes_from_file_to_file() {
        let limits = Limits::default();
        let mut first = Embedded::new(b"f 1 0 0 1 0 1 0 1 s 0 0 0 1", EntityState::default(), &limits);
        for _ in 0..2 {
            let kw = first.next_token().unwrap();
            first.read_entity(&kw).unwrap().unwrap();
        }
        let mut second = Embedded::new(b"s 1 1 1 2 zz", first.take_state(), &limits);
        let kw = second.next_token().unwrap();
        second.read_entity(&kw).unwrap().unwrap();
        // The material of the first file is still current: no default, no warning.
        assert_eq!(second.scene().spheres[1].material, 0);
        assert!(second.take_warnings().is_empty());
        let zz = second.next_token().unwrap();
        assert!(second.read_entity(&zz).is_none());
    }
}
