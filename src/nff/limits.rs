//! Resource limits for parsing: how much a file may make the parser allocate.
//!
//! The parser never reserves memory from a count written in the file (a polygon that
//! claims four billion vertices fails at the end of the file, not in the allocator),
//! so its memory follows the bytes actually read. These limits bound that too: a file
//! that describes more primitives, vertices or lights than the limit is refused at
//! the first one past it, with its line and column, before anything is built from it.
//! The defaults are far above the largest SPD scenes (about 1.2 million primitives
//! at the sizes the SPD suggests) and keep a render of a file within a few gigabytes.

use crate::limits::{DEFAULT_MAX_LIGHTS, DEFAULT_MAX_PRIMITIVES, DEFAULT_MAX_VERTICES};

/// How much one file may describe. [`Limits::default`] gives the defaults documented
/// in `docs/command-line.md` (the constants of [`crate::limits`]); `nffrt` raises them with `--max-primitives`, `--max-vertices` and
/// `--max-lights`.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Limits {
    /// Most primitives (spheres, cones, polygons, patches, planes, boxes) kept.
    pub max_primitives: usize,
    /// Most polygon, patch and mesh vertices kept, all together.
    pub max_vertices: usize,
    /// Most point lights (each costs a shadow ray per shaded hit).
    pub max_lights: usize,
}

impl Limits {
    /// No limit at all (for trusted, generated input).
    pub const NONE: Limits = Limits {
        max_primitives: usize::MAX,
        max_vertices: usize::MAX,
        max_lights: usize::MAX,
    };
}

impl Default for Limits {
    /// 10 million primitives, 40 million vertices, 100 000 lights.
    fn default() -> Self {
        Limits {
            max_primitives: DEFAULT_MAX_PRIMITIVES,
            max_vertices: DEFAULT_MAX_VERTICES,
            max_lights: DEFAULT_MAX_LIGHTS,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::limits::MAX_WARNINGS;
    use crate::nff::parse_bytes_with;

    const SPHERES: &[u8] = b"f 1 1 1 1 0 1 0 1\ns 0 0 0 1\ns 1 0 0 1\ns 2 0 0 1\n";

    #[test]
    fn the_first_primitive_past_the_limit_is_refused_where_it_stands() {
        let two = Limits {
            max_primitives: 2,
            ..Limits::default()
        };
        let e = parse_bytes_with(SPHERES, &two).unwrap_err();
        assert_eq!((e.line, e.column), (4, 1), "{e}");
        assert!(e.to_string().contains("more than 2 primitives"), "{e}");
        let three = Limits {
            max_primitives: 3,
            ..Limits::default()
        };
        assert_eq!(parse_bytes_with(SPHERES, &three).unwrap().spheres.len(), 3);
    }

    #[test]
    fn vertices_and_lights_have_their_own_limits() {
        let tight = Limits {
            max_primitives: 100,
            max_vertices: 5,
            max_lights: 1,
        };
        let polys = b"p 3 0 0 0 1 0 0 0 1 0\npp 3 0 0 0 0 0 1 1 0 0 0 0 1 0 1 0 0 0 1\n";
        let e = parse_bytes_with(polys, &tight).unwrap_err();
        assert_eq!(e.line, 2, "{e}");
        assert!(
            e.to_string()
                .contains("more than 5 polygon, patch and mesh vertices"),
            "{e}"
        );
        let e = parse_bytes_with(b"l 0 0 1\nl 0 0 2\n", &tight).unwrap_err();
        assert_eq!((e.line, e.column), (2, 1), "{e}");
        assert!(e.to_string().contains("more than 1 light"), "{e}");
        assert!(parse_bytes_with(polys, &Limits::default()).is_ok());
    }

    #[test]
    fn a_huge_vertex_count_fails_at_the_limit_not_at_the_end_of_the_data() {
        // Ten vertices given, a billion claimed, limit 8: refused at the ninth.
        let mut src = b"p 1000000000".to_vec();
        for i in 0..10 {
            src.extend_from_slice(format!("\n{i} {} 0", i * i).as_bytes());
        }
        let tight = Limits {
            max_vertices: 8,
            ..Limits::default()
        };
        let e = parse_bytes_with(&src, &tight).unwrap_err();
        assert_eq!(e.line, 10, "{e}");
    }

    #[test]
    fn warnings_are_capped_with_a_final_count() {
        let src = "s 0 0 0 0\n".repeat(MAX_WARNINGS + 500);
        let scene = parse_bytes_with(src.as_bytes(), &Limits::default()).unwrap();
        assert_eq!(scene.warnings.len(), MAX_WARNINGS + 1);
        let last = &scene.warnings[MAX_WARNINGS].message;
        // 1500 degenerate spheres + the default-material and no-camera warnings.
        assert!(last.contains("502 more warnings"), "{last}");
    }
}
