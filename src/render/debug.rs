//! `--pixel`: trace one pixel exactly as the renderer does and keep the ray tree.
//!
//! [`trace_pixel`] runs the same integrator as [`super::render`] with a
//! [`Recorder`] that builds a [`RayNode`] tree per eye ray, and combines the samples
//! with the same functions, so the value it reports is bit for bit the rendered
//! pixel's. [`PixelTrace`]'s `Display` prints the tree indented, one line per fact;
//! its `Serialize` gives the same data as JSON (tuples as arrays, vectors as
//! `{x, y, z}`), for `nffrt view`.

use std::fmt;

use super::integrator::{AreaOutcome, HitRecord, LightOutcome, PathEvent, Recorder, TraceContext};
use super::path_log::{write_path, PathStep};
use super::{spd_mean, Branch, CameraSample, RenderError, RowTracer, SampleId, Stats};
use crate::geometry::SourceKind;
use crate::image::skybox::SkyTexel;
use crate::image::{quantize, Region};
use crate::math::{Ray, Vec3};
use crate::options::{check_render, RenderLimits, RenderOptions, Sampling};
use crate::prepare::RenderScene;
use crate::scene::{Dialect, Material, View};

/// One ray of the tree and what it saw.
#[derive(Clone, Debug, PartialEq, serde::Serialize)]
pub struct RayNode {
    /// Ray origin.
    pub origin: Vec3,
    /// Unit direction.
    pub dir: Vec3,
    /// The surface hit, `None` for a ray that left the scene.
    pub hit: Option<HitNode>,
    /// The colour this ray returns (the background for a miss).
    pub color: Vec3,
    /// For a miss under a skybox, the face and texel it saw.
    pub sky: Option<SkyTexel>,
    /// The moment the ray sees the scene at.
    pub time: f32,
    /// For a ray from a rough surface, the direction a smooth one would have given
    /// it (its own was drawn about a microfacet normal).
    pub smooth_dir: Option<Vec3>,
}

/// A surface hit of a [`RayNode`].
#[derive(Clone, Debug, PartialEq, serde::Serialize)]
pub struct HitNode {
    /// Ray-tree depth (eye ray = 1).
    pub depth: u32,
    /// The NFF entity hit.
    pub kind: SourceKind,
    /// Its line in the scene file.
    pub line: u32,
    /// Index into the material table and the material itself.
    pub material: (u32, Material),
    /// Distance along the ray.
    pub t: f32,
    /// The hit point.
    pub point: Vec3,
    /// Geometric normal, facing the ray.
    pub normal: Vec3,
    /// Shading normal, facing the ray (differs from `normal` on patches).
    pub shading_normal: Vec3,
    /// True if the ray enters the object (against the primitive's normal).
    pub entering: bool,
    /// The ambient term.
    pub ambient: Vec3,
    /// For a ray inside absorbing glass, the fraction of light left after its way
    /// to this hit (Beer-Lambert).
    pub absorbed: Option<Vec3>,
    /// Each light's outcome, in file order.
    pub lights: Vec<LightRecord>,
    /// Secondary rays: kind, weight and the subtree.
    pub children: Vec<(Branch, Vec3, RayNode)>,
}

/// What one light did at a hit.
#[derive(Clone, Debug, PartialEq, serde::Serialize)]
pub enum LightRecord {
    /// A point light's outcome.
    Point(LightOutcome),
    /// An area light: each sampled point with its outcome, and the sum.
    Area {
        /// The points sampled and what became of each.
        points: Vec<(Vec3, LightOutcome)>,
        /// The counts and the total contribution.
        outcome: AreaOutcome,
    },
}

/// What became of one eye ray: its Whitted ray tree, or its path.
#[derive(Clone, Debug, PartialEq, serde::Serialize)]
#[serde(untagged)]
pub enum Traced {
    /// The ray tree (Whitted).
    Tree(Box<RayNode>),
    /// The path's events (path tracing).
    Path(Vec<PathStep>),
}

