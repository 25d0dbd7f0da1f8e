//! `nffrt info`: a human or JSON summary of a scene.

use std::path::PathBuf;

use clap::Args;
use serde::Serialize;

use super::limits::SceneLimitArgs;
use super::load::{load_scene, print_warnings, Need};
use super::CliError;
use nffrt::accel::{Bvh, BvhStats};
use nffrt::aff::AffSummary;
use nffrt::image::Encoding;
use nffrt::options::display_encoding;
use nffrt::prepare::scene_geometry;
use nffrt::scene::{Accel, IntegratorKind};
use nffrt::words::count;

/// Arguments of `nffrt info`.
#[derive(Args, Debug)]
pub struct InfoArgs {
    /// Scene file, NFF, P3F or AFF (by its extension or --format); `-` reads standard input.
    pub scene: PathBuf,
    /// Print one JSON object instead of the human summary.
    #[arg(long)]
    pub json: bool,
    /// Also build the BVH and print the statistics of its 8-wide tree, the one traversed
    /// (nodes, leaves, depth, leaf sizes, SAH cost, node visits per ray, build time).
    #[arg(long)]
    pub bvh: bool,
    /// Resource limits.
    #[command(flatten)]
    pub limits: SceneLimitArgs,
}

/// The BVH part of `info --bvh`.
#[derive(Serialize)]
struct BvhInfo {
    #[serde(flatten)]
    stats: BvhStats,
    bounds_min: Option<[f32; 3]>,
    bounds_max: Option<[f32; 3]>,
    build_s: f64,
}

fn bvh_info(scene: &nffrt::Scene) -> BvhInfo {
    let t0 = std::time::Instant::now();
    let bvh = Bvh::new(scene_geometry(scene));
    let build_s = t0.elapsed().as_secs_f64();
    let bounds = bvh.bounds();
    BvhInfo {
        stats: bvh.stats(),
        bounds_min: bounds.map(|b| b.0.to_array()),
        bounds_max: bounds.map(|b| b.1.to_array()),
        build_s,
    }
}

/// The camera as `info --json` gives it (f32 values, written as their shortest
/// decimals).
#[derive(Serialize)]
struct CameraJson {
    from: [f32; 3],
    at: [f32; 3],
    up: [f32; 3],
    /// Vertical field of view, degrees.
    angle: f32,
    /// Width and height in pixels.
    resolution: [u32; 2],
    /// Lens diameter in pixels (0: a pinhole).
    aperture: f32,
    /// Focal distance over |from - at|.
    focal: f32,
}

impl CameraJson {
    fn of(v: &nffrt::scene::View) -> CameraJson {
        CameraJson {
            from: v.from.to_array(),
            at: v.at.to_array(),
            up: v.up.to_array(),
            angle: v.angle,
            resolution: [v.width, v.height],
            aperture: v.aperture,
            focal: v.focal,
        }
    }
}

