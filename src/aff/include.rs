//! The files of an AFF scene: `i DETAIL NAME` includes NAME, found from the
//! including file's directory. Each file is read once however often it is included
//! (the robot scene includes one material file 291 times), checked as text
//! ([`crate::nff::scene_text`]) and given AFF's comments: `%` starts one, as `#`
//! does. Refused, at the include: a file that is missing or unreadable, one that
//! includes itself (directly or not), includes nested deeper than
//! [`MAX_INCLUDE_DEPTH`], more than [`MAX_INCLUSIONS`] includes followed in all, and
//! files adding up to more bytes than the scene may have.

use std::collections::HashMap;
use std::io::Read as _;
use std::path::{Path, PathBuf};
use std::sync::Arc;

use super::error::AffError;
use super::scene::SourceFile;
use crate::limits::{MAX_INCLUDE_DEPTH, MAX_INCLUSIONS};
use crate::nff::{scene_text, ParseError, ParseErrorKind};

/// A file ready to lex: its index in [`Sources::files`], its text and its directory.
#[derive(Clone, Debug)]
pub(super) struct Opened {
    /// Index into the scene's files.
    pub file: u32,
    /// The text, `%` comments made `#` ones.
    pub text: Arc<[u8]>,
    /// Where the files it names are found.
    pub dir: PathBuf,
}

/// Why an include was refused: a problem at the include, or in the included file
/// (its bytes are not text).
pub(super) enum IncludeError {
    /// At the include's file name.
    At(ParseErrorKind),
    /// In the included file.
    In(AffError),
}

/// The scene's files, read so far.
#[derive(Debug, Default)]
pub(super) struct Sources {
    /// Every file read, the top one first.
    pub files: Vec<SourceFile>,
    /// The files read, by canonical path.
    read: HashMap<PathBuf, Opened>,
    /// Canonical paths of the files being read, outermost first (the top file's only
    /// if it has a path).
    active: Vec<PathBuf>,
    /// How deep the files being read nest (the top file is 1).
    depth: usize,
    /// Bytes parsed: every file's, each time it is included.
    bytes: u64,
    /// Most bytes the scene may parse.
    max_bytes: u64,
    /// Includes followed.
    pub inclusions: usize,
}

impl Sources {
    /// The sources of a scene whose files may add up to `max_bytes`.
    pub fn new(max_bytes: u64) -> Sources {
        Sources {
            max_bytes,
            ..Sources::default()
        }
    }

    /// Opens the top file, `bytes` named `name` (read from `path`, if any), whose
    /// named files are in `dir`.
    pub fn open_top(
        &mut self,
        name: &str,
        path: Option<&Path>,
        bytes: &[u8],
        dir: &Path,
    ) -> Result<Opened, AffError> {
        self.files.push(SourceFile {
            name: name.to_string(),
            path: path.map(Path::to_path_buf),
        });
        self.bytes = bytes.len() as u64;
        let text = prepare(bytes).map_err(|error| AffError {
            file: name.to_string(),
            error,
        })?;
        if let Some(canonical) = path.and_then(|p| p.canonicalize().ok()) {
            self.active.push(canonical);
        }
        self.depth = 1;
        Ok(Opened {
            file: 0,
            text,
            dir: dir.to_path_buf(),
        })
    }

    /// Opens `name`, included by a file in `dir`: read once, then taken from memory.
    /// [`Sources::leave`] must follow once it is read.
    pub fn include(&mut self, dir: &Path, name: &str) -> Result<Opened, IncludeError> {
        let refuse = |message: String| Err(IncludeError::At(ParseErrorKind::Invalid(message)));
        if self.depth >= MAX_INCLUDE_DEPTH {
            return refuse(format!(
                "includes nest deeper than {MAX_INCLUDE_DEPTH} files (the limit): is there a cycle?"
            ));
        }
        if self.inclusions >= MAX_INCLUSIONS {
            return refuse(format!("more than {MAX_INCLUSIONS} includes in all (the limit)"));
        }
        let path = dir.join(name);
        let shown = path.display().to_string();
        let canonical = match path.canonicalize() {
            Ok(c) if c.is_dir() => return refuse(format!("cannot include {name}: {shown} is a directory")),
            Ok(c) => c,
            Err(e) => {
                return refuse(format!(
                    "cannot include {name}: {} ({shown})",
                    crate::io_reason(&e)
                ))
            }
        };
        if self.active.contains(&canonical) {
            return refuse(format!("include cycle: {shown} is already being read"));
        }
        let opened = match self.read.get(&canonical) {
            Some(o) => o.clone(),
            None => self.read_new(&path, shown, &canonical, name)?,
        };
        let bytes = self.bytes + opened.text.len() as u64;
        if bytes > self.max_bytes {
            return refuse(format!(
                "cannot include {name}: the scene's text adds up to more than {} bytes, each file counted as often as it is included (--max-scene-bytes raises the limit)",
                self.max_bytes
            ));
        }
        self.bytes = bytes;
        self.inclusions += 1;
        self.depth += 1;
        self.active.push(canonical);
        Ok(opened)
    }

    /// Marks the file [`Sources::include`] opened last as read.
    pub fn leave(&mut self) {
        self.depth -= 1;
        self.active.pop();
    }

    /// The prepared texts of every file, the top one first (for the scene's fingerprint).
    pub fn texts(&self) -> Vec<Arc<[u8]>> {
        let mut opened: Vec<&Opened> = self.read.values().collect();
        opened.sort_by_key(|o| o.file);
        opened.iter().map(|o| o.text.clone()).collect()
    }

    /// Reads a file not read before.
    fn read_new(
        &mut self,
        path: &Path,
        shown: String,
        canonical: &Path,
        name: &str,
    ) -> Result<Opened, IncludeError> {
        let left = self.max_bytes.saturating_sub(self.bytes);
        let mut bytes = Vec::new();
        let read =
            std::fs::File::open(path).and_then(|f| f.take(left.saturating_add(1)).read_to_end(&mut bytes));
        if let Err(e) = read {
            let message = format!("cannot include {name}: {} ({shown})", crate::io_reason(&e));
            return Err(IncludeError::At(ParseErrorKind::Invalid(message)));
        }
        if bytes.len() as u64 > left {
            let message = format!(
                "cannot include {name}: the scene's text adds up to more than {} bytes, each file counted as often as it is included (--max-scene-bytes raises the limit)",
                self.max_bytes
            );
            return Err(IncludeError::At(ParseErrorKind::Invalid(message)));
        }
        let file = self.files.len() as u32;
        let text = prepare(&bytes).map_err(|error| {
            IncludeError::In(AffError {
                file: shown.clone(),
                error,
            })
        })?;
        self.files.push(SourceFile {
            name: shown,
            path: Some(path.to_path_buf()),
        });
        let opened = Opened {
            file,
            text,
            dir: path.parent().unwrap_or(Path::new("")).to_path_buf(),
        };
        self.read.insert(canonical.to_path_buf(), opened.clone());
        Ok(opened)
    }
}

/// The text of a file checked ([`scene_text`]) and with every `%` made a `#`, so
/// that NFF's lexer takes AFF's comments for its own (line and column stay those of
/// the file).
fn prepare(bytes: &[u8]) -> Result<Arc<[u8]>, ParseError> {
    let text = scene_text(bytes)?;
    Ok(text.iter().map(|&b| if b == b'%' { b'#' } else { b }).collect())
}
