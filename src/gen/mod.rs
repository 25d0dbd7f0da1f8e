//! Built-in generators for the seven classic scenes of Eric Haines' Standard
//! Procedural Databases (SPD 3.14): `balls`, `gears`, `mount`, `rings`, `teapot`,
//! `tetra` and `tree`, at every size that keeps a scene within [`DEFAULT_MAX_PRIMITIVES`].
//!
//! Each generator follows the published description of the SPD's algorithm and
//! makes the same scene as the SPD program: the same camera, lights, background and
//! materials (rounded to six significant digits, as the SPD prints them), the same
//! primitives in the same order (written out, even on the same lines), and geometry
//! that agrees with the SPD's printed numbers to within a unit of their sixth digit.
//!
//! The fractal mountain is no exception: its pseudo-random displacements come from
//! the SPD's own hash and generator, reproduced. Only beyond size 7, where the SPD's
//! hash is undefined C, is the mountain our own: the size-7 mountain refined
//! further, through all its vertices (and so the default one's), new points being
//! displaced by a hash of their position.
//!
//! The size factor means what it means in the SPD, and the SPD's default sizes are
//! ours. Sizes are limited so that no scene has more than [`DEFAULT_MAX_PRIMITIVES`]
//! primitives.
//!
//! ```
//! use nffrt::gen::{generate, SpdScene};
//! let scene = generate(SpdScene::Balls, 2).unwrap();
//! assert_eq!(scene.spheres.len(), 1 + 9 + 81);
//! assert_eq!(SpdScene::from_name("tetra"), Some(SpdScene::Tetra));
//! ```

mod balls;
mod builder;
mod dvec;
mod gears;
mod mount;
mod rings;
mod teapot;
mod teapot_data;
mod tetra;
mod tree;

use crate::limits::DEFAULT_MAX_PRIMITIVES;
use crate::scene::Scene;

/// One of the seven classic SPD scenes.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum SpdScene {
    /// The sphereflake: size = levels of nine children per sphere.
    Balls,
    /// Meshed gears: size = gears along each side of a cube.
    Gears,
    /// Fractal mountain and four glass spheres: size = subdivision levels.
    Mount,
    /// Pyramid of pentagonal rings: size = layers.
    Rings,
    /// Newell's teapot on a checkerboard: size = cuts per patch side.
    Teapot,
    /// Recursive tetrahedron: size = recursion levels.
    Tetra,
    /// Aono and Kunii tree: size = levels of branching.
    Tree,
}

/// Why a scene cannot be generated.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
pub enum GenError {
    /// The size is outside what the generator accepts. The message says the range and,
    /// for a size above it, why: `must be a whole number from 1 to 7 for balls (size 8
    /// would already make 48427562 primitives, over the limit of 10000000)`.
    #[error("{}", size_range_words(*.scene, *.size))]
    SizeOutOfRange {
        /// The scene asked for.
        scene: SpdScene,
        /// The size asked for.
        size: u32,
    },
}

/// The message of [`GenError::SizeOutOfRange`].
fn size_range_words(scene: SpdScene, size: u32) -> String {
    let (name, max) = (scene.name(), scene.max_size());
    let mut words = format!("must be a whole number from 1 to {max} for {name}");
    if size > max {
        words.push_str(&format!(
            " (size {} would already make {} primitives, over the limit of {DEFAULT_MAX_PRIMITIVES})",
            max + 1,
            scene.primitive_count(max + 1)
        ));
    }
    words
}

impl SpdScene {
    /// All seven scenes, in alphabetical order.
    pub const ALL: [SpdScene; 7] = [
        SpdScene::Balls,
        SpdScene::Gears,
        SpdScene::Mount,
        SpdScene::Rings,
        SpdScene::Teapot,
        SpdScene::Tetra,
        SpdScene::Tree,
    ];