#[derive(Serialize)]
struct InfoJson {
    /// The scene file as named on the command line (`<stdin>` for `-`).
    scene: String,
    /// `nff`, `p3f-2019`, `p3f-2025` or `aff` (the rest describes an AFF scene's
    /// first frame).
    dialect: &'static str,
    /// An AFF scene's animation, hierarchy, objects, textures and triangles.
    #[serde(skip_serializing_if = "Option::is_none")]
    aff: Option<AffSummary>,
    camera: CameraJson,
    /// The acceleration structure a render uses without `--accel`: the P3F file's
    /// `accel`, else `bvh`.
    accel: Accel,
    /// The traversal kernels the queries run: `avx2` or `portable` (`NFFRT_SIMD`).
    kernels: &'static str,
    /// P3F `spp`, if given.
    #[serde(skip_serializing_if = "Option::is_none")]
    spp: Option<u32>,
    /// P3F `integrator` as written, if any.
    #[serde(skip_serializing_if = "Option::is_none")]
    integrator: Option<IntegratorKind>,
    /// How `nffrt render` writes this scene's 8-bit pictures without `--encoding`
    /// or `--integrator`: `linear`, `srgb` or `gamma2.2`.
    encoding: Encoding,
    /// The shutter's opening and closing times: the file's `shutter`, else 0 and 1.
    shutter: [f32; 2],
    /// Materials that emit light (P3F's 14-number `f` / `mat`).
    emissive_materials: usize,
    /// Materials with a non-zero roughness (P3F `roughness`).
    rough_materials: usize,
    moving_spheres: usize,
    /// The skybox folder as written, if any.
    #[serde(skip_serializing_if = "Option::is_none")]
    skybox: Option<String>,
    area_lights: usize,
    meshes: usize,
    mesh_triangles: usize,
    mesh_vertices: usize,
    aperture: f32,
    focal: f32,
    spheres: usize,
    polygons: usize,
    patches: usize,
    cones: usize,
    planes: usize,
    boxes: usize,
    lights: usize,
    materials: usize,
    width: u32,
    height: u32,
    polygon_vertices: usize,
    patch_vertices: usize,
    bounds_min: Option<[f32; 3]>,
    bounds_max: Option<[f32; 3]>,
    warnings: Vec<String>,
    parse_s: f64,
    #[serde(skip_serializing_if = "Option::is_none")]
    bvh: Option<BvhInfo>,
}

/// The 8-bit encoding `nffrt render` gives `scene`'s pictures by default.
fn default_encoding(scene: &nffrt::Scene) -> Encoding {
    display_encoding(scene.integrator.unwrap_or_default(), scene.dialect.is_p3f())
}

