//! The page's camera in the scene's terms: the view a request asks for, and that
//! view written as the block to paste into the file ("copy camera").

use super::protocol::{CameraMsg, OptionsMsg};
use nffrt::image::{Encoding, Region};
use nffrt::math::Vec3;
use nffrt::options::{check_render, RenderLimits, RenderOptions, RenderRequest};
use nffrt::prepare::PrepareOptions;
use nffrt::scene::{Accel, Dialect, IntegratorKind, SceneInfo, View};

/// The scene's view moved to `camera` (the lens, hither and angle span stay the
/// file's), at the requested resolution.
pub fn view_of(file: &View, camera: &CameraMsg, options: &OptionsMsg) -> View {
    View {
        from: Vec3::from_array(camera.from),
        at: Vec3::from_array(camera.at),
        up: Vec3::from_array(camera.up),
        angle: camera.angle,
        width: options.width,
        height: options.height,
        ..*file
    }
}

/// What the page's settings ask of a render: what `nffrt render --width --height
/// --max-depth --spp` asks, with the lens off (`--aperture 0`) unless wanted and
/// area lights from their centre unless soft shadows are.
pub fn request(options: &OptionsMsg) -> RenderRequest {
    RenderRequest {
        width: Some(options.width),
        height: Some(options.height),
        max_depth: Some(options.max_depth),
        spp: Some(options.spp),
        aperture: (!options.lens).then_some(0.0),
        hard_shadows: !options.soft_shadows,
        smooth: !options.rough,
        integrator: Some(options.integrator),
        ..RenderRequest::default()
    }
}

/// The options the page's settings give on `scene`, checked as every render is
/// ([`check_render`]: the renderer's ranges and the default pixel limit, which
/// the page is told of), with the 8-bit encoding `nffrt render` would write them
/// in, or why they cannot be rendered.
pub fn options_of(options: &OptionsMsg, scene: &SceneInfo) -> Result<(RenderOptions, Encoding), String> {
    let resolved = request(options).resolve(scene)?;
    let opts = resolved.opts;
    let full = Region::full(opts.width, opts.height);
    check_render(&opts, &full, &RenderLimits::default()).map_err(|e| e.to_string())?;
    Ok((opts, resolved.encoding))
}

/// The settings a page starts with on `scene`: what `nffrt render --spp SPP
/// --integrator INTEGRATOR` renders (the file's size, samples and integrator
/// unless the command line says, the same defaults), every effect on, the file's
/// shutter, and `accel` or the file's structure.
pub fn first_options(
    scene: &SceneInfo,
    spp: Option<u32>,
    integrator: Option<IntegratorKind>,
    accel: Option<Accel>,
) -> OptionsMsg {
    let request = RenderRequest {
        spp,
        integrator,
        ..RenderRequest::default()
    };
    // A file's settings are within the limits, so this resolves; should it not,
    // the file's size with the defaults is where the page starts.
    let opts = request
        .resolve(scene)
        .map(|r| r.opts)
        .unwrap_or_else(|_| RenderOptions::from_view(&scene.view));
    OptionsMsg {
        width: opts.width,
        height: opts.height,
        max_depth: opts.max_depth,
        spp: opts.sampling.samples_per_pixel(),
        lens: true,
        soft_shadows: true,
        rough: true,
        integrator: opts.integrator,
        shutter: scene.shutter,
        accel: accel.or(scene.accel).unwrap_or_default(),
        denoise: false,
    }
}

/// What the page's settings ask of the render-time scene.
pub fn prepare_options(options: &OptionsMsg) -> PrepareOptions {
    PrepareOptions {
        shutter: Some(options.shutter),
        accel: Some(options.accel),
    }
}

/// `view` as the scene file's camera block: `v` for NFF (no lens) and P3F 2019/20
/// (with `aperture` and `focal`), `camera` for P3F 2024/25
/// ([`nffrt::nff::view_block`]; its numbers read back to the same `f32`).
pub fn camera_block(view: &View, dialect: Dialect) -> String {
    nffrt::nff::view_block(view, dialect)
}

#[cfg(test)]
mod tests {
    use super::*;
    use nffrt::nff::{parse_format, Format, Limits};
    use nffrt::options::Sampling;

    /// A view whose numbers need every digit.
    fn odd_view(base: View) -> View {
        View {
            from: Vec3::new(0.1, -2.345_678_9, 1e-7),
            at: Vec3::new(1.0 / 3.0, 0.0, -7.25),
            up: Vec3::new(0.0, 1.0, 0.2),
            angle: 37.123_455,
            width: 321,
            height: 123,
            ..base
        }
    }

    #[test]
    fn blocks_read_back_as_the_same_view_in_every_language() {
        for (text, format) in [
            (
                "v from 0 0 5 at 0 0 0 up 0 1 0 angle 40 hither 1 resolution 8 8\ns 0 0 0 1\n",
                Format::Nff,
            ),
            (
                "v from 0 0 5 at 0 0 0 up 0 1 0 angle 40 hither 1 resolution 8 8 aperture 2 focal 1.5\n\
                 s 0 0 0 1\n",
                Format::P3f,
            ),
            (
                "spp 0\ncamera eye 0 0 5 at 0 0 0 up 0 1 0 angle 40 hither 0.5 resolution 8 8 \
                 aperture 3 focal 2\ns 0 0 0 1\n",
                Format::P3f,
            ),
        ] {
            let scene = parse_format(text.as_bytes(), format, &Limits::default()).unwrap();
            let view = odd_view(scene.view);
            let block = camera_block(&view, scene.dialect);
            // The block replaces the file's camera: the file then has exactly this view.
            let first_line_end = text.find("\ns ").unwrap();
            let edited = format!(
                "{}{block}{}",
                &text[..text.find(['v', 'c']).unwrap()],
                &text[first_line_end + 1..]
            );
            let back = parse_format(edited.as_bytes(), format, &Limits::default())
                .unwrap_or_else(|e| panic!("{e}\n{edited}"));
            assert_eq!(back.view, view, "{edited}");
        }
    }