/// The ray trees of every eye ray of one pixel, and the pixel's value.
#[derive(Clone, Debug, PartialEq, serde::Serialize)]
pub struct PixelTrace {
    /// Pixel column.
    pub x: u32,
    /// Pixel row.
    pub y: u32,
    /// The options the pixel was traced with.
    pub opts: RenderOptions,
    /// Each eye ray: its camera sample and what became of it.
    pub samples: Vec<(CameraSample, Traced)>,
    /// True if the camera has a lens (the lens positions are printed).
    pub lens: bool,
    /// True if geometry moves while the shutter is open (the times are printed).
    pub motion: bool,
    /// The pixel's linear value, identical to the rendered one.
    pub value: Vec3,
    /// Ray counts of this pixel.
    pub stats: Stats,
    /// Light positions, for the printout.
    pub lights: Vec<Vec3>,
    /// The scene's language (names the keywords in the printout).
    pub dialect: Dialect,
}

/// A secondary ray announced by `branch`: its kind, weight and, from a rough
/// surface, the direction a smooth one would have given it.
type Pending = (Branch, Vec3, Option<Vec3>);

/// Builds the tree from the recursion's events.
struct TreeRecorder<'a> {
    materials: &'a [Material],
    open: Vec<(Option<Pending>, RayNode)>,
    pending: Option<Pending>,
    /// Points of the area light being sampled.
    points: Vec<(Vec3, LightOutcome)>,
    root: Option<RayNode>,
    /// The path tracer's events.
    path: Vec<PathStep>,
}

impl TreeRecorder<'_> {
    fn attach(&mut self, branch: Option<Pending>, mut node: RayNode) {
        match (self.open.last_mut(), branch) {
            (Some((_, parent)), Some((kind, w, smooth))) => {
                node.smooth_dir = smooth;
                parent
                    .hit
                    .as_mut()
                    .expect("open nodes are hits")
                    .children
                    .push((kind, w, node));
            }
            _ => self.root = Some(node),
        }
    }
}

impl TreeRecorder<'_> {
    fn push_light(&mut self, record: LightRecord) {
        if let Some((_, RayNode { hit: Some(h), .. })) = self.open.last_mut() {
            h.lights.push(record);
        }
    }
}

impl Recorder for TreeRecorder<'_> {
    fn miss(&mut self, ray: &Ray, background: Vec3, texel: Option<SkyTexel>) {
        let node = RayNode {
            sky: texel,
            time: ray.time,
            smooth_dir: None,
            origin: ray.origin,
            dir: ray.dir,
            hit: None,
            color: background,
        };
        let branch = self.pending.take();
        self.attach(branch, node);
    }

    fn hit(&mut self, ray: &Ray, h: &HitRecord) {
        let m = h.primitive.material;
        let node = RayNode {
            sky: None,
            time: ray.time,
            smooth_dir: None,
            origin: ray.origin,
            dir: ray.dir,
            hit: Some(HitNode {
                depth: h.depth,
                kind: h.primitive.kind,
                line: h.primitive.line,
                material: (m, self.materials[m as usize]),
                t: h.t,
                point: h.point,
                normal: h.normal,
                shading_normal: h.shading_normal,
                entering: h.entering,
                ambient: h.ambient,
                absorbed: h.absorbed,
                lights: Vec::new(),
                children: Vec::new(),
            }),
            color: Vec3::ZERO,
        };
        let branch = self.pending.take();
        self.open.push((branch, node));
    }

    fn light(&mut self, _index: usize, outcome: LightOutcome) {
        self.push_light(LightRecord::Point(outcome));
    }

    fn light_sample(&mut self, _index: usize, point: Vec3, outcome: LightOutcome) {
        self.points.push((point, outcome));
    }

    fn area_light(&mut self, _index: usize, outcome: AreaOutcome) {
        let points = std::mem::take(&mut self.points);
        self.push_light(LightRecord::Area { points, outcome });
    }

    fn branch(&mut self, kind: Branch, weight: Vec3, smooth: Option<Vec3>) {
        self.pending = Some((kind, weight, smooth));
    }

    fn path(&mut self, event: PathEvent) {
        self.path.push(PathStep::of(event));
    }

    fn done(&mut self, color: Vec3) {
        if let Some((branch, mut node)) = self.open.pop() {
            node.color = color;
            self.attach(branch, node);
        }
    }
}

