//! Reading and writing NFF (Neutral File Format) scenes.
//!
//! The accepted syntax (whitespace-separated tokens; line breaks carry no meaning;
//! `#` starts a comment that runs to the end of the line):
//!
//! ```text
//! v from x y z at x y z up x y z angle deg hither d resolution w h   camera
//! b r g b                                background colour
//! l x y z [r g b]                        point light
//! f r g b Kd Ks shine T ior              material for the objects that follow
//! s cx cy cz r                           sphere (r < 0: inside visible)
//! c bx by bz br ax ay az ar              open cone / cylinder
//! p n  x y z ...(n times)                polygon, convex or concave
//! pp n x y z nx ny nz ...(n times)       polygonal patch with vertex normals
//! pl x1 y1 z1 x2 y2 z2 x3 y3 z3          infinite plane (extension)
//! aabb xmin xmax ymin ymax zmin zmax     axis-aligned box (extension)
//! ```

mod chunks;
mod embed;
mod entities;
mod error;
mod keywords;
mod lexer;
mod limits;
mod p3f;
mod parser;
mod text;
mod writer;

pub(crate) use embed::{Embedded, EntityState};
pub(crate) use entities::is_degenerate;
pub use error::{ParseError, ParseErrorKind};
pub use lexer::{Lexer, Token};
pub use limits::Limits;
pub(crate) use parser::parse_f32;
pub use parser::{parse, parse_bytes, parse_bytes_with, parse_format, parse_format_cancellable};
pub(crate) use text::scene_text;

/// The language of a scene file.
#[derive(Clone, Copy, Debug, PartialEq, Eq, serde::Serialize)]
#[serde(rename_all = "lowercase")]
pub enum Format {
    /// NFF, with nffrt's extensions (`pl`, `aabb`).
    Nff,
    /// P3F, the IST course's extended NFF, in either of its dialects.
    P3f,
    /// AFF, BART's animated NFF: read by [`crate::aff`] (its files include others),
    /// never by this module's parser.
    Aff,
}

impl Format {
    /// The format a file's name implies: P3F for a `.p3f` extension, AFF for `.aff`
    /// (any case), NFF otherwise.
    pub fn of_path(path: &std::path::Path) -> Format {
        match path.extension().and_then(|e| e.to_str()) {
            Some(e) if e.eq_ignore_ascii_case("p3f") => Format::P3f,
            Some(e) if e.eq_ignore_ascii_case("aff") => Format::Aff,
            _ => Format::Nff,
        }
    }
}
pub use writer::{view_block, write_nff, write_p3f, write_scene};
