//! What a caller asks of a render, resolved against a scene into [`RenderOptions`].
//! The command line's flags, the viewer's settings and the Python bindings'
//! arguments all become a [`RenderRequest`], so the scene's defaults, the policies
//! (which sampling, what an effect that needs samples gets) and the checks are
//! written once, here.

use super::{check_settings, RenderOptions, Sampling};
use crate::image::Encoding;
use crate::limits::{DEFAULT_EFFECT_SPP, DEFAULT_MAX_DEPTH, MAX_RESOLUTION};
use crate::scene::{IntegratorKind, SceneInfo};

/// What a caller asks of a render; `None` leaves a setting to the scene or the
/// default.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct RenderRequest {
    /// Image width (the other side follows the scene's aspect ratio when alone).
    pub width: Option<u32>,
    /// Image height.
    pub height: Option<u32>,
    /// Samples per pixel (default: the file's `spp`, else 1 — or
    /// [`DEFAULT_EFFECT_SPP`] when an effect needs samples).
    pub spp: Option<u32>,
    /// The SPD benchmark protocol: rays through the pixel corners (not with `spp`).
    pub spd: bool,
    /// Maximum ray-tree depth (default [`DEFAULT_MAX_DEPTH`]).
    pub max_depth: Option<u32>,
    /// Lens diameter in pixels of the view plane, replacing the scene's.
    pub aperture: Option<f32>,
    /// Focal distance as a multiple of `|from - at|`, replacing the scene's.
    pub focal: Option<f32>,
    /// Points per side of the grid every hit samples on each area light.
    pub light_samples: Option<u32>,
    /// Each area light shines from its centre alone (the viewer's toggle).
    pub hard_shadows: bool,
    /// The sample pattern ([`RenderOptions::seed`]; default 0).
    pub seed: Option<u32>,
    /// The light transport (default: the file's `integrator`, else Whitted's).
    pub integrator: Option<IntegratorKind>,
    /// Every surface smooth, whatever its material's roughness (the viewer's toggle).
    pub smooth: bool,
    /// How 8-bit pictures hold the values (default: [`display_encoding`]).
    pub encoding: Option<Encoding>,
}

/// A request resolved: the options, and what the caller should be told about how
/// they were chosen (one sentence each, for standard error or a status line).
#[derive(Clone, Debug, PartialEq)]
pub struct Resolved {
    /// The render's options.
    pub opts: RenderOptions,
    /// How an 8-bit picture of the render holds its values (float pictures hold
    /// them linear whatever this says).
    pub encoding: Encoding,
    /// Notes on defaults chosen for the caller.
    pub notes: Vec<String>,
}

/// The 8-bit encoding of a picture rendered with `integrator` from a scene in P3F
/// (`p3f`) or NFF, unless the caller chooses: Whitted's pictures linear, as the
/// course's first assignment and the SPD write them (their colours are display
/// values); path-traced ones, whose values are radiance, display-encoded — with the
/// course's `toGamma` (gamma 2.2) for P3F, the course's path tracer's scenes, and
/// with sRGB's curve for NFF, as pbrt and Mitsuba write theirs (docs/path-tracing.md).
pub fn display_encoding(integrator: IntegratorKind, p3f: bool) -> Encoding {
    match (integrator, p3f) {
        (IntegratorKind::Whitted, _) => Encoding::Linear,
        (IntegratorKind::Path, true) => Encoding::Gamma22,
        (IntegratorKind::Path, false) => Encoding::Srgb,
    }
}

impl RenderRequest {
    /// The options of this request on `scene`, or why it cannot be rendered (a
    /// sentence naming the setting and its range).
    pub fn resolve(&self, scene: &SceneInfo) -> Result<Resolved, String> {
        let view = &scene.view;
        let (width, height) = image_size(self.width, self.height, view.width, view.height)?;
        let mut notes = Vec::new();
        let opts = RenderOptions {
            width,
            height,
            max_depth: self.max_depth.unwrap_or(DEFAULT_MAX_DEPTH),
            sampling: self.sampling(scene, &mut notes)?,
            aperture: self.aperture,
            focal: self.focal,
            light_samples: self.light_samples,
            soft_shadows: !self.hard_shadows,
            seed: self.seed.unwrap_or(0),
            integrator: self.integrator.or(scene.integrator).unwrap_or_default(),
            roughness: !self.smooth,
        };
        check_settings(&opts)?;
        let encoding =
            (self.encoding).unwrap_or_else(|| display_encoding(opts.integrator, scene.dialect.is_p3f()));
        Ok(Resolved {
            opts,
            encoding,
            notes,
        })
    }

