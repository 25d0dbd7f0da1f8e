//! Turns AFF files into an [`AffScene`]: the state shared by every file of a scene
//! ([`Builder`]: the scene so far, the open transform nodes, the files read) and
//! the reader of one file ([`FileParser`]), which dispatches through the keyword
//! table (`keywords.rs`). NFF's entities are read by NFF's own readers
//! ([`Embedded`]); AFF's own, one function per keyword, are in `entities.rs`,
//! `mesh.rs`, `hierarchy.rs` and `keyframes.rs`.

use std::collections::HashMap;
use std::path::Path;
use std::sync::atomic::{AtomicBool, Ordering};

use super::error::{AffError, Failure, Read};
use super::include::{IncludeError, Opened, Sources};
use super::keywords;
use super::scene::{AffScene, AffWarning, Location, Node, NodeTransform, Object, Shape};
use crate::limits::MAX_WARNINGS;
use crate::math::Vec3;
use crate::nff::{Embedded, EntityState, Limits, ParseError, ParseErrorKind, Token};

/// Entities read between two looks at the cancellation flag.
const CANCEL_POLL: usize = 256;

/// What every file of a scene adds to.
pub(super) struct Builder<'c> {
    /// The scene so far (its `nff` part travels with the file being read, in
    /// [`EntityState`], until the end).
    pub scene: AffScene,
    /// The files.
    pub sources: Sources,
    /// The open transform nodes, innermost last (the root first).
    pub stack: Vec<u32>,
    /// The scene's detail level (`d`): includes of a higher one are skipped.
    pub detail: i64,
    /// Limits on what the files may describe.
    pub limits: Limits,
    /// Mesh geometry already read, by where its keyword stands: a file included again
    /// gives the same geometry, stored once.
    pub mesh_at: HashMap<(u32, u32, u32), u32>,
    /// Triangles of every mesh placed (each placing counted): those of a flattened frame.
    pub placed_triangles: usize,
    /// Keyframe blocks by name.
    pub track_names: HashMap<String, u32>,
    /// Textures by the path read.
    pub texture_paths: HashMap<std::path::PathBuf, u32>,
    /// Warnings past [`MAX_WARNINGS`], counted instead of kept.
    pub warnings_left_out: usize,
    /// Entities read, for polling `cancel`.
    pub entities: usize,
    /// Raised by the caller to stop early.
    pub cancel: &'c AtomicBool,
}

/// The reader of one file.
pub(super) struct FileParser<'t, 'b, 'c> {
    /// Its tokens, with NFF's readers and their state.
    pub p: Embedded<'t>,
    /// Its index in the scene's files.
    pub file: u32,
    /// Its directory, where the files it names are.
    pub dir: &'t Path,
    /// The scene's state.
    pub b: &'b mut Builder<'c>,
    /// Nodes open when this file started (it closes only those it opens).
    pub open_at_start: usize,
}

/// A 1-based line and column.
pub(super) type Loc = (u32, u32);

/// Where `t` stands.
pub(super) fn loc(t: &Token) -> Loc {
    (t.line, t.column)
}

/// An error of the kind `Invalid` at `at`.
pub(super) fn invalid(at: Loc, message: impl Into<String>) -> ParseError {
    ParseError::new(at.0, at.1, ParseErrorKind::Invalid(message.into()))
}

impl<'c> Builder<'c> {
    /// An empty scene with its root node, reading within `limits` and `max_bytes`.
    pub fn new(limits: &Limits, max_bytes: u64, cancel: &'c AtomicBool) -> Builder<'c> {
        let mut scene = AffScene {
            ambient: Vec3::ONE,
            ..AffScene::default()
        };
        scene.nodes.push(Node {
            parent: None,
            transform: NodeTransform::Root,
            objects: Vec::new(),
            at: Location {
                file: 0,
                line: 1,
                column: 1,
            },
        });
        Builder {
            scene,
            sources: Sources::new(max_bytes),
            stack: vec![0],
            detail: 0,
            limits: *limits,
            mesh_at: HashMap::new(),
            placed_triangles: 0,
            track_names: HashMap::new(),
            texture_paths: HashMap::new(),
            warnings_left_out: 0,
            entities: 0,
            cancel,
        }
    }

    /// Keeps a warning, or counts it past [`MAX_WARNINGS`].
    pub fn warn(&mut self, at: Location, message: String) {
        if self.scene.warnings.len() >= MAX_WARNINGS {
            self.warnings_left_out += 1;
            return;
        }
        self.scene.warnings.push(AffWarning { at, message });
    }

    /// `FILE:LINE:COLUMN` of `at`.
    pub fn describe(&self, at: Location) -> String {
        let file = &self.sources.files[at.file as usize].name;
        format!("{file}:{}:{}", at.line, at.column)
    }

    /// The innermost open node.
    pub fn node(&self) -> u32 {
        *self.stack.last().expect("the root stays open")
    }

    /// Reads `opened` (the top file or an included one) from `state`, returning the
    /// state it leaves.
    pub fn read_file(&mut self, opened: &Opened, state: EntityState) -> Result<EntityState, AffError> {
        let text = opened.text.clone();
        let mut fp = FileParser {
            p: Embedded::new(&text, state, &self.limits),
            file: opened.file,
            dir: &opened.dir,
            open_at_start: self.stack.len(),
            b: self,
        };
        match fp.run() {
            Ok(()) => Ok(fp.p.take_state()),
            Err(Failure::Nested(e)) => Err(e),
            Err(Failure::Here(error)) => Err(AffError {
                file: fp.b.sources.files[fp.file as usize].name.clone(),
                error,
            }),
        }
    }
}

impl FileParser<'_, '_, '_> {
    /// Reads every entity of the file.
    fn run(&mut self) -> Read {
        while let Some(tok) = self.p.next_token() {
            self.b.entities += 1;
            if self.b.entities.is_multiple_of(CANCEL_POLL) && self.b.cancel.load(Ordering::Relaxed) {
                return Err(ParseError::new(tok.line, tok.column, ParseErrorKind::Cancelled).into());
            }
            let Some(read) = keywords::find(tok.text) else {
                return Err(keywords::unknown(&tok).into());
            };
            read(self, &tok)?;
            self.keep_warnings();
        }
        self.close_file()
    }