/// Traces pixel `(x, y)` of `scene` seen by `view` as the renderer does, the
/// options and the pixel checked as [`super::render_region`] checks a render (a
/// skybox face that could not be decoded is an error too).
pub fn trace_pixel(
    scene: &RenderScene,
    view: &View,
    opts: &RenderOptions,
    x: u32,
    y: u32,
) -> Result<PixelTrace, RenderError> {
    let pixel = Region {
        x0: x,
        y0: y,
        x1: x.saturating_add(1),
        y1: y.saturating_add(1),
    };
    check_render(opts, &pixel, &RenderLimits::default())?;
    let frame = RowTracer::new(scene, view, opts);
    let mut ctx = TraceContext::default();
    let mut samples = Vec::new();
    let mut trace_at = |sample: CameraSample, id: SampleId| {
        let mut rec = TreeRecorder {
            materials: scene.materials(),
            open: Vec::new(),
            pending: None,
            points: Vec::new(),
            root: None,
            path: Vec::new(),
        };
        let c = frame.sample_radiance(&sample, &id, &mut ctx, &mut rec);
        let traced = match rec.root {
            Some(tree) => Traced::Tree(Box::new(tree)),
            None => Traced::Path(rec.path),
        };
        samples.push((sample, traced));
        c
    };
    let value = match opts.sampling {
        Sampling::SpdCorners => {
            let (fx, fy) = (x as f32, y as f32);
            let c = [(fx, fy), (fx + 1.0, fy), (fx, fy + 1.0), (fx + 1.0, fy + 1.0)]
                .map(|(a, b)| trace_at(CameraSample::at(a, b), SampleId::single(a as u32, b as u32)));
            spd_mean(c[0], c[1], c[2], c[3])
        }
        // The render's sum: each sample weighted by 1/n, added in order.
        _ => {
            let sampler = *frame.sampler();
            let n = sampler.count();
            let weight = 1.0 / n as f32;
            let mut sum = Vec3::ZERO;
            for s in 0..n {
                let (sample, id) = sampler.sample(x, y, s);
                sum += trace_at(sample, id) * weight;
            }
            sum
        }
    };
    scene.decode_assets().map_err(RenderError::Asset)?;
    Ok(PixelTrace {
        x,
        y,
        opts: *opts,
        samples,
        lens: frame.camera().has_lens(),
        motion: scene.has_motion(),
        value,
        stats: ctx.stats,
        lights: scene.info().lights.iter().map(|l| l.position).collect(),
        dialect: scene.info().dialect,
    })
}

/// A vector with four decimals.
struct V(Vec3);

impl fmt::Display for V {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        // Adding 0 turns -0 into 0, which reads better.
        write!(
            f,
            "({:.4}, {:.4}, {:.4})",
            self.0.x + 0.0,
            self.0.y + 0.0,
            self.0.z + 0.0
        )
    }
}

/// A light point's outcome as printed.
struct Outcome<'a>(&'a LightOutcome);

impl fmt::Display for Outcome<'_> {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self.0 {
            LightOutcome::Behind => write!(f, "behind the surface (no shadow ray)"),
            LightOutcome::Shadowed => write!(f, "shadowed"),
            LightOutcome::Lit(c) => write!(f, "adds {}", V(*c)),
        }
    }
}

/// A secondary ray's weight: one number when its three channels agree.
struct Weight(Vec3);

impl fmt::Display for Weight {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let w = self.0;
        if w.x == w.y && w.y == w.z {
            write!(f, "{}", w.x)
        } else {
            write!(f, "{}", V(w))
        }
    }
}

/// The primitive kind as printed, with the keyword it has in the scene's language.
pub fn kind_name(k: SourceKind, dialect: Dialect) -> &'static str {
    match k {
        SourceKind::Sphere => "sphere (s)",
        SourceKind::MovingSphere => "moving sphere (sm)",
        SourceKind::Polygon => "polygon (p)",
        SourceKind::Patch => "patch (pp)",
        SourceKind::Cone => "cone (c)",
        SourceKind::Plane => "plane (pl)",
        SourceKind::Box if dialect.is_p3f() => "box (box)",
        SourceKind::Box => "box (aabb)",
        SourceKind::Mesh => "mesh triangle (mesh)",
    }
}

