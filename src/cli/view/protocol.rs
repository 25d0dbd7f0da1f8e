//! The messages of `nffrt view`'s WebSocket, as typed serde enums.
//!
//! The page sends JSON text messages ([`ClientMessage`]); the server answers with
//! JSON text ([`ServerMessage`]) and sends pictures as binary messages
//! ([`encode_binary`]): a 4-byte little-endian length, a JSON header of that many
//! bytes ([`FrameHeader`], or `{"kind":"png"}`), then the payload (8-bit RGB rows,
//! top row first, or a PNG file).
//!
//! Every render request carries the whole state (camera and options), so a lost or
//! reordered request cannot leave the two sides disagreeing. Each one starts a new
//! *generation*, numbered by the server: its acknowledgement ([`ServerMessage::View`])
//! and its frames carry the number, and once the acknowledgement is sent no frame
//! of an older generation follows it.

use serde::{Deserialize, Serialize};

use nffrt::limits::{DEFAULT_MAX_PIXELS, DEFAULT_SHUTTER, MAX_RAY_DEPTH, MAX_RESOLUTION, MAX_SPP};
use nffrt::scene::{Accel, IntegratorKind, View};

/// The largest text message accepted; longer ones get an error reply.
pub const MAX_MESSAGE_BYTES: usize = 16 * 1024;
/// The largest binary message accepted: a reference picture's file (PNG, PPM, PFM
/// or OpenEXR), as the page's file picker sends it.
pub const MAX_REFERENCE_BYTES: usize = 32 << 20;

/// A camera as the page moves it: the view's position, target, up and angle.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct CameraMsg {
    /// Eye position.
    pub from: [f32; 3],
    /// Point looked at (the orbit's centre).
    pub at: [f32; 3],
    /// Up direction.
    pub up: [f32; 3],
    /// Vertical field of view in degrees, as the scene file's `angle`.
    pub angle: f32,
}

impl CameraMsg {
    /// The camera of `view`.
    pub fn of(view: &View) -> CameraMsg {
        CameraMsg {
            from: view.from.to_array(),
            at: view.at.to_array(),
            up: view.up.to_array(),
            angle: view.angle,
        }
    }
}

fn yes() -> bool {
    true
}

fn default_shutter() -> [f32; 2] {
    DEFAULT_SHUTTER
}

/// The render settings the page controls. The later ones may be left out (older
/// pages, scripts): they then mean what the file says, as far as the page can.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct OptionsMsg {
    /// Picture width in pixels.
    pub width: u32,
    /// Picture height in pixels.
    pub height: u32,
    /// Maximum ray-tree depth (eye ray = 1).
    pub max_depth: u32,
    /// Samples per pixel to converge to (1: pixel centres).
    pub spp: u32,
    /// The scene's lens (P3F `aperture`); false renders through a pinhole.
    pub lens: bool,
    /// Area lights sampled over their surface; false: from their centre.
    pub soft_shadows: bool,
    /// Rough materials rough (fuzzy reflection, rough refraction); false: every
    /// surface smooth.
    #[serde(default = "yes")]
    pub rough: bool,
    /// The light transport, by its name (default Whitted's).
    #[serde(default)]
    pub integrator: IntegratorKind,
    /// When the camera's shutter opens and closes, `[open, close]` (default: 0 to
    /// 1). Moving spheres are bounded over it: a new shutter prepares the scene again.
    #[serde(default = "default_shutter")]
    pub shutter: [f32; 2],
    /// The acceleration structure (default: the BVH). The picture is the same with
    /// each; a new one prepares the scene again.
    #[serde(default)]
    pub accel: Accel,
    /// Show each finished pass denoised (Open Image Denoise), while the noisy
    /// picture keeps refining (default: off).
    #[serde(default)]
    pub denoise: bool,
}

/// A message from the page.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(tag = "type", rename_all = "snake_case", deny_unknown_fields)]
pub enum ClientMessage {
    /// Render with this camera and these options: a new generation.
    Render {
        /// The camera.
        camera: CameraMsg,
        /// The settings.
        options: OptionsMsg,
        /// The frame of an animated (AFF) scene, 0 its first; left out, the scene
        /// as loaded (frame 0 of an AFF scene). A frame the scene does not have is
        /// refused.
        #[serde(default, skip_serializing_if = "Option::is_none")]
        frame: Option<u32>,
    },
    /// Trace pixel `(x, y)` of the current generation's picture (its frame) and send
    /// its ray tree.
    Pixel {
        /// Column, from the left.
        x: u32,
        /// Row, from the top.
        y: u32,
    },
    /// Send the current full-resolution picture as a PNG file.
    Png,
}