    /// Refuses a file that leaves a block it opened unclosed.
    fn close_file(&mut self) -> Read {
        if self.b.stack.len() > self.open_at_start {
            let node = &self.b.scene.nodes[self.b.node() as usize];
            let at = (node.at.line, node.at.column);
            return Err(invalid(at, "this block is not closed by a '}' in its file").into());
        }
        Ok(())
    }

    /// Where `t` stands in the scene.
    pub fn at(&self, t: &Token) -> Location {
        Location {
            file: self.file,
            line: t.line,
            column: t.column,
        }
    }

    /// Keeps a warning at `t`.
    pub fn warn(&mut self, t: &Token, message: String) {
        let at = self.at(t);
        self.b.warn(at, message);
    }

    /// Moves the warnings of NFF's readers into the scene's, with this file.
    fn keep_warnings(&mut self) {
        for w in self.p.take_warnings() {
            let at = Location {
                file: self.file,
                line: w.line,
                column: w.column,
            };
            self.b.warn(at, w.message);
        }
    }

    /// Adds a static object of `shape` to the innermost node.
    pub fn add_object(&mut self, shape: Shape, material: u32, kw: &Token) {
        let node = self.b.node();
        let index = self.b.scene.objects.len() as u32;
        self.b.scene.objects.push(Object {
            node,
            material,
            shape,
            at: self.at(kw),
        });
        self.b.scene.nodes[node as usize].objects.push(index);
    }

    /// Reads the next token as a whole number (negative allowed).
    pub fn integer(&mut self, what: &str) -> Result<(i64, Loc), ParseError> {
        let tok = self.p.next_token();
        match tok
            .as_ref()
            .and_then(|t| std::str::from_utf8(t.text).ok()?.parse::<i64>().ok())
        {
            Some(n) => Ok((n, tok.as_ref().map(loc).unwrap_or_default())),
            None => Err(self.p.expected(tok, &format!("a whole number ({what})"))),
        }
    }

    /// Reads the next token as a name (a file, a texture, a transform): any token of
    /// UTF-8 text, and where it stands.
    pub fn name(&mut self, what: &str) -> Result<(String, Loc), ParseError> {
        let tok = self.p.next_token();
        match tok.and_then(|t| Some((std::str::from_utf8(t.text).ok()?.to_string(), loc(&t)))) {
            Some(named) => Ok(named),
            None => Err(self.p.expected(tok, what)),
        }
    }

    /// Takes the `{` that opens a block.
    pub fn open_brace(&mut self, after: &str) -> Result<(), ParseError> {
        match self.p.next_token() {
            Some(t) if t.text == b"{" => Ok(()),
            tok => Err(self.p.expected(tok, &format!("'{{' after {after}"))),
        }
    }

    /// Reads an included file, `name` as written at `at`.
    pub fn include_file(&mut self, name: &str, at: Loc) -> Read {
        let opened = match self.b.sources.include(self.dir, name) {
            Ok(o) => o,
            Err(IncludeError::At(kind)) => return Err(ParseError::new(at.0, at.1, kind).into()),
            Err(IncludeError::In(e)) => return Err(Failure::Nested(e)),
        };
        let state = self.p.take_state();
        let state = self.b.read_file(&opened, state).map_err(Failure::Nested)?;
        self.b.sources.leave();
        self.p.put_state(state);
        Ok(())
    }
}
