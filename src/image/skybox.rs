//! The skybox: a cube map of six 8-bit images, looked up as the P3F course's
//! template does (P3F-SPEC, "Skybox"): the face is that of the direction's dominant
//! component — the x face if `|x| > |y|`, else the y face, with `m` that component's
//! magnitude; then the z face instead if `|z| > m` — named +X `left`, −X `right`,
//! +Y `top`, −Y `bottom`, +Z `front`, −Z `back`. On the face, coordinates
//! `(sc, tc)` are right `(-z, y)`, left `(z, y)`, top `(-x, -z)`, bottom `(-x, z)`,
//! front `(-x, y)`, back `(x, y)`; `s = (sc/m + 1)/2`, `t = (tc/m + 1)/2`, and the
//! texel is `(floor((w-1) s), floor((h-1) t))` counting rows from the **bottom** of
//! the image. A texel's colour is its 8-bit value / 255 (no filtering, no gamma).

use std::path::PathBuf;
use std::sync::atomic::{AtomicU64, Ordering};
use std::sync::{Arc, OnceLock};
use std::time::Instant;

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
    /// Every face, in the order a [`Skybox`] keeps them.
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

/// Why a face image could not be decoded: the file, and what went wrong (naming the
/// line of the scene that named the skybox).
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct FaceError {
    /// The face's file.
    pub path: PathBuf,
    /// What went wrong.
    pub message: String,
}

impl std::fmt::Display for FaceError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "{}: {}", self.path.display(), self.message)
    }
}

/// Decodes a face's image.
pub type FaceDecoder = Box<dyn Fn(CubeFace) -> Result<FaceImage, FaceError> + Send + Sync>;

/// A cube-map background. The faces' sizes are known from their headers when it is
/// made; their texels are decoded once each, by whichever comes first: the decoding
/// [`Skybox::decode_in_background`] starts, or the first ray that sees the face. So
/// no ray waits for a face it does not see, and a render starts without waiting for
/// any; [`Skybox::decode_all`] then reports a face that could not be decoded (its
/// rays saw black), before a picture is written.
pub struct Skybox {
    /// Width and height of each face, in [`CubeFace::ALL`]'s order.
    sizes: [(u32, u32); 6],
    /// Each face's RGB triples, row by row from the top, once decoded.
    texels: [OnceLock<Result<Vec<u8>, FaceError>>; 6],
    /// How to decode a face not yet decoded (`None`: all were given decoded).
    decoder: Option<FaceDecoder>,
    /// Nanoseconds spent decoding, summed over the faces decoded so far.
    decode_ns: AtomicU64,
}

impl std::fmt::Debug for Skybox {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        let decoded = self.texels.each_ref().map(|t| t.get().is_some());
        f.debug_struct("Skybox")
            .field("sizes", &self.sizes)
            .field("decoded", &decoded)
            .finish()
    }
}

impl Skybox {
    /// A skybox of decoded faces, in [`CubeFace::ALL`]'s order.
    pub fn decoded(faces: [FaceImage; 6]) -> Skybox {
        Skybox {
            sizes: faces.each_ref().map(|f| (f.width, f.height)),
            texels: faces.map(|f| OnceLock::from(Ok(f.rgb))),
            decoder: None,
            decode_ns: AtomicU64::new(0),
        }
    }

    /// A skybox whose faces have the sizes `sizes` (each at least 1 x 1, in
    /// [`CubeFace::ALL`]'s order) and are decoded by `decoder` when first needed; a
    /// face decoded to another size is an error.
    pub fn lazy(sizes: [(u32, u32); 6], decoder: FaceDecoder) -> Skybox {
        Skybox {
            sizes,
            texels: Default::default(),
            decoder: Some(decoder),
            decode_ns: AtomicU64::new(0),
        }
    }

    /// Starts decoding every face on a thread of its own (faces a ray needs first
    /// are decoded by that ray's thread; without a thread, all of them are).
    pub fn decode_in_background(self: &Arc<Skybox>) {
        let sky = Arc::clone(self);
        let _ = std::thread::Builder::new()
            .name("skybox decode".into())
            .spawn(move || sky.decode_all());
    }

    /// Decodes the faces not yet decoded (waiting for those under way): the first
    /// face, in [`CubeFace::ALL`]'s order, that could not be.
    pub fn decode_all(&self) -> Result<(), FaceError> {
        for face in CubeFace::ALL {
            if let Err(e) = self.face(face) {
                return Err(e.clone());
            }
        }
        Ok(())
    }

