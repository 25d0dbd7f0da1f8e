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
//! use nffrt::{load::Assets, options::RenderOptions, prepare::prepare, render::render};
//! let scene = nffrt::nff::parse("v from 0 0 5 at 0 0 0 up 0 1 0 angle 40 hither 1 resolution 8 8\n\
//!                                l 0 0 10\nf 1 1 1 1 0 1 0 1\ns 0 0 0 1\n").unwrap();
//! let prepared = prepare(scene, &Assets::default());
//! let opts = RenderOptions::from_view(prepared.view());
//! let (image, stats) = render(&prepared, prepared.view(), &opts).unwrap();
//! assert_eq!((image.width, stats.eye_rays), (8, 64));
//! ```

pub mod background;
pub mod emitters;
pub mod lighting;

pub use background::Background;
pub use emitters::Emitters;
pub use lighting::{LightQuad, LightSource, Lighting, Model};

use crate::accel::{Aggregate, Bvh, Rootstock};
use crate::geometry::{build_geometry_for_shutter, place_instances, Geometry, Hit, Primitive, Prototype};
use crate::image::skybox::FaceError;
use crate::image::Texture;
use crate::load::Assets;
use crate::math::Vec3;
use crate::scene::{Accel, Material, Scene, SceneInfo, View};
use rayon::prelude::*;
use std::sync::Arc;

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
    /// The images textured materials sample ([`Material::texture`]).
    textures: Vec<Arc<Texture>>,
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
    let (bvh, info, textures) = build(scene, opts, None);
    assemble(bvh, info, textures, assets, opts)
}

/// Prepares the frame whose fixed part is `fixed` and whose other primitives, camera,
/// lights and materials are `moving`'s (see [`FixedPart`]): only `moving`'s
/// primitives are built, under one root with `fixed`'s, in the arrays of `spare`
/// when it is an earlier frame's tree on the same fixed part
/// ([`RenderScene::into_bvh`]) or the arrays it lent ([`FixedPart::lend`]; nothing
/// of the fixed part is copied then). The same pictures as [`prepare_with`] of the
/// whole frame. `None` when `fixed` lent its arrays and `spare` is neither them nor
/// a frame's tree on them.
pub fn prepare_frame(
    fixed: &FixedPart,
    moving: Scene,
    spare: Option<Bvh>,
    assets: &Assets,
    opts: &PrepareOptions,
) -> Option<RenderScene> {
    let (bvh, mut info, textures) = build(moving, opts, fixed.prototypes.as_ref());
    info.include_counts(&fixed.info);
    let tree = fixed.stock.graft(bvh, spare)?;
    Some(assemble(tree, info, textures, assets, opts))
}

/// The part of an animated scene's frames that never moves, built once for all of
/// them ([`prepare_frame`]).
pub struct FixedPart {
    stock: Rootstock,
    info: SceneInfo,
    /// The prototypes of the frames' instances, built once for all of them.
    prototypes: Option<Prototypes>,
}

impl FixedPart {
    /// Builds the primitives of `scene` (its other settings are the frames'), and the
    /// prototypes it and the frames' moving parts place.
    pub fn new(scene: Scene, opts: &PrepareOptions) -> FixedPart {
        let prototypes = (!scene.prototypes.is_empty()).then(|| Prototypes::build(&scene.prototypes));
        let (bvh, info, _) = build(scene, opts, prototypes.as_ref());
        FixedPart {
            stock: Rootstock::new(bvh),
            info,
            prototypes,
        }
    }

    /// Its arrays, for a caller that renders one frame at a time to give as the
    /// first frame's `spare` (and each frame's tree to the next): the fixed part is
    /// then never copied, and held once in memory.
    pub fn lend(&mut self) -> Option<Bvh> {
        self.stock.lend()
    }
}

/// The structures built over a scene's prototypes ([`Scene::prototypes`]), once for
/// every scene that places them.
struct Prototypes {
    /// What they were built from.
    source: Arc<Vec<Scene>>,
    /// A BVH over each prototype's primitives, in their own space.
    built: Vec<Arc<dyn Prototype>>,
}