    /// The sampling: the SPD's corners, or `spp` from the request, else from the
    /// file; one sample through each pixel centre when neither says more. An effect
    /// that one centred sample would drop (a lens) is never dropped silently: with
    /// neither saying anything it gets [`DEFAULT_EFFECT_SPP`] samples and a note,
    /// and an explicit single sample is one jittered sample of the effect
    /// (`Stratified { spp: 1 }`: noisy, not sharp). A file's `spp 0` asks for the
    /// course's one fixed sample at the pixel centre, and gets it.
    fn sampling(&self, scene: &SceneInfo, notes: &mut Vec<String>) -> Result<Sampling, String> {
        if self.spd {
            if self.spp.is_some() {
                return Err("the SPD protocol has its own sampling: it cannot be combined with spp".into());
            }
            return Ok(Sampling::SpdCorners);
        }
        if self.spp == Some(0) {
            return Err("0 samples per pixel: at least 1".into());
        }
        let effect = self.effect_needing_samples(scene);
        let spp = match (self.spp.or(scene.spp), effect) {
            (Some(n), _) => n,
            (None, Some(effect)) => {
                notes.push(format!(
                    "{effect} needs more than one sample per pixel: rendering with {DEFAULT_EFFECT_SPP} \
                     (set spp to choose)"
                ));
                DEFAULT_EFFECT_SPP
            }
            (None, None) => 1,
        };
        let path = self.integrator.or(scene.integrator) == Some(IntegratorKind::Path);
        Ok(match spp {
            // A path draws its every direction from the sample: never a fixed one.
            _ if path => Sampling::Stratified { spp: spp.max(1) },
            0 => Sampling::PixelCenters,
            1 if effect.is_some() => Sampling::Stratified { spp: 1 },
            1 => Sampling::PixelCenters,
            spp => Sampling::Stratified { spp },
        })
    }

    /// The first effect of the render that one centred sample per pixel would drop,
    /// named for a note: path tracing itself, the lens, motion while the shutter is
    /// open, rough mirrors or glass.
    fn effect_needing_samples(&self, scene: &SceneInfo) -> Option<&'static str> {
        if self.integrator.or(scene.integrator) == Some(IntegratorKind::Path) {
            return Some("path tracing");
        }
        let aperture = self.aperture.unwrap_or(scene.view.aperture);
        let moving = scene.has_moving_spheres();
        let rough = !self.smooth
            && scene
                .materials
                .iter()
                .any(|m| m.roughness > 0.0 && (m.ks > 0.0 || m.t > 0.0));
        if aperture > 0.0 {
            Some("the lens (depth of field)")
        } else if moving && scene.shutter[1] > scene.shutter[0] {
            Some("motion (moving spheres)")
        } else if rough && scene.dialect.is_p3f() {
            Some("roughness (fuzzy reflection or rough refraction)")
        } else {
            None
        }
    }
}

