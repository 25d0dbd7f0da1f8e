//! Unit tests of the AFF reader on scenes written in the tests: hierarchies and
//! motion whose results are worked out by hand (`hierarchy.rs`), and malformed
//! scenes refused where they go wrong (`errors.rs`). Scenes that need files (includes,
//! textures) are tested in `tests/aff_files.rs`.

mod errors;
mod hierarchy;

use super::{parse_text, AffError, AffScene};

/// A camera for the test scenes.
const VIEW: &str = "v from 0 0 10 at 0 0 0 up 0 1 0 angle 40 hither 1 resolution 8 8\nf 1 1 1 1 0 1 0 1\n";

/// `body` after [`VIEW`], parsed.
fn scene(body: &str) -> AffScene {
    parse_text(&format!("{VIEW}{body}")).unwrap_or_else(|e| panic!("{e}"))
}

/// The error of `body` after [`VIEW`] (whose two lines come first).
fn error(body: &str) -> AffError {
    match parse_text(&format!("{VIEW}{body}")) {
        Ok(_) => panic!("accepted:\n{body}"),
        Err(e) => e,
    }
}