/// The limits the page checks its settings against before it asks (the server
/// checks every request against the same ones, `camera::options_of`).
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct LimitsMsg {
    /// The largest width or height.
    pub max_side: u32,
    /// The most pixels, width times height.
    pub max_pixels: u64,
    /// The deepest ray tree.
    pub max_depth: u32,
    /// The most samples per pixel.
    pub max_spp: u32,
}

impl LimitsMsg {
    /// nffrt's limits (`nffrt::limits`).
    pub const NFFRT: LimitsMsg = LimitsMsg {
        max_side: MAX_RESOLUTION,
        max_pixels: DEFAULT_MAX_PIXELS,
        max_depth: MAX_RAY_DEPTH,
        max_spp: MAX_SPP,
    };
}

/// The scene's counts, as the status line shows them.
#[derive(Clone, Debug, Default, PartialEq, Serialize)]
pub struct Counts {
    /// Primitives of every kind (a mesh counts its triangles).
    pub primitives: usize,
    /// Lights.
    pub lights: usize,
    /// Materials.
    pub materials: usize,
}

/// An AFF scene's animation, as the page's time slider shows it.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct AnimationMsg {
    /// How many frames (1 for a still AFF scene): 0 to `frames - 1`.
    pub frames: u32,
    /// The time of frame 0.
    pub start: f64,
    /// The time between two frames.
    pub step: f64,
    /// Each frame's camera (the file's, keyframed), where "reset" goes on it.
    pub cameras: Vec<CameraMsg>,
}

/// A message to the page.
#[derive(Clone, Debug, Serialize)]
#[serde(tag = "type", rename_all = "snake_case")]
pub enum ServerMessage {
    /// The scene loaded (at start and after each successful reload).
    Scene {
        /// The file as named on the command line.
        name: String,
        /// `nff`, `p3f-2019` or `p3f-2025` ([`nffrt::scene::Dialect::name`]).
        dialect: &'static str,
        /// Reload count: 0 for the file as first loaded.
        version: u64,
        /// What the scene holds.
        counts: Counts,
        /// The parser's warnings, `LINE:COLUMN: message`.
        warnings: Vec<String>,
        /// The file's camera (where "reset" goes).
        camera: CameraMsg,
        /// The settings a first render uses.
        options: OptionsMsg,
        /// True if the scene has a lens (P3F `aperture` above 0).
        has_lens: bool,
        /// True if the scene has area lights.
        has_area_lights: bool,
        /// True if some material is rough (the roughness switch matters).
        has_roughness: bool,
        /// True if the scene has moving spheres (the shutter matters).
        has_motion: bool,
        /// An AFF scene's frames (`None` for NFF and P3F).
        animation: Option<AnimationMsg>,
        /// Seconds spent parsing and building.
        load_s: f64,
        /// What the settings may be.
        limits: LimitsMsg,
        /// The denoiser, `Open Image Denoise 2.5.1`, or `None` when it is not
        /// installed (the denoise switch is then greyed out).
        denoiser: Option<String>,
        /// Why there is no denoiser and how to get one (`None` when there is).
        denoiser_help: Option<String>,
    },
    /// A reference picture was loaded: every finished pass of a picture of its
    /// size is then measured against it (binary `flip` messages), and it follows as
    /// a binary `reference` message (8-bit RGB, for flipping between the two).
    Reference {
        /// Its file name (from the command line or the file picker).
        name: String,
        /// Its width.
        width: u32,
        /// Its height.
        height: u32,
        /// `ldr` (an 8-bit picture: LDR-FLIP against the picture as shown) or `hdr`
        /// (a float one: HDR-FLIP against the linear values).
        mode: &'static str,
    },
    /// A render request was accepted as generation `gen`, or a reload started one.
    View {
        /// The generation.
        gen: u64,
        /// `"request"` (the page asked) or `"reload"` (the file changed; the camera
        /// is the file's if the edit moved it).
        reason: &'static str,
        /// The camera rendered.
        camera: CameraMsg,
        /// The settings rendered.
        options: OptionsMsg,
        /// The frame rendered (`None`: the scene as loaded).
        frame: Option<u32>,
        /// The camera as a block for the scene file (`v` or `camera`).
        camera_block: String,
    },
    /// The scene file changed but could not be loaded; the last picture stays.
    LoadError {
        /// `FILE:LINE:COLUMN: what` for a parse error, else the reason.
        message: String,
        /// The line, for a parse error.
        line: Option<u32>,
        /// The column, for a parse error.
        column: Option<u32>,
    },
    /// A message could not be used; nothing changed.
    Error {
        /// What was wrong.
        message: String,
    },
    /// The ray tree of a pixel (the data of `render --pixel`).
    RayTree {
        /// The generation whose camera and options it was traced with.
        gen: u64,
        /// The camera it was traced with (for drawing the rays over the picture).
        camera: CameraMsg,
        /// The frame it was traced in (`None`: the scene as loaded).
        frame: Option<u32>,
        /// True if the scene's angle spans the image edges (P3F), not pixel centres.
        angle_spans_edges: bool,
        /// Each primitive kind's name in the scene's language, e.g. `"sphere (s)"`.
        kinds: serde_json::Value,
        /// The trace: `nffrt::render::debug::PixelTrace` as JSON.
        trace: serde_json::Value,
    },
}