    /// A 10x20 picture, depth 3, one sample, every effect on.
    fn small_options() -> OptionsMsg {
        OptionsMsg {
            width: 10,
            height: 20,
            max_depth: 3,
            spp: 1,
            lens: true,
            soft_shadows: true,
            rough: true,
            integrator: IntegratorKind::Whitted,
            shutter: [0.0, 1.0],
            accel: nffrt::scene::Accel::Bvh,
            denoise: false,
        }
    }

    #[test]
    fn options_map_to_the_render_flags() {
        let o = small_options();
        let scene = nffrt::Scene::default().info();
        let r = request(&o).resolve(&scene).unwrap().opts;
        assert_eq!((r.width, r.height, r.max_depth), (10, 20, 3));
        assert_eq!(
            (r.sampling, r.aperture, r.soft_shadows),
            (Sampling::PixelCenters, None, true)
        );
        let r = request(&OptionsMsg {
            spp: 9,
            lens: false,
            soft_shadows: false,
            ..o
        })
        .resolve(&scene)
        .unwrap()
        .opts;
        assert_eq!(
            (r.sampling, r.aperture, r.soft_shadows),
            (Sampling::Stratified { spp: 9 }, Some(0.0), false)
        );
        assert!(r.roughness && r.integrator == IntegratorKind::Whitted);
        let r = request(&OptionsMsg {
            rough: false,
            integrator: IntegratorKind::Path,
            ..o
        })
        .resolve(&scene)
        .unwrap()
        .opts;
        assert!(!r.roughness && r.integrator == IntegratorKind::Path);
        assert_eq!(prepare_options(&o).shutter, Some([0.0, 1.0]));
    }

    /// The page starts where `nffrt render` would: the file's samples, one without
    /// an effect that needs more, the effect default with one, and what the command
    /// line asks.
    #[test]
    fn the_first_settings_are_the_render_commands() {
        let parse = |text: &str, format| {
            parse_format(text.as_bytes(), format, &Limits::default())
                .unwrap()
                .info()
        };
        let nff = parse(
            "v from 0 0 5 at 0 0 0 up 0 1 0 angle 40 hither 1 resolution 8 6\ns 0 0 0 1\n",
            Format::Nff,
        );
        let first = first_options(&nff, None, None, None);
        assert_eq!(
            (first.width, first.height, first.spp, first.max_depth),
            (8, 6, 1, 5)
        );
        assert_eq!(
            (first.integrator, first.accel),
            (IntegratorKind::Whitted, Accel::Bvh)
        );
        let asked = first_options(&nff, Some(9), Some(IntegratorKind::Path), Some(Accel::Grid));
        assert_eq!(
            (asked.spp, asked.integrator, asked.accel),
            (9, IntegratorKind::Path, Accel::Grid)
        );
        // Path tracing needs samples: the command line's default for it.
        assert_eq!(
            first_options(&nff, None, Some(IntegratorKind::Path), None).spp,
            16
        );
        let p3f = parse(
            "spp 9\naccel grid\ncamera eye 0 0 5 at 0 0 0 up 0 1 0 angle 40 hither 1 resolution 8 8\ns 0 0 0 1\n",
            Format::P3f,
        );
        let first = first_options(&p3f, None, None, None);
        assert_eq!((first.spp, first.accel), (9, Accel::Grid));
        let lens = parse(
            "camera eye 0 0 5 at 0 0 0 up 0 1 0 angle 40 hither 1 resolution 8 8 aperture 2 focal 1\ns 0 0 0 1\n",
            Format::P3f,
        );
        assert_eq!(first_options(&lens, None, None, None).spp, 16);
    }

    /// The page's settings out of range are refused by the renderer's own checks,
    /// each naming the setting; the pixel limit is the one the page is told of.
    #[test]
    fn settings_out_of_range_are_refused_naming_the_setting() {
        let o = small_options();
        let scene = nffrt::Scene::default().info();
        assert!(options_of(&o, &scene).is_ok());
        for (bad, says) in [
            (OptionsMsg { spp: 0, ..o }, "0 samples per pixel"),
            (OptionsMsg { spp: 4097, ..o }, "4097 samples per pixel"),
            (OptionsMsg { max_depth: 65, ..o }, "max depth 65"),
            (OptionsMsg { max_depth: 0, ..o }, "max depth 0"),
            (OptionsMsg { width: 32769, ..o }, "width 32769"),
            (OptionsMsg { height: 0, ..o }, "height 0"),
            (
                OptionsMsg {
                    width: 16384,
                    height: 8192,
                    ..o
                },
                "more than the limit of 67108864",
            ),
        ] {
            let e = options_of(&bad, &scene).unwrap_err();
            assert!(e.contains(says), "{e:?} lacks {says:?}");
        }
    }
}
