//! The skybox: a cube map of six 8-bit images, looked up as the P3F course's
//! template does (P3F-SPEC, "Skybox"): the face is that of the direction's dominant
//! component — the x face if `|x| > |y|`, else the y face, with `m` that component's
//! magnitude; then the z face instead if `|z| > m` — named +X `left`, −X `right`,
//! +Y `top`, −Y `bottom`, +Z `front`, −Z `back`. On the face, coordinates
//! `(sc, tc)` are right `(-z, y)`, left `(z, y)`, top `(-x, -z)`, bottom `(-x, z)`,
//! front `(-x, y)`, back `(x, y)`; `s = (sc/m + 1)/2`, `t = (tc/m + 1)/2`, and the
//! texel is `(floor((w-1) s), floor((h-1) t))` counting rows from the **bottom** of
//! the image. A texel's colour is its 8-bit value / 255 (no filtering, no gamma).

use crate::math::Vec3;

/// A face of the skybox cube, by the template's names.
#[derive(Clone, Copy, Debug, PartialEq, Eq, serde::Serialize)]
#[serde(rename_all = "lowercase")]
pub enum CubeFace {
    /// Seen looking along −X.
    Right,
    /// Seen looking along +X.
    Left,
    /// Seen looking along +Y.
    Top,
    /// Seen looking along −Y.
    Bottom,
    /// Seen looking along +Z.
    Front,
    /// Seen looking along −Z.
    Back,
}

impl CubeFace {
    /// Every face, in the order of [`Skybox::faces`].
    pub const ALL: [CubeFace; 6] = [
        CubeFace::Right,
        CubeFace::Left,
        CubeFace::Top,
        CubeFace::Bottom,
        CubeFace::Front,
        CubeFace::Back,
    ];

    /// The face's name, which is also its image's file stem.
    pub fn name(self) -> &'static str {
        match self {
            CubeFace::Right => "right",
            CubeFace::Left => "left",
            CubeFace::Top => "top",
            CubeFace::Bottom => "bottom",
            CubeFace::Front => "front",
            CubeFace::Back => "back",
        }
    }
}

/// One decoded face image: 8-bit RGB, rows top first.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct FaceImage {
    /// Width in texels (at least 1).
    pub width: u32,
    /// Height in texels (at least 1).
    pub height: u32,
    /// `width * height` RGB triples, row by row from the top.
    pub rgb: Vec<u8>,
}

/// A cube-map background, decoded once per scene.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Skybox {
    /// The face images in [`CubeFace::ALL`]'s order.
    pub faces: [FaceImage; 6],
}

/// Where a direction meets the skybox.
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize)]
pub struct SkyTexel {
    /// The face.
    pub face: CubeFace,
    /// Texel column, from the left.
    pub column: u32,
    /// Texel row, from the **bottom** (the template's `t`).
    pub row: u32,
}

impl Skybox {
    /// The face and texel that direction `d` (any length, not zero) sees.
    pub fn texel(&self, d: Vec3) -> SkyTexel {
        let (ax, ay, az) = (d.x.abs(), d.y.abs(), d.z.abs());
        let (mut face, mut m, mut sc, mut tc) = if ax > ay {
            if d.x > 0.0 {
                (CubeFace::Left, ax, d.z, d.y)
            } else {
                (CubeFace::Right, ax, -d.z, d.y)
            }
        } else if d.y > 0.0 {
            (CubeFace::Top, ay, -d.x, -d.z)
        } else {
            (CubeFace::Bottom, ay, -d.x, d.z)
        };
        if az > m {
            m = az;
            (face, sc, tc) = if d.z > 0.0 {
                (CubeFace::Front, -d.x, d.y)
            } else {
                (CubeFace::Back, d.x, d.y)
            };
        }
        let img = &self.faces[face as usize];
        let s = (sc / m + 1.0) * 0.5;
        let t = (tc / m + 1.0) * 0.5;
        // Clamped: rounding can put s or t a hair outside [0, 1].
        let at = |f: f32, n: u32| (((n - 1) as f32 * f).floor().max(0.0) as u32).min(n - 1);
        SkyTexel {
            face,
            column: at(s, img.width),
            row: at(t, img.height),
        }
    }

    /// The colour of a texel.
    pub fn color(&self, t: &SkyTexel) -> Vec3 {
        let img = &self.faces[t.face as usize];
        let from_top = img.height - 1 - t.row;
        let i = 3 * (from_top as usize * img.width as usize + t.column as usize);
        let c = |k: usize| img.rgb[i + k] as f32 / 255.0;
        Vec3::new(c(0), c(1), c(2))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A skybox whose faces are 5 x 3 and whose texel (column, row from the top)
    /// of face f has the colour (f, column, row).
    fn labelled() -> Skybox {
        let face = |f: u8| FaceImage {
            width: 5,
            height: 3,
            rgb: (0..3u8)
                .flat_map(|row| (0..5u8).flat_map(move |col| [f, col, row]))
                .collect(),
        };
        Skybox {
            faces: [face(0), face(1), face(2), face(3), face(4), face(5)],
        }
    }

    #[test]
    fn each_axis_reads_the_centre_texel_of_its_face() {
        let sky = labelled();
        for (d, face) in [
            (Vec3::new(1.0, 0.0, 0.0), CubeFace::Left),
            (Vec3::new(-1.0, 0.0, 0.0), CubeFace::Right),
            (Vec3::new(0.0, 1.0, 0.0), CubeFace::Top),
            (Vec3::new(0.0, -1.0, 0.0), CubeFace::Bottom),
            (Vec3::new(0.0, 0.0, 1.0), CubeFace::Front),
            (Vec3::new(0.0, 0.0, -1.0), CubeFace::Back),
        ] {
            let t = sky.texel(d * 3.0);
            // floor(4 * 0.5) = 2, floor(2 * 0.5) = 1: the centre of a 5 x 3 face.
            assert_eq!((t.face, t.column, t.row), (face, 2, 1), "{d:?}");
            let c = sky.color(&t) * 255.0;
            assert_eq!((c.x, c.y, c.z), (face as usize as f32, 2.0, 1.0), "{d:?}");
        }
    }

    #[test]
    fn face_coordinates_follow_the_template() {
        let sky = labelled();
        // Looking along -Z (back face: sc = x, tc = y), up and to the right: the
        // last column, the top row (rows count from the bottom; the top is row 0
        // of the image).
        let t = sky.texel(Vec3::new(0.99, 0.99, -1.0));
        assert_eq!((t.face, t.column, t.row), (CubeFace::Back, 3, 1));
        // A tie between |x| and |y| goes to y: the top face (sc = -x, tc = -z), at its
        // right edge (s = 1) and a quarter up from its bottom (t = 0.25: row 0 from
        // the bottom, the image's last row).
        let t = sky.texel(Vec3::new(-1.0, 1.0, 0.5));
        assert_eq!((t.face, t.column, t.row), (CubeFace::Top, 4, 0));
        assert_eq!(sky.color(&t) * 255.0, Vec3::new(2.0, 4.0, 2.0));
        // Along +X (left face: sc = z): a positive z moves right.
        let t = sky.texel(Vec3::new(1.0, 0.0, 0.9));
        assert_eq!((t.face, t.column), (CubeFace::Left, 3));
        // z wins only when strictly larger.
        assert_eq!(sky.texel(Vec3::new(1.0, 0.0, 1.0)).face, CubeFace::Left);
    }
}