impl PixelTrace {
    fn write_node(&self, f: &mut fmt::Formatter<'_>, node: &RayNode, indent: usize) -> fmt::Result {
        let pad = "  ".repeat(indent);
        writeln!(f, "{pad}ray from {} dir {}", V(node.origin), V(node.dir))?;
        let Some(h) = &node.hit else {
            return match node.sky {
                Some(t) => writeln!(
                    f,
                    "{pad}miss: skybox face {}, texel ({}, {}) from its bottom-left: {}",
                    t.face.name(),
                    t.column,
                    t.row,
                    V(node.color)
                ),
                None => writeln!(f, "{pad}miss: background {}", V(node.color)),
            };
        };
        let side = if h.entering { "entering" } else { "leaving" };
        writeln!(
            f,
            "{pad}hit {} at line {}, t = {:.4}, {side}",
            kind_name(h.kind, self.dialect),
            h.line,
            h.t
        )?;
        if let Some(left) = h.absorbed {
            writeln!(
                f,
                "{pad}  inside glass for {:.4}: {} of the light left (Beer-Lambert)",
                h.t,
                V(left)
            )?;
        }
        writeln!(f, "{pad}  point {}  normal {}", V(h.point), V(h.normal))?;
        if h.shading_normal != h.normal {
            writeln!(f, "{pad}  shading normal {}", V(h.shading_normal))?;
        }
        let (mi, m) = &h.material;
        let specular = if self.dialect != crate::scene::Dialect::Nff {
            format!(" specular {}", V(m.specular))
        } else {
            String::new()
        };
        let mut extra = String::new();
        if m.roughness > 0.0 {
            extra += &format!(" roughness {}", m.roughness);
        }
        if m.emission != Vec3::ZERO {
            extra += &format!(" emission {}", V(m.emission));
        }
        writeln!(
            f,
            "{pad}  material #{mi}: colour {} Kd {}{specular} Ks {} shine {} T {} ior {}{extra}",
            V(m.color),
            m.kd,
            m.ks,
            m.shine,
            m.t,
            m.ior
        )?;
        writeln!(f, "{pad}  ambient {}", V(h.ambient))?;
        for (k, record) in h.lights.iter().enumerate() {
            let at = self.lights.get(k).map(|&p| V(p).to_string()).unwrap_or_default();
            match record {
                LightRecord::Point(outcome) => {
                    writeln!(f, "{pad}  light {} at {at}: {}", k + 1, Outcome(outcome))?
                }
                LightRecord::Area { points, outcome } => {
                    writeln!(
                        f,
                        "{pad}  area light {} at {at}: {}, {} lit, {} shadowed, {} behind: adds {}",
                        k + 1,
                        crate::words::count(outcome.samples, "point", "points"),
                        outcome.samples - outcome.shadowed - outcome.behind,
                        outcome.shadowed,
                        outcome.behind,
                        V(outcome.contribution)
                    )?;
                    for (p, o) in points {
                        writeln!(f, "{pad}    point {}: {}", V(*p), Outcome(o))?;
                    }
                }
            }
        }
        if h.children.is_empty() && (m.ks > 0.0 || m.t > 0.0) {
            writeln!(f, "{pad}  no secondary rays: depth {} is the limit", h.depth)?;
        }
        for (kind, w, child) in &h.children {
            let name = match kind {
                Branch::Reflection => "reflection",
                Branch::TotalInternalReflection => "reflection (total internal reflection)",
                Branch::Refraction => "refraction",
            };
            writeln!(f, "{pad}  {name}, weight {}:", Weight(*w))?;
            if let Some(smooth) = child.smooth_dir {
                let angle = smooth.dot(child.dir).clamp(-1.0, 1.0).acos().to_degrees();
                writeln!(
                    f,
                    "{pad}    rough: drawn {angle:.2} degrees from the smooth direction {}",
                    V(smooth)
                )?;
            }
            self.write_node(f, child, indent + 2)?;
        }
        writeln!(f, "{pad}  = colour {}", V(node.color))
    }
}

impl fmt::Display for PixelTrace {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        writeln!(
            f,
            "pixel ({}, {}) of {}x{}, sampling {}, max depth {}",
            self.x, self.y, self.opts.width, self.opts.height, self.opts.sampling, self.opts.max_depth
        )?;
        let n = self.samples.len();
        for (k, (sample, node)) in self.samples.iter().enumerate() {
            let (px, py) = sample.raster;
            let lens = if self.lens {
                let (u, v) = sample.lens;
                format!(", lens ({u}, {v})")
            } else {
                String::new()
            };
            let time = if self.motion {
                format!(", shutter fraction {}", sample.time)
            } else {
                String::new()
            };
            writeln!(
                f,
                "eye ray {} of {n} through raster ({px}, {py}){lens}{time}:",
                k + 1
            )?;
            match node {
                Traced::Tree(tree) => self.write_node(f, tree, 1)?,
                Traced::Path(steps) => write_path(
                    f,
                    steps,
                    "  ",
                    |k| kind_name(k, self.dialect),
                    |v| V(v).to_string(),
                )?,
            }
        }
        let v = self.value;
        writeln!(
            f,
            "pixel value {} -> 8-bit ({}, {}, {})",
            V(v),
            quantize(v.x),
            quantize(v.y),
            quantize(v.z)
        )?;
        let s = &self.stats;
        writeln!(
            f,
            "rays: {} eye, {} reflection, {} refraction, {} shadow ({} blocked)",
            s.eye_rays, s.reflection_rays, s.refraction_rays, s.shadow_rays, s.shadow_blocked
        )
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::load::Assets;
    use crate::prepare::prepare;