    /// The SPD's name for the scene (`balls`, `gears`, ...).
    pub fn name(self) -> &'static str {
        match self {
            SpdScene::Balls => "balls",
            SpdScene::Gears => "gears",
            SpdScene::Mount => "mount",
            SpdScene::Rings => "rings",
            SpdScene::Teapot => "teapot",
            SpdScene::Tetra => "tetra",
            SpdScene::Tree => "tree",
        }
    }

    /// The scene called `name`, if any.
    pub fn from_name(name: &str) -> Option<SpdScene> {
        SpdScene::ALL.into_iter().find(|s| s.name() == name)
    }

    /// What the size factor counts, for help texts.
    pub fn size_meaning(self) -> &'static str {
        match self {
            SpdScene::Balls => "recursion levels (9 children per sphere)",
            SpdScene::Gears => "gears along each side of the cube",
            SpdScene::Mount => "subdivision levels",
            SpdScene::Rings => "layers of the pyramid",
            SpdScene::Teapot => "cuts per patch side",
            SpdScene::Tetra => "recursion levels",
            SpdScene::Tree => "branching levels",
        }
    }

    /// The SPD's default size, which gives at most 10 000 primitives.
    pub fn default_size(self) -> u32 {
        match self {
            SpdScene::Balls => balls::DEFAULT_SIZE,
            SpdScene::Gears => gears::DEFAULT_SIZE,
            SpdScene::Mount => mount::DEFAULT_SIZE,
            SpdScene::Rings => rings::DEFAULT_SIZE,
            SpdScene::Teapot => teapot::DEFAULT_SIZE,
            SpdScene::Tetra => tetra::DEFAULT_SIZE,
            SpdScene::Tree => tree::DEFAULT_SIZE,
        }
    }

    /// The number of primitives (of every kind) at `size`, saturating at `u64::MAX`.
    pub fn primitive_count(self, size: u32) -> u64 {
        let n = size as u128;
        let pow = |b: u128, e: u32| b.checked_pow(e).unwrap_or(u128::MAX / 4);
        let count: u128 = match self {
            // sum of 9^k for k = 0..=n spheres, one floor polygon
            SpdScene::Balls => (pow(9, size.saturating_add(1)) - 1) / 8 + 1,
            // per gear two faces and 4 * 36 sides; one floor polygon
            SpdScene::Gears => 146 * n * n * n + 1,
            // two triangles per cell of the 2^n grid; four spheres
            SpdScene::Mount => 2 * pow(4, size) + 4,
            // 30 cylinders and 30 spheres per object, sum of d^2 objects; one wall
            SpdScene::Rings => 10 * n * (n + 1) * (2 * n + 1) + 1,
            // 2 n^2 triangles per patch less n at each of the 8 cusp patches; n^2 squares
            SpdScene::Teapot => 64 * n * n - 8 * n + n * n,
            // 4^n triangles (size 0 is one tetrahedron, like size 1)
            SpdScene::Tetra => pow(4, size.max(1)),
            // 2^(n+1) - 1 branches, each a cone and a sphere; one field polygon
            SpdScene::Tree => 2 * (pow(2, size.saturating_add(1)) - 1) + 1,
        };
        u64::try_from(count).unwrap_or(u64::MAX)
    }

    /// The largest size whose scene stays within [`DEFAULT_MAX_PRIMITIVES`].
    pub fn max_size(self) -> u32 {
        let mut size = 1;
        while self.primitive_count(size + 1) <= DEFAULT_MAX_PRIMITIVES as u64 {
            size += 1;
        }
        size
    }
}

impl std::fmt::Display for SpdScene {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(self.name())
    }
}

/// Generates `which` at `size` (see [`SpdScene::default_size`]); sizes from 1 to
/// [`SpdScene::max_size`] are accepted.
pub fn generate(which: SpdScene, size: u32) -> Result<Scene, GenError> {
    if size == 0 || size > which.max_size() {
        return Err(GenError::SizeOutOfRange { scene: which, size });
    }
    Ok(match which {
        SpdScene::Balls => balls::generate(size),
        SpdScene::Gears => gears::generate(size),
        SpdScene::Mount => mount::generate(size),
        SpdScene::Rings => rings::generate(size),
        SpdScene::Teapot => teapot::generate(size),
        SpdScene::Tetra => tetra::generate(size),
        SpdScene::Tree => tree::generate(size),
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn names_round_trip() {
        for s in SpdScene::ALL {
            assert_eq!(SpdScene::from_name(s.name()), Some(s));
        }
        assert_eq!(SpdScene::from_name("teapots"), None);
    }

    #[test]
    fn default_sizes_stay_under_ten_thousand_primitives() {
        for s in SpdScene::ALL {
            let n = s.primitive_count(s.default_size());
            assert!(n <= 10_000, "{s}: {n}");
            assert!(s.default_size() <= s.max_size());
        }
    }

    #[test]
    fn limits_refuse_the_next_size_with_an_explanation() {
        assert_eq!(SpdScene::Balls.max_size(), 7);
        assert_eq!(SpdScene::Mount.max_size(), 11);
        let e = generate(SpdScene::Balls, 8).unwrap_err().to_string();
        assert!(
            e.contains("from 1 to 7") && e.contains("48427562") && e.contains("10000000"),
            "{e}"
        );
        assert!(generate(SpdScene::Tree, 0).is_err());
        assert!(generate(SpdScene::Tree, u32::MAX).is_err());
    }
}