/// The header of a binary picture message.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct FrameHeader {
    /// Always `"frame"`.
    pub kind: &'static str,
    /// The generation it belongs to.
    pub gen: u64,
    /// The full picture's width.
    pub width: u32,
    /// The full picture's height.
    pub height: u32,
    /// Each payload pixel stands for a `stride` x `stride` block (1: full resolution).
    pub stride: u32,
    /// Samples per pixel in the picture (0 for a coarse one).
    pub samples: u32,
    /// Samples per pixel it converges to.
    pub target: u32,
    /// Rays traced in this generation so far.
    pub rays: u64,
    /// Milliseconds since the generation's request arrived.
    pub ms: f64,
    /// True for the converged picture, byte for byte `nffrt render`'s.
    pub complete: bool,
    /// True for a denoised picture (the page's denoise switch).
    pub denoised: bool,
}

/// The header of a binary error map: the FLIP of one finished pass against the
/// reference, the payload its map in magma colours (8-bit RGB rows, top first).
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct FlipHeader {
    /// Always `"flip"`.
    pub kind: &'static str,
    /// The generation measured.
    pub gen: u64,
    /// Its size.
    pub width: u32,
    /// Its height.
    pub height: u32,
    /// Samples per pixel of the pass measured.
    pub samples: u32,
    /// FLIP's mean over the picture.
    pub mean: f64,
    /// True if the picture measured was the denoised one.
    pub denoised: bool,
}

/// A binary message: the header's length (4 bytes, little-endian), the header as
/// JSON, then the payload.
pub fn encode_binary(header: &impl Serialize, payload: &[u8]) -> Vec<u8> {
    let json = serde_json::to_vec(header).expect("headers serialize");
    let mut out = Vec::with_capacity(4 + json.len() + payload.len());
    out.extend_from_slice(&(json.len() as u32).to_le_bytes());
    out.extend_from_slice(&json);
    out.extend_from_slice(payload);
    out
}

/// Reads a page's text message: well-formed JSON of a known shape, within the size
/// limit, with a usable camera and shutter. The error says what was wrong. (The
/// render settings' ranges are the renderer's to check, `camera::options_of`.)
pub fn parse_client_message(text: &str) -> Result<ClientMessage, String> {
    if text.len() > MAX_MESSAGE_BYTES {
        return Err(format!(
            "message too large: {} bytes (at most {MAX_MESSAGE_BYTES})",
            text.len()
        ));
    }
    let msg: ClientMessage = serde_json::from_str(text).map_err(|e| format!("bad message: {e}"))?;
    if let ClientMessage::Render { camera, options, .. } = &msg {
        check_camera(camera)?;
        check_shutter(options)?;
    }
    Ok(msg)
}

fn check_camera(c: &CameraMsg) -> Result<(), String> {
    let all = c.from.iter().chain(&c.at).chain(&c.up);
    if !all.chain([&c.angle]).all(|v| v.is_finite() && v.abs() < 1e30) {
        return Err("bad camera: every number must be finite (and below 1e30)".into());
    }
    let [from, at, up] = [c.from, c.at, c.up].map(nffrt::math::Vec3::from_array);
    let dir = at - from;
    if dir.length_squared() <= 0.0 || !dir.length_squared().is_normal() {
        return Err("bad camera: 'from' and 'at' coincide".into());
    }
    let side = dir.normalize().cross(up);
    if up.length_squared() <= 0.0 || side.length() <= 1e-6 * up.length() {
        return Err("bad camera: 'up' is parallel to the view direction".into());
    }
    if !(c.angle > 0.0 && c.angle < 180.0) {
        return Err(format!("bad camera: angle {} is not between 0 and 180", c.angle));
    }
    Ok(())
}

