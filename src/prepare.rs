//! The prepare step: a parsed [`Scene`] and its [`Assets`] made into a
//! [`RenderScene`], everything a render reads, built once: the acceleration
//! structure over the render-time primitives, the materials, the light sources with
//! their intensities, the background, and the shading rules. The command line, the
//! viewer and the Python bindings all render a `RenderScene`, any number of times,
//! from any thread, each render with its own camera ([`View`]) and options.
//!
//! The scene is consumed: its primitive lists are converted and then freed before the
//! acceleration structure is built (the memory peak); its settings, lights and
//! materials as parsed, and a summary of its primitives, stay as [`SceneInfo`].
//!
//! ```
//! use nffrt::{load::Assets, options::RenderOptions, prepare::prepare};
//! let scene = nffrt::nff::parse("v from 0 0 5 at 0 0 0 up 0 1 0 angle 40 hither 1 resolution 8 8\n\
//!                                l 0 0 10\nf 1 1 1 1 0 1 0 1\ns 0 0 0 1\n").unwrap();
//! let prepared = prepare(scene, &Assets::default());
//! let opts = RenderOptions::from_view(prepared.view());
//! let (image, stats) = prepared.render(prepared.view(), &opts).unwrap();
//! assert_eq!((image.width, stats.eye_rays), (8, 64));
//! ```

use thiserror::Error;

use crate::accel::{Aggregate, Bvh};
use crate::geometry::{build_geometry_for_shutter, Primitive};
use crate::image::skybox::FaceError;
use crate::image::{Image, Region};
use crate::load::Assets;
use crate::options::{check_render, Refused, RenderLimits, RenderOptions};
use crate::render::emitters::Emitters;
use crate::render::{render_region, Background, Lighting, Observer, Silent, Stats};
use crate::scene::{Accel, Material, Scene, SceneInfo, View};

/// Why a render did not run to the end.
#[derive(Debug, Error, PartialEq, Eq)]
pub enum RenderError {
    /// The options or the region were refused before the render started.
    #[error(transparent)]
    Refused(#[from] Refused),
    /// The observer cancelled the render.
    #[error("the render was cancelled")]
    Cancelled,
    /// A skybox face could not be decoded (the picture is not given).
    #[error("{0}")]
    Asset(FaceError),
}

/// A scene ready to render (see the module docs).
pub struct RenderScene {
    info: SceneInfo,
    accel: Aggregate,
    lighting: Lighting,
    background: Background,
    shutter: [f32; 2],
    /// Moving geometry seen over a shutter that stays open for some time.
    motion: bool,
    /// The lights and emissive primitives a path tracer samples.
    emitters: Emitters,
}

/// What a caller may choose of the render-time scene, replacing the file's settings.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct PrepareOptions {
    /// When the camera's shutter opens and closes (`[open, close]`, `open <= close`;
    /// default: the file's `shutter`, else [`crate::limits::DEFAULT_SHUTTER`]).
    /// Moving geometry is bounded over it.
    pub shutter: Option<[f32; 2]>,
    /// The acceleration structure (default: the file's `accel`, else the BVH).
    pub accel: Option<Accel>,
}

/// Prepares `scene` with the files it names, `assets` (its skybox, if decoded), as
/// the file says.
pub fn prepare(scene: Scene, assets: &Assets) -> RenderScene {
    prepare_with(scene, assets, &PrepareOptions::default())
}

/// Prepares `scene` with the files it names, `assets`, and the choices of `opts`.
pub fn prepare_with(scene: Scene, assets: &Assets, opts: &PrepareOptions) -> RenderScene {
    let info = scene.info();
    let shutter = opts.shutter.unwrap_or(info.shutter);
    let geometry = build_geometry_for_shutter(&scene, shutter);
    drop(scene);
    let moving = info.has_moving_spheres();
    let lighting = Lighting::new(&info);
    let accel = Aggregate::new(
        Bvh::new(geometry),
        opts.accel.or(info.accel).unwrap_or(Accel::Bvh),
    );
    RenderScene {
        emitters: Emitters::new(&lighting.lights, accel.bvh(), &info.materials),
        lighting,
        background: Background::new(info.background, assets.skybox.clone()),
        accel,
        shutter,
        motion: moving && shutter[1] > shutter[0],
        info,
    }
}