    /// Seconds spent decoding the faces decoded so far, summed over the threads that
    /// decoded them (a cost of CPU time; on other threads, part of it overlaps the
    /// render).
    pub fn decode_seconds(&self) -> f64 {
        self.decode_ns.load(Ordering::Relaxed) as f64 * 1e-9
    }

    /// Face `face`'s texels, decoded now if they were not yet.
    fn face(&self, face: CubeFace) -> &Result<Vec<u8>, FaceError> {
        let i = face as usize;
        self.texels[i].get_or_init(|| {
            let decoder = self.decoder.as_ref().expect("undecoded faces have a decoder");
            let start = Instant::now();
            let image = decoder(face);
            let ns = u64::try_from(start.elapsed().as_nanos()).unwrap_or(u64::MAX);
            self.decode_ns.fetch_add(ns, Ordering::Relaxed);
            let image = image?;
            if (image.width, image.height) != self.sizes[i] {
                return Err(FaceError {
                    path: PathBuf::from(face.name()),
                    message: format!(
                        "the {} face decoded to {} x {} texels, not the {} x {} of its header",
                        face.name(),
                        image.width,
                        image.height,
                        self.sizes[i].0,
                        self.sizes[i].1
                    ),
                });
            }
            Ok(image.rgb)
        })
    }
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
        let (width, height) = self.sizes[face as usize];
        let s = (sc / m + 1.0) * 0.5;
        let t = (tc / m + 1.0) * 0.5;
        // Clamped: rounding can put s or t a hair outside [0, 1].
        let at = |f: f32, n: u32| (((n - 1) as f32 * f).floor().max(0.0) as u32).min(n - 1);
        SkyTexel {
            face,
            column: at(s, width),
            row: at(t, height),
        }
    }

    /// The colour of a texel (black on a face that could not be decoded: see
    /// [`Skybox::decode_all`]).
    pub fn color(&self, t: &SkyTexel) -> Vec3 {
        let Ok(rgb) = self.face(t.face) else {
            return Vec3::ZERO;
        };
        let (width, height) = self.sizes[t.face as usize];
        let from_top = height - 1 - t.row;
        let i = 3 * (from_top as usize * width as usize + t.column as usize);
        let c = |k: usize| rgb[i + k] as f32 / 255.0;
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
        Skybox::decoded([face(0), face(1), face(2), face(3), face(4), face(5)])
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

    /// A lazy skybox decodes each face once, whoever asks first and however many
    /// threads ask together, to the texels a decoded one has; a face its decoder
    /// fails on (or decodes to another size than its header's) looks black and is
    /// reported by `decode_all`, the first in face order.
    #[test]
    fn lazy_faces_decode_once_and_report_the_first_failure() {
        use std::sync::atomic::AtomicUsize;
        let calls = Arc::new(AtomicUsize::new(0));
        let counted = Arc::clone(&calls);
        let whole = labelled();
        let broken = |face: CubeFace| FaceError {
            path: PathBuf::from(face.name()),
            message: "cut".into(),
        };
        let sky = Arc::new(Skybox::lazy(
            [(5, 3); 6],
            Box::new(move |face| {
                counted.fetch_add(1, Ordering::SeqCst);
                let mut rgb: Vec<u8> = (0..3u8)
                    .flat_map(|row| (0..5u8).flat_map(move |col| [face as u8, col, row]))
                    .collect();
                match face {
                    CubeFace::Top => Err(broken(face)),
                    CubeFace::Back => {
                        rgb.truncate(9);
                        Ok(FaceImage {
                            width: 3,
                            height: 1,
                            rgb,
                        })
                    }
                    _ => Ok(FaceImage {
                        width: 5,
                        height: 3,
                        rgb,
                    }),
                }
            }),
        ));
        let d = Vec3::new(1.0, 0.2, -0.3);
        std::thread::scope(|s| {
            for _ in 0..4 {
                s.spawn(|| assert_eq!(sky.color(&sky.texel(d)), whole.color(&whole.texel(d))));
            }
        });
        assert_eq!(calls.load(Ordering::SeqCst), 1, "the left face decoded once");
        assert_eq!(sky.color(&sky.texel(Vec3::new(0.0, 1.0, 0.0))), Vec3::ZERO);
        assert_eq!(sky.decode_all(), Err(broken(CubeFace::Top)));
        // Left and top were decoded (top's failure kept), right now; it stops at top.
        assert_eq!(calls.load(Ordering::SeqCst), 3);
        assert_eq!(sky.color(&sky.texel(Vec3::new(0.0, 0.0, -1.0))), Vec3::ZERO);
        let back = sky.texels[CubeFace::Back as usize].get().unwrap();
        assert!(
            back.as_ref().is_err_and(|e| e.message.contains("3 x 1")),
            "{back:?}"
        );
    }
}