/// Checks what the renderer's own checks do not cover: the shutter, a setting of
/// the render-time scene (the render settings are checked as every render's are,
/// `camera::options_of`).
fn check_shutter(o: &OptionsMsg) -> Result<(), String> {
    let [open, close] = o.shutter;
    if !(open.is_finite() && close.is_finite() && open.abs() < 1e6 && close.abs() < 1e6) {
        return Err("bad options: the shutter's times must be finite (and below 1e6)".into());
    }
    if open > close {
        return Err(format!(
            "bad options: the shutter closes ({close}) before it opens ({open})"
        ));
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;
    use proptest::prelude::*;

    fn render_msg() -> ClientMessage {
        ClientMessage::Render {
            camera: CameraMsg {
                from: [0.0, 0.0, 5.0],
                at: [0.0; 3],
                up: [0.0, 1.0, 0.0],
                angle: 40.0,
            },
            options: OptionsMsg {
                width: 64,
                height: 48,
                max_depth: 5,
                spp: 4,
                lens: true,
                soft_shadows: true,
                rough: true,
                integrator: IntegratorKind::Path,
                shutter: [0.0, 0.5],
                accel: Accel::Grid,
                denoise: true,
            },
            frame: Some(2),
        }
    }

    #[test]
    fn known_messages_parse_and_bad_ones_are_explained() {
        let text = serde_json::to_string(&render_msg()).unwrap();
        assert_eq!(parse_client_message(&text), Ok(render_msg()));
        assert_eq!(
            parse_client_message(r#"{"type":"pixel","x":3,"y":4}"#),
            Ok(ClientMessage::Pixel { x: 3, y: 4 })
        );
        assert_eq!(parse_client_message(r#"{"type":"png"}"#), Ok(ClientMessage::Png));
        for (bad, says) in [
            ("{", "bad message"),
            (r#"{"type":"launch"}"#, "unknown variant"),
            (r#"{"type":"pixel","x":-1,"y":0}"#, "bad message"),
            (r#"{"type":"pixel","x":1,"y":0,"z":2}"#, "unknown field"),
            (r#"{"type":"pixel","x":1,"y":0,"frame":2}"#, "unknown field"),
            (r#"[1,2]"#, "bad message"),
        ] {
            let e = parse_client_message(bad).unwrap_err();
            assert!(e.contains(says), "{bad}: {e}");
        }
        let big = format!(r#"{{"type":"png","pad":"{}"}}"#, "x".repeat(MAX_MESSAGE_BYTES));
        assert!(parse_client_message(&big).unwrap_err().contains("too large"));
    }

    #[test]
    fn options_without_the_later_settings_mean_the_defaults() {
        let text = r#"{"type":"render","camera":{"from":[0,0,5],"at":[0,0,0],"up":[0,1,0],"angle":40},
            "options":{"width":8,"height":6,"max_depth":5,"spp":1,"lens":true,"soft_shadows":true}}"#;
        let Ok(ClientMessage::Render { options, frame, .. }) = parse_client_message(text) else {
            panic!("refused")
        };
        assert_eq!(frame, None);
        assert!(options.rough);
        assert_eq!(options.integrator, IntegratorKind::Whitted);
        assert_eq!(options.shutter, [0.0, 1.0]);
        assert_eq!(options.accel, Accel::Bvh);
        assert!(!options.denoise);
    }

    #[test]
    fn out_of_range_cameras_and_shutters_are_refused() {
        let with = |f: &dyn Fn(&mut CameraMsg, &mut OptionsMsg)| {
            let ClientMessage::Render {
                mut camera,
                mut options,
                frame,
            } = render_msg()
            else {
                unreachable!()
            };
            f(&mut camera, &mut options);
            let msg = ClientMessage::Render {
                camera,
                options,
                frame,
            };
            parse_client_message(&serde_json::to_string(&msg).unwrap())
        };
        assert!(with(&|c, _| c.at = c.from).unwrap_err().contains("coincide"));
        assert!(with(&|c, _| c.up = [0.0, 0.0, -1.0])
            .unwrap_err()
            .contains("parallel"));
        assert!(with(&|c, _| c.angle = 180.0).unwrap_err().contains("angle"));
        assert!(with(&|c, _| c.from[0] = 1e38).unwrap_err().contains("finite"));
        assert!(with(&|_, o| o.shutter = [1.0, 0.5])
            .unwrap_err()
            .contains("closes (0.5) before it opens (1)"));
        assert!(with(&|_, _| ()).is_ok());
    }

    /// Any JSON value, nested a few levels.
    fn json() -> impl Strategy<Value = serde_json::Value> {
        let leaf = prop_oneof![
            Just(serde_json::Value::Null),
            any::<bool>().prop_map(serde_json::Value::from),
            any::<f64>().prop_map(serde_json::Value::from),
            any::<i64>().prop_map(serde_json::Value::from),
            prop_oneof![
                Just("render".to_string()),
                Just("pixel".to_string()),
                Just("png".to_string()),
                ".*"
            ]
            .prop_map(serde_json::Value::from),
        ];
        leaf.prop_recursive(4, 64, 8, |inner| {
            prop_oneof![
                prop::collection::vec(inner.clone(), 0..8).prop_map(serde_json::Value::from),
                prop::collection::btree_map(
                    prop_oneof![
                        Just("type".to_string()),
                        Just("camera".to_string()),
                        Just("options".to_string()),
                        Just("x".to_string()),
                        "[a-z_]{1,8}"
                    ],
                    inner,
                    0..6
                )
                .prop_map(|m| serde_json::Value::Object(m.into_iter().collect())),
            ]
        })
    }

    /// What the parser makes of `text` is a proper answer: a message that reads back
    /// as itself once written, or an error that says which kind of problem it is.
    fn answered(text: &str) -> Result<(), String> {
        match parse_client_message(text) {
            Ok(msg) => {
                let again = parse_client_message(&serde_json::to_string(&msg).unwrap());
                if again.as_ref() == Ok(&msg) {
                    Ok(())
                } else {
                    Err(format!("{msg:?} reads back as {again:?}"))
                }
            }
            Err(e) => {
                let kinds = ["message too large", "bad message", "bad camera", "bad options"];
                if kinds.iter().any(|k| e.starts_with(k)) {
                    Ok(())
                } else {
                    Err(format!("an error of no known kind: {e:?}"))
                }
            }
        }
    }

    fn finite() -> impl Strategy<Value = f32> {
        prop_oneof![-1e3f32..1e3, any::<f32>()]
    }

    proptest! {
        /// Arbitrary text never panics the parser: a message or an explanation.
        #[test]
        fn any_text_gets_a_message_or_an_error(text in ".{0,300}") {
            prop_assert!(answered(&text).is_ok(), "{:?}", answered(&text));
        }

        /// Arbitrary JSON, shaped much like real messages, never panics it either.
        #[test]
        fn any_json_gets_a_message_or_an_error(value in json()) {
            let text = value.to_string();
            prop_assert!(answered(&text).is_ok(), "{:?}", answered(&text));
        }

        /// Every well-formed render request reads back as itself, or is refused for a
        /// value out of range, never for its form.
        #[test]
        fn render_requests_round_trip(
            v in prop::array::uniform10(finite()),
            w in 0u32..5000, h in 0u32..5000, depth in 0u32..80, spp in 0u32..5000,
            lens: bool, soft: bool, rough: bool, path: bool, shutter in prop::array::uniform2(finite()),
            denoise: bool, frame: Option<u32>,
        ) {
            let msg = ClientMessage::Render {
                camera: CameraMsg { from: [v[0], v[1], v[2]], at: [v[3], v[4], v[5]], up: [v[6], v[7], v[8]], angle: v[9] },
                options: OptionsMsg {
                    width: w, height: h, max_depth: depth, spp, lens, soft_shadows: soft, rough,
                    integrator: if path { IntegratorKind::Path } else { IntegratorKind::Whitted }, shutter,
                    accel: Accel::None, denoise,
                },
                frame,
            };
            match parse_client_message(&serde_json::to_string(&msg).unwrap()) {
                Ok(back) => prop_assert_eq!(back, msg),
                // (JSON has no infinities or NaN: serde_json writes them as null.)
                Err(e) => prop_assert!(
                    e.starts_with("bad camera") || e.starts_with("bad options")
                        || v.iter().chain(&shutter).any(|x| !x.is_finite()),
                    "{}", e
                ),
            }
        }
    }
}