impl RenderScene {
    /// The scene's settings and summary.
    pub fn info(&self) -> &SceneInfo {
        &self.info
    }

    /// The scene file's camera.
    pub fn view(&self) -> &View {
        &self.info.view
    }

    /// When the camera's shutter opens and closes.
    pub fn shutter(&self) -> [f32; 2] {
        self.shutter
    }

    /// True if some geometry moves while the shutter is open: eye samples then take
    /// their times.
    pub fn has_motion(&self) -> bool {
        self.motion
    }

    /// The acceleration structure.
    pub fn accel(&self) -> &Aggregate {
        &self.accel
    }

    /// The number of render-time primitives (polygons as the triangles they are cut
    /// into, a split cone once).
    pub fn primitive_count(&self) -> usize {
        self.accel.primitive_count()
    }

    /// Render-time primitive `index`, as the acceleration structure reports it.
    #[inline]
    pub fn primitive(&self, index: u32) -> &Primitive {
        self.accel.primitive(index)
    }

    /// The material table.
    #[inline]
    pub fn materials(&self) -> &[Material] {
        &self.info.materials
    }

    /// The lights with their intensities, the ambient term and the shading rules.
    pub fn lighting(&self) -> &Lighting {
        &self.lighting
    }

    /// The lights and emissive primitives a path tracer samples.
    pub fn emitters(&self) -> &Emitters {
        &self.emitters
    }

    /// What rays that leave the scene see.
    pub fn background(&self) -> &Background {
        &self.background
    }

    /// Renders the whole `opts.width` x `opts.height` image seen by `view` (see
    /// [`RenderScene::render_region`]).
    pub fn render(&self, view: &View, opts: &RenderOptions) -> Result<(Image, Stats), RenderError> {
        let full = Region::full(opts.width, opts.height);
        self.render_region(view, opts, &full, &Silent)
    }

    /// Checks `opts` and `region` ([`check_render`]), then renders the region of the
    /// full image seen by `view`, reporting rows to `observer`: the same pixels as
    /// the full render has there, bit for bit.
    pub fn render_region(
        &self,
        view: &View,
        opts: &RenderOptions,
        region: &Region,
        observer: &dyn Observer,
    ) -> Result<(Image, Stats), RenderError> {
        check_render(opts, region, &RenderLimits::default())?;
        let rendered = render_region(self, view, opts, region, observer).ok_or(RenderError::Cancelled)?;
        self.decode_assets().map_err(RenderError::Asset)?;
        Ok(rendered)
    }

    /// Waits until the files the scene names are decoded (a skybox's faces are decoded
    /// while rendering, [`crate::image::skybox::Skybox`]): the first that could not
    /// be, whose rays saw black. A caller tracing rays itself checks this before
    /// giving out what it traced.
    pub fn decode_assets(&self) -> Result<(), FaceError> {
        self.background.decode_all()
    }
}

#[cfg(test)]
mod tests {
    use std::sync::atomic::{AtomicU32, Ordering};

    use super::*;
    use crate::options::Sampling;

    /// A red sphere in front of a grey mirror plane, lit from the camera's side.
    const SCENE: &str = "v from 0 0 6 at 0 0 0 up 0 1 0 angle 40 hither 1 resolution 23 17\n\
                         b 0.1 0.2 0.3\nl 2 3 8\nf 1 0 0 0.8 0.2 20 0 1\ns 0 0 0 1.2\n\
                         f 0.5 0.5 0.5 0.5 0.5 10 0 1\npl 0 0 -2 1 0 -2 0 1 -2\n";

    fn prepared() -> RenderScene {
        prepare(crate::nff::parse(SCENE).unwrap(), &Assets::default())
    }