impl Prototypes {
    /// Builds each of `source`'s prototypes.
    fn build(source: &Arc<Vec<Scene>>) -> Prototypes {
        let built = source
            .par_iter()
            .map(|p| {
                Arc::new(Bvh::prototype(build_geometry_for_shutter(
                    p,
                    p.shutter_interval(),
                ))) as Arc<dyn Prototype>
            })
            .collect();
        Prototypes {
            source: source.clone(),
            built,
        }
    }
}

/// `scene`'s primitives built into a BVH, its summary and its textures (the scene's
/// lists freed before the build: the memory peak). Its instances place
/// `prototypes` when they were built from the scene's prototypes.
fn build(
    scene: Scene,
    opts: &PrepareOptions,
    prototypes: Option<&Prototypes>,
) -> (Bvh, SceneInfo, Vec<Arc<Texture>>) {
    let info = scene.info();
    let shutter = opts.shutter.unwrap_or(info.shutter);
    let geometry = geometry_of(&scene, shutter, prototypes);
    let textures = {
        let mut scene = scene;
        std::mem::take(&mut scene.textures)
    };
    (Bvh::new(geometry), info, textures)
}

/// Every render-time primitive of `scene`, its moving spheres bounded over
/// `shutter`, with its instances placing `prototypes` when they were built from
/// the scene's prototypes, else prototypes built here.
fn geometry_of(scene: &Scene, shutter: [f32; 2], prototypes: Option<&Prototypes>) -> Geometry {
    let mut geometry = build_geometry_for_shutter(scene, shutter);
    if !scene.instances.is_empty() {
        let own;
        let prototypes = match prototypes {
            Some(p) if Arc::ptr_eq(&p.source, &scene.prototypes) => p,
            _ => {
                own = Prototypes::build(&scene.prototypes);
                &own
            }
        };
        place_instances(scene, &prototypes.built, &mut geometry);
    }
    geometry
}

/// Every render-time primitive of `scene`, its instances' prototypes built: what
/// [`Bvh::new`] builds the scene's tree over (for a caller that times or
/// inspects the build; [`prepare`] does it all).
pub fn scene_geometry(scene: &Scene) -> Geometry {
    geometry_of(scene, scene.shutter_interval(), None)
}

/// The render-time scene of `bvh`, summarised by `info`, as `opts` choose.
fn assemble(
    bvh: Bvh,
    info: SceneInfo,
    textures: Vec<Arc<Texture>>,
    assets: &Assets,
    opts: &PrepareOptions,
) -> RenderScene {
    let shutter = opts.shutter.unwrap_or(info.shutter);
    let moving = info.has_moving_spheres();
    let lighting = Lighting::new(&info);
    let accel = Aggregate::new(bvh, opts.accel.or(info.accel).unwrap_or_default());
    RenderScene {
        emitters: Emitters::new(&lighting.lights, accel.bvh(), &info.materials),
        lighting,
        background: Background::new(info.background, assets.skybox.clone()),
        accel,
        shutter,
        motion: moving && shutter[1] > shutter[0],
        info,
        textures,
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

    /// The scene's BVH, the rest dropped: a frame's tree handed to the next frame's
    /// [`prepare_frame`] to build in.
    pub fn into_bvh(self) -> Bvh {
        self.accel.into_bvh()
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

    /// The texel that multiplies what material `m` sends back at `hit` on `prim`
    /// (see [`Material::texture`]): `None` for an untextured material, or a
    /// primitive without texture coordinates.
    #[inline]
    pub fn texel(&self, m: &Material, prim: &Primitive, hit: &Hit) -> Option<Vec3> {
        let texture = self.textures.get(m.texture? as usize)?;
        let [u, v] = prim.texcoords(hit, self.accel.data())?;
        Some(texture.sample(u, v))
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

    /// Waits until the files the scene names are decoded (a skybox's faces are decoded
    /// while rendering, [`crate::image::skybox::Skybox`]): the first that could not
    /// be, whose rays saw black. A caller tracing rays itself checks this before
    /// giving out what it traced.
    pub fn decode_assets(&self) -> Result<(), FaceError> {
        self.background.decode_all()
    }
}