/// Runs `nffrt info`.
pub fn run(args: InfoArgs) -> Result<(), CliError> {
    let loaded = load_scene(&args.scene, &args.limits, Need::Summary)?;
    let s = &loaded.scene;
    let b = s.bounds();
    let bounds = (!b.is_empty()).then_some((b.min.to_array(), b.max.to_array()));
    let bvh = args.bvh.then(|| bvh_info(s));
    let aff = loaded.aff.as_ref().map(|a| a.summary());
    let dialect = if aff.is_some() { "aff" } else { s.dialect.name() };
    if args.json {
        let j = InfoJson {
            scene: loaded.name.clone(),
            dialect,
            aff,
            camera: CameraJson::of(&s.view),
            accel: s.accel.unwrap_or_default(),
            kernels: nffrt::accel::simd::level().name(),
            spp: s.spp,
            integrator: s.integrator,
            encoding: default_encoding(s),
            shutter: s.shutter_interval(),
            emissive_materials: emissive_materials(s),
            rough_materials: rough_materials(s),
            moving_spheres: s.moving_spheres.len(),
            skybox: s.environment.as_ref().map(|e| e.folder.clone()),
            area_lights: area_lights(s),
            meshes: s.meshes.len(),
            mesh_triangles: s.mesh_triangles.len(),
            mesh_vertices: s.mesh_vertices.len(),
            aperture: s.view.aperture,
            focal: s.view.focal,
            spheres: s.spheres.len(),
            polygons: s.polygons.len(),
            patches: s.patches.len(),
            cones: s.cones.len(),
            planes: s.planes.len(),
            boxes: s.boxes.len(),
            lights: s.lights.len(),
            materials: s.materials.len(),
            width: s.view.width,
            height: s.view.height,
            polygon_vertices: s.polygon_vertices.len(),
            patch_vertices: s.patch_vertices.len(),
            bounds_min: bounds.map(|b| b.0),
            bounds_max: bounds.map(|b| b.1),
            warnings: s.warnings.iter().map(|w| w.to_string()).collect(),
            parse_s: loaded.parse_s,
            bvh,
        };
        outln!("{}", serde_json::to_string(&j).expect("plain data serializes"));
        return Ok(());
    }
    let v = &s.view;
    outln!("scene       {}", loaded.name);
    outln!("resolution  {} x {}", v.width, v.height);
    outln!(
        "camera      from {} {} {}  at {} {} {}  up {} {} {}  angle {}",
        v.from.x,
        v.from.y,
        v.from.z,
        v.at.x,
        v.at.y,
        v.at.z,
        v.up.x,
        v.up.y,
        v.up.z,
        v.angle
    );
    outln!("format      {dialect}");
    if let Some(a) = &aff {
        print_aff(a);
    }
    match s.accel {
        Some(a) => outln!(
            "accel       {} (as the file asks; --accel chooses another)",
            accel_name(a)
        ),
        None => outln!("accel       bvh (the default; --accel chooses another)"),
    }
    let variable = nffrt::accel::simd::SIMD_VARIABLE;
    let kernels = nffrt::accel::simd::level().name();
    match nffrt::accel::simd::requested() {
        Ok(Some(_)) => outln!("kernels     {kernels} (as {variable} asks)"),
        _ => outln!("kernels     {kernels} (the widest this CPU runs; {variable}=avx2|portable chooses)"),
    }
    if let Some(n) = s.spp {
        outln!(
            "spp         {n}{}",
            if n == 0 {
                " (one sample at each pixel centre)"
            } else {
                ""
            }
        );
    }
    if let Some(i) = s.integrator {
        outln!("integrator  {} (as the file asks)", i.name());
    }
    outln!(
        "encoding    {} (8-bit pictures of {}; --encoding chooses another)",
        default_encoding(s),
        match s.integrator.unwrap_or_default() {
            IntegratorKind::Whitted => "Whitted's rules: linear, as the course's first assignment",
            IntegratorKind::Path if s.dialect.is_p3f() => "path tracing: the course's toGamma",
            IntegratorKind::Path => "path tracing: sRGB",
        }
    );
    if s.shutter.is_some() || !s.moving_spheres.is_empty() {
        let [open, close] = s.shutter_interval();
        let default = if s.shutter.is_none() { " (the default)" } else { "" };
        outln!("shutter     open from time {open} to {close}{default}");
    }
    if v.aperture > 0.0 {
        outln!(
            "lens        aperture {}, focal {} x the view distance",
            count(v.aperture, "pixel", "pixels"),
            v.focal
        );
    }
    if let Some(e) = &s.environment {
        outln!("skybox      {} (six faces)", e.folder);
    }
    let areas = area_lights(s);
    outln!(
        "lights      {} ({} point, {} area)",
        s.lights.len(),
        s.lights.len() - areas,
        areas
    );
    let (emissive, rough) = (emissive_materials(s), rough_materials(s));
    let finish = match (emissive, rough) {
        (0, 0) => String::new(),
        (e, 0) => format!(" ({e} emitting)"),
        (0, r) => format!(" ({r} rough)"),
        (e, r) => format!(" ({e} emitting, {r} rough)"),
    };
    outln!("materials   {}{finish}", s.materials.len());
    outln!("primitives  {}", s.primitive_count());
    for (name, n) in s.kind_counts() {
        if n > 0 && name != "instances" {
            // (A name of ten letters or more still gets a space.)
            outln!("  {name:<9} {n}");
        }
    }
    if !s.instances.is_empty() {
        let placed: usize = s
            .instances
            .iter()
            .map(|x| s.prototypes[x.prototype as usize].primitive_count())
            .sum();
        let built: usize = s.prototypes.iter().map(nffrt::Scene::primitive_count).sum();
        outln!(
            "  {:<10}{} of {} built once ({}), placing {}",
            "instances",
            s.instances.len(),
            count(s.prototypes.len(), "prototype", "prototypes"),
            count(built, "triangle", "triangles"),
            count(placed, "triangle", "triangles")
        );
    }
    if !s.meshes.is_empty() {
        outln!(
            "  {:<10}{} in {} ({})",
            "meshes",
            count(s.mesh_triangles.len(), "triangle", "triangles"),
            count(s.meshes.len(), "mesh", "meshes"),
            count(s.mesh_vertices.len(), "vertex", "vertices")
        );
    }
    match bounds {
        Some((lo, hi)) => outln!("bounds      {lo:?} .. {hi:?}"),
        None => outln!("bounds      (no bounded primitive)"),
    }
    outln!(
        "load time   {:.1} ms parsing, {:.1} ms checking the files it names (headers only)",
        loaded.parse_s * 1e3,
        loaded.assets_s * 1e3
    );
    outln!("warnings    {}", s.warnings.len());
    if let Some(b) = &bvh {
        print_bvh(b);
    }
    print_warnings(&loaded, 20);
    Ok(())
}