    #[test]
    fn a_region_has_the_full_renders_pixels() {
        let p = prepared();
        let opts = RenderOptions {
            sampling: Sampling::Stratified { spp: 3 },
            ..RenderOptions::from_view(p.view())
        };
        let (full, _) = p.render(p.view(), &opts).unwrap();
        let r = Region {
            x0: 5,
            y0: 2,
            x1: 19,
            y1: 11,
        };
        let (crop, stats) = p.render_region(p.view(), &opts, &r, &Silent).unwrap();
        assert_eq!((crop.width, crop.height), (14, 9));
        assert_eq!(stats.eye_rays, 14 * 9 * 3);
        for y in 0..9 {
            for x in 0..14 {
                assert_eq!(crop.get(x, y), full.get(x + 5, y + 2), "({x}, {y})");
            }
        }
    }

    #[test]
    fn bad_options_are_errors_not_panics() {
        let p = prepared();
        let good = RenderOptions::from_view(p.view());
        let full = Region::full(23, 17);
        let cases: [(RenderOptions, Region, &str); 10] = [
            (RenderOptions { width: 0, ..good }, full, "width and height"),
            (
                RenderOptions {
                    height: 40000,
                    ..good
                },
                full,
                "width and height",
            ),
            (RenderOptions { max_depth: 0, ..good }, full, "max depth 0"),
            (
                RenderOptions {
                    max_depth: 65,
                    ..good
                },
                full,
                "max depth 65",
            ),
            (
                RenderOptions {
                    sampling: Sampling::Stratified { spp: 0 },
                    ..good
                },
                full,
                "0 samples",
            ),
            (
                RenderOptions {
                    aperture: Some(f32::NAN),
                    ..good
                },
                full,
                "aperture NaN",
            ),
            (
                RenderOptions {
                    focal: Some(0.0),
                    ..good
                },
                full,
                "focal distance 0",
            ),
            (
                RenderOptions {
                    light_samples: Some(0),
                    ..good
                },
                full,
                "0 light samples",
            ),
            (
                good,
                Region {
                    x0: 0,
                    y0: 0,
                    x1: 24,
                    y1: 17,
                },
                "does not fit",
            ),
            (
                good,
                Region {
                    x0: 3,
                    y0: 0,
                    x1: 3,
                    y1: 17,
                },
                "is empty",
            ),
        ];
        for (opts, region, want) in cases {
            match p.render_region(p.view(), &opts, &region, &Silent) {
                Err(RenderError::Refused(m)) => assert!(m.to_string().contains(want), "{m:?} lacks {want:?}"),
                other => panic!("{want}: {:?}", other.map(|(_, s)| s)),
            }
        }
        let huge = RenderOptions {
            width: 32768,
            height: 32768,
            ..good
        };
        let e = p.render(p.view(), &huge).unwrap_err();
        assert!(e.to_string().contains("more than the limit"), "{e}");
    }

    /// Cancels once `after` rows are done.
    struct CancelAfter {
        rows: AtomicU32,
        after: u32,
    }

    impl Observer for CancelAfter {
        fn row_done(&self, _rays: u64) {
            self.rows.fetch_add(1, Ordering::SeqCst);
        }
        fn cancelled(&self) -> bool {
            self.rows.load(Ordering::SeqCst) >= self.after
        }
    }

    #[test]
    fn an_observer_cancels() {
        let p = prepared();
        // Tall, so that rows already started when it cancels cannot be all of them.
        let opts = RenderOptions {
            height: 400,
            ..RenderOptions::from_view(p.view())
        };
        let observer = CancelAfter {
            rows: AtomicU32::new(0),
            after: 2,
        };
        let full = Region::full(23, 400);
        assert_eq!(
            p.render_region(p.view(), &opts, &full, &observer).unwrap_err(),
            RenderError::Cancelled
        );
        assert!(observer.rows.load(Ordering::SeqCst) < 400);
    }
}