    /// Counts in a tree: (hits, reflection rays, refraction rays, shadow rays, blocked).
    fn tally(node: &RayNode, acc: &mut [u64; 5]) {
        let Some(h) = &node.hit else { return };
        acc[0] += 1;
        for record in &h.lights {
            let LightRecord::Point(o) = record else {
                panic!("the test scene has point lights only")
            };
            acc[3] += (*o != LightOutcome::Behind) as u64;
            acc[4] += (*o == LightOutcome::Shadowed) as u64;
        }
        for (kind, _, child) in &h.children {
            match kind {
                Branch::Refraction => acc[2] += 1,
                _ => acc[1] += 1,
            }
            tally(child, acc);
        }
    }

    /// The tree holds exactly the rays the tracer counted: every secondary ray, every
    /// shadow ray and every hit appears once, whatever the pixel.
    #[test]
    fn the_tree_accounts_for_every_ray() {
        let scene = crate::nff::parse(
            "b 0.1 0.1 0.1\nv from 0 -6 2 at 0 0 0.5 up 0 0 1 angle 50 hither 1 resolution 12 9\n\
             l -4 -4 6\nl 4 -2 5\nf 0.8 0.8 0.8 0.8 0.2 10 0 1\np 4 -5 -5 0 5 -5 0 5 5 0 -5 5 0\n\
             f 1 1 1 0.1 0.1 50 0.9 1.5\ns -0.8 0 1 0.8\nf 0.9 0.9 0.9 0.1 0.9 50 0 1\ns 1 0.8 1 0.7\n",
        )
        .unwrap();
        let scene = prepare(scene, &Assets::default());
        let opts = RenderOptions::from_view(scene.view());
        let mut refracted = 0;
        for y in 0..opts.height {
            for x in 0..opts.width {
                let t = trace_pixel(&scene, scene.view(), &opts, x, y).unwrap();
                let mut acc = [0; 5];
                let Traced::Tree(tree) = &t.samples[0].1 else {
                    panic!("Whitted traces trees")
                };
                tally(tree, &mut acc);
                let s = &t.stats;
                assert_eq!(acc[0], s.eye_hits + s.secondary_hits, "({x}, {y})");
                assert_eq!(acc[1], s.reflection_rays, "({x}, {y})");
                assert_eq!(acc[2], s.refraction_rays, "({x}, {y})");
                assert_eq!((acc[3], acc[4]), (s.shadow_rays, s.shadow_blocked), "({x}, {y})");
                assert_eq!(tree.color, t.value);
                refracted += s.refraction_rays;
            }
        }
        // The glass sphere is in view, so the check covered refraction too.
        assert!(refracted > 0);
    }

    /// The JSON form names each hit's primitive kind and line and each light's outcome.
    #[test]
    fn the_tree_serializes_with_kinds_lines_and_outcomes() {
        let scene = crate::nff::parse(
            "v from 0 0 10 at 0 0 0 up 0 1 0 angle 30 hither 1 resolution 3 3\nl 0 0 20\n\
             f 1 1 1 1 0 1 0 1\ns 0 0 0 1\n",
        )
        .unwrap();
        let scene = prepare(scene, &Assets::default());
        let t = trace_pixel(
            &scene,
            scene.view(),
            &RenderOptions::from_view(scene.view()),
            1,
            1,
        )
        .unwrap();
        let json = serde_json::to_value(&t).unwrap();
        let hit = &json["samples"][0][1]["hit"];
        assert_eq!(hit["kind"], "Sphere");
        assert_eq!(hit["line"], 4);
        assert!(
            hit["lights"][0]["Point"]["Lit"]["x"].as_f64().unwrap() > 0.0,
            "{hit}"
        );
        assert_eq!(json["value"]["x"].as_f64().unwrap(), t.value.x as f64);
    }
}