/// The lines of an AFF scene's summary; the rest of `info` describes its first frame.
fn print_aff(a: &AffSummary) {
    let [start, end] = a.time_span;
    outln!(
        "animation   {} from time {start} to {end}, {} apart (the rest: frame 0, at time {start})",
        count(a.frames, "frame", "frames"),
        a.frame_step
    );
    outln!(
        "files       {} read, {} followed{}",
        a.files,
        count(a.inclusions, "include", "includes"),
        match a.skipped_inclusions {
            0 => String::new(),
            n => format!(", {n} skipped for their detail level"),
        }
    );
    let unkeyed = match a.unkeyed_transforms {
        0 => String::new(),
        n => format!(" ({n} without keys)"),
    };
    outln!(
        "transforms  {} static, {} keyframed{unkeyed}; {}{}",
        a.static_transforms,
        a.animated_transforms,
        count(a.keyframe_blocks, "keyframe block", "keyframe blocks"),
        if a.animated_camera {
            ", the camera's among them"
        } else {
            ""
        }
    );
    let objects: Vec<String> = a
        .objects
        .named()
        .iter()
        .filter(|(_, n)| *n > 0)
        .map(|(kind, n)| format!("{n} {}", kind.replace('_', " ")))
        .collect();
    outln!(
        "objects     {} (meshes: {} distinct)",
        objects.join(", "),
        a.mesh_geometries
    );
    outln!(
        "textures    {} ({})",
        a.textures.len(),
        count(a.texels, "texel", "texels")
    );
    outln!(
        "triangles   {} stored (instanced), {} in a flattened frame",
        a.instanced_triangles,
        a.flattened_triangles
    );
}

fn accel_name(a: Accel) -> &'static str {
    match a {
        Accel::None => "none",
        Accel::Grid => "grid",
        Accel::Bvh => "bvh",
    }
}

fn area_lights(s: &nffrt::Scene) -> usize {
    s.lights.iter().filter(|l| l.area.is_some()).count()
}

fn emissive_materials(s: &nffrt::Scene) -> usize {
    s.materials
        .iter()
        .filter(|m| m.emission != nffrt::math::Vec3::ZERO)
        .count()
}

fn rough_materials(s: &nffrt::Scene) -> usize {
    s.materials.iter().filter(|m| m.roughness != 0.0).count()
}

fn print_bvh(b: &BvhInfo) {
    let s = &b.stats;
    outln!("bvh");
    outln!(
        "  primitives  {} in the tree, {} unbounded beside it",
        s.primitives,
        s.unbounded
    );
    if s.references != s.primitives {
        outln!(
            "  entries     {} (long oblique cones filed once per piece)",
            s.references
        );
    }
    if let (Some(lo), Some(hi)) = (b.bounds_min, b.bounds_max) {
        outln!("  bounds      {lo:?} .. {hi:?}");
    }
    outln!(
        "  nodes       {} 8-wide ({}), {:.1} of 8 lanes used per node",
        s.nodes,
        count(s.leaves, "leaf", "leaves"),
        s.mean_lanes
    );
    outln!("  depth       {}", s.depth);
    outln!(
        "  leaf size   min {}, mean {:.2}, max {}",
        s.min_leaf,
        s.mean_leaf,
        s.max_leaf
    );
    outln!(
        "  SAH cost    {:.2} ({:.2} node visits per ray)",
        s.sah_cost,
        s.expected_visits
    );
    outln!("  build time  {:.1} ms", b.build_s * 1e3);
}