/// The image size of a render asked for with `width` and/or `height` of a scene
/// whose file says `scene_w` x `scene_h`: the file's size, or both sides as given,
/// or one side given and the other following the file's aspect ratio (rounded to
/// the nearest pixel). Each side must come out between 1 and [`MAX_RESOLUTION`]: a
/// side that follows the aspect ratio past it is an error saying so, never capped
/// (a capped side would change the picture's shape).
pub fn image_size(
    width: Option<u32>,
    height: Option<u32>,
    scene_w: u32,
    scene_h: u32,
) -> Result<(u32, u32), String> {
    let check = |name: &str, n: u32| {
        if (1..=MAX_RESOLUTION).contains(&n) {
            Ok(n)
        } else {
            Err(format!("{name} {n} is not between 1 and {MAX_RESOLUTION}"))
        }
    };
    // `given` pixels along a side of `side` scene pixels: the other side, `other` long.
    let follow = |given: u32, side: u32, other: u32, name: &str, given_name: &str| {
        let (g, s, o) = (given as u64, side.max(1) as u64, other as u64);
        let n = ((g * o + s / 2) / s).max(1);
        if n > MAX_RESOLUTION as u64 {
            return Err(format!(
                "{given_name} {given} with the scene's aspect ratio ({scene_w}x{scene_h}) makes the {name} {n}, \
                 more than {MAX_RESOLUTION}: give both width and height"
            ));
        }
        Ok(n as u32)
    };
    match (width, height) {
        (Some(w), Some(h)) => Ok((check("width", w)?, check("height", h)?)),
        (Some(w), None) => {
            let w = check("width", w)?;
            Ok((w, follow(w, scene_w, scene_h, "height", "width")?))
        }
        (None, Some(h)) => {
            let h = check("height", h)?;
            Ok((follow(h, scene_h, scene_w, "width", "height")?, h))
        }
        (None, None) => Ok((scene_w, scene_h)),
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::scene::Scene;

    fn scene(text: &str, p3f: bool) -> SceneInfo {
        let format = if p3f {
            crate::nff::Format::P3f
        } else {
            crate::nff::Format::Nff
        };
        let s: Scene = crate::nff::parse_format(text.as_bytes(), format, &Default::default()).unwrap();
        s.info()
    }

    const NFF: &str = "v from 0 0 5 at 0 0 0 up 0 1 0 angle 40 hither 1 resolution 640 480\ns 0 0 0 1\n";
    const LENS: &str =
        "v from 0 0 5 at 0 0 0 up 0 1 0 angle 40 hither 1 resolution 64 48 aperture 8 focal 1\n\
                        s 0 0 0 1\n";
    #[test]
    fn path_traced_pictures_are_display_encoded_unless_asked_otherwise() {
        let p3f = scene(
            &format!("integrator path\n{}", LENS.replace("v from", "camera eye")),
            true,
        );
        let nff = scene(NFF, false);
        let encoding = |r: RenderRequest, s: &SceneInfo| r.resolve(s).unwrap().encoding;
        let path = RenderRequest {
            integrator: Some(IntegratorKind::Path),
            ..Default::default()
        };
        assert_eq!(encoding(RenderRequest::default(), &p3f), Encoding::Gamma22);
        assert_eq!(encoding(path, &nff), Encoding::Srgb);
        assert_eq!(encoding(RenderRequest::default(), &nff), Encoding::Linear);
        let whitted = RenderRequest {
            integrator: Some(IntegratorKind::Whitted),
            ..Default::default()
        };
        assert_eq!(encoding(whitted, &p3f), Encoding::Linear);
        let chosen = RenderRequest {
            encoding: Some(Encoding::Linear),
            ..path
        };
        assert_eq!(encoding(chosen, &p3f), Encoding::Linear);
    }

    #[test]
    fn one_side_given_keeps_the_aspect_ratio() {
        assert_eq!(image_size(None, None, 640, 480), Ok((640, 480)));
        assert_eq!(image_size(Some(320), None, 640, 480), Ok((320, 240)));
        assert_eq!(image_size(None, Some(100), 640, 480), Ok((133, 100))); // 133.3
        assert_eq!(image_size(Some(5), None, 23, 17), Ok((5, 4))); // 3.7
        assert_eq!(image_size(Some(7), Some(9), 640, 480), Ok((7, 9)));
        assert_eq!(image_size(Some(1), None, 32768, 1), Ok((1, 1))); // never 0
        assert_eq!(image_size(None, Some(32768), 1, 2), Ok((16384, 32768)));
    }

    #[test]
    fn a_side_past_the_limit_is_an_error_that_says_where_it_came_from() {
        let e = image_size(Some(100_000), None, 512, 512).unwrap_err();
        assert_eq!(e, "width 100000 is not between 1 and 32768");
        // Within the limit itself, but the aspect ratio makes the height 65536.
        let e = image_size(Some(32768), None, 1, 2).unwrap_err();
        assert!(
            e.contains("makes the height 65536") && e.contains("give both"),
            "{e}"
        );
        assert!(image_size(Some(0), Some(5), 1, 1).is_err());
    }

    #[test]
    fn sampling_follows_the_request_then_the_file() {
        let s = scene(NFF, false);
        let opts = |r: RenderRequest| r.resolve(&s).unwrap().opts.sampling;
        assert_eq!(opts(RenderRequest::default()), Sampling::PixelCenters);
        let four = RenderRequest {
            spp: Some(4),
            ..Default::default()
        };
        assert_eq!(opts(four), Sampling::Stratified { spp: 4 });
        let spd = RenderRequest {
            spd: true,
            ..Default::default()
        };
        assert_eq!(opts(spd), Sampling::SpdCorners);
        assert!(RenderRequest { spp: Some(2), ..spd }.resolve(&s).is_err());
        let p3f = scene(
            "spp 9\ncamera eye 0 0 5 at 0 0 0 up 0 1 0 angle 40 hither 1 resolution 8 8\ns 0 0 0 1\n",
            true,
        );
        assert_eq!(
            RenderRequest::default().resolve(&p3f).unwrap().opts.sampling,
            Sampling::Stratified { spp: 9 }
        );
        assert_eq!(
            four.resolve(&p3f).unwrap().opts.sampling,
            Sampling::Stratified { spp: 4 }
        );
    }

    #[test]
    fn a_lens_is_never_dropped_silently() {
        let lens = scene(LENS, true);
        // No spp anywhere: the default that shows the effect, and a note saying so.
        let r = RenderRequest::default().resolve(&lens).unwrap();
        assert_eq!(
            r.opts.sampling,
            Sampling::Stratified {
                spp: DEFAULT_EFFECT_SPP
            }
        );
        assert_eq!(r.notes.len(), 1);
        assert!(
            r.notes[0].contains("lens") && r.notes[0].contains("16"),
            "{:?}",
            r.notes
        );
        // An explicit single sample: one jittered lens sample, no note.
        let one = RenderRequest {
            spp: Some(1),
            ..Default::default()
        };
        let r = one.resolve(&lens).unwrap();
        assert_eq!(
            (r.opts.sampling, r.notes.len()),
            (Sampling::Stratified { spp: 1 }, 0)
        );
        // A lens asked for on a pinhole scene, and a lens switched off.
        let plain = scene(NFF, false);
        let asked = RenderRequest {
            aperture: Some(6.0),
            ..Default::default()
        };
        assert_eq!(
            asked.resolve(&plain).unwrap().opts.sampling,
            Sampling::Stratified { spp: 16 }
        );
        let off = RenderRequest {
            aperture: Some(0.0),
            ..Default::default()
        };
        let r = off.resolve(&lens).unwrap();
        assert_eq!((r.opts.sampling, r.notes.len()), (Sampling::PixelCenters, 0));
        // The course's `spp 0`: one fixed sample at the pixel centre, as asked.
        let spp0 = scene(&format!("spp 0\n{}", LENS.replace("v from", "camera eye")), true);
        assert_eq!(
            RenderRequest::default().resolve(&spp0).unwrap().opts.sampling,
            Sampling::PixelCenters
        );
    }

    #[test]
    fn bad_values_are_errors_naming_the_setting() {
        let s = scene(NFF, false);
        for (r, want) in [
            (
                RenderRequest {
                    max_depth: Some(0),
                    ..Default::default()
                },
                "max depth 0",
            ),
            (
                RenderRequest {
                    max_depth: Some(65),
                    ..Default::default()
                },
                "max depth 65",
            ),
            (
                RenderRequest {
                    spp: Some(0),
                    ..Default::default()
                },
                "0 samples per pixel",
            ),
            (
                RenderRequest {
                    spp: Some(4097),
                    ..Default::default()
                },
                "4097 samples",
            ),
            (
                RenderRequest {
                    aperture: Some(-3.0),
                    ..Default::default()
                },
                "aperture -3",
            ),
            (
                RenderRequest {
                    aperture: Some(f32::NAN),
                    ..Default::default()
                },
                "aperture NaN",
            ),
            (
                RenderRequest {
                    focal: Some(0.0),
                    ..Default::default()
                },
                "focal distance 0",
            ),
            (
                RenderRequest {
                    light_samples: Some(0),
                    ..Default::default()
                },
                "0 light samples",
            ),
            (
                RenderRequest {
                    width: Some(0),
                    ..Default::default()
                },
                "width 0",
            ),
        ] {
            let e = r.resolve(&s).unwrap_err();
            assert!(e.contains(want), "{e:?} lacks {want:?}");
        }
    }
}
