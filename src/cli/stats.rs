//! The report of `nffrt render --stats` (text) and `--stats-json` (JSON): the
//! settings that shaped the render, its ray counts and its timings.
//!
//! The settings are listed once, in [`settings`]; both reports show every entry, so
//! an effect added later (a lens, area lights) is one more line there.

use serde::ser::{SerializeMap, Serializer};
use serde::Serialize;
use serde_json::{json, Value};

use nffrt::accel::QueryCounts;
use nffrt::image::Region;
use nffrt::options::{RenderOptions, Sampling};
use nffrt::prepare::RenderScene;
use nffrt::render::{Camera, Stage, StageStats, Stats};
use nffrt::scene::{Accel, Dialect, SceneInfo};
use nffrt::words::shortest_f64;

/// The settings of a render, in report order: `(JSON key, value)`; the text report
/// labels each with its key, underscores as spaces.
#[derive(Clone, Debug, Default)]
pub struct Settings(Vec<(&'static str, Value)>);

impl Settings {
    /// Adds a setting known only once the render is done (the encoding written, the
    /// denoiser used).
    pub fn push(&mut self, key: &'static str, value: Value) {
        self.0.push((key, value));
    }
}

impl Serialize for Settings {
    fn serialize<S: Serializer>(&self, s: S) -> Result<S::Ok, S::Error> {
        let mut map = s.serialize_map(Some(self.0.len()))?;
        for (key, value) in &self.0 {
            map.serialize_entry(key, value)?;
        }
        map.end()
    }
}

/// What shaped the render of `region` of `scene` with `opts` on `threads` threads:
/// the full image size, the region and its pixel count, the sampling and its samples
/// per pixel ([`Sampling::samples_per_pixel`]: 1 for `--spd`, whose corner rays each
/// pixel shares with its neighbours), the depth, and the effects in use: the lens
/// (aperture in pixels, 0 for a pinhole, and focal ratio, from the flags or the
/// scene), the area lights and how they are sampled, the skybox, the scene's
/// dialect and shading model.
pub fn settings(
    opts: &RenderOptions,
    region: &Region,
    threads: usize,
    scene: &SceneInfo,
    skybox: bool,
) -> Settings {
    let sampling = match opts.sampling {
        Sampling::PixelCenters => "centres",
        Sampling::Stratified { .. } => "stratified",
        Sampling::Independent { .. } => "independent",
        Sampling::SpdCorners => "spd-corners",
    };
    let spp = opts.sampling.samples_per_pixel();
    let area_lights = scene.area_lights();
    let light_sampling = match (area_lights, opts.soft_shadows, opts.light_samples) {
        (0, _, _) => "none".to_string(),
        (_, false, _) => "centre".to_string(),
        (_, true, Some(n)) => format!("{n}x{n} per hit"),
        (_, true, None) if spp > 1 => "one per sample, stratified".to_string(),
        (_, true, None) => "the lights' grids".to_string(),
    };
    let shading = match scene.dialect {
        Dialect::Nff => "nff",
        Dialect::Aff => "aff",
        Dialect::P3f2019 | Dialect::P3f2025 => "p3f",
    };
    Settings(vec![
        ("width", json!(opts.width)),
        ("height", json!(opts.height)),
        ("region", json!([region.x0, region.y0, region.x1, region.y1])),
        ("pixels", json!(region.area())),
        ("sampling", json!(sampling)),
        ("samples_per_pixel", json!(spp)),
        ("max_depth", json!(opts.max_depth)),
        ("threads", json!(threads)),
        // (JSON numbers are f64: each f32 as the decimal it prints as, `1.2`.)
        (
            "aperture",
            json!(shortest_f64(opts.aperture.unwrap_or(scene.view.aperture))),
        ),
        (
            "focal",
            json!(shortest_f64(opts.focal.unwrap_or(scene.view.focal))),
        ),
        ("area_lights", json!(area_lights)),
        ("light_sampling", json!(light_sampling)),
        ("skybox", json!(skybox)),
        ("dialect", json!(scene.dialect.name())),
        ("shading", json!(shading)),
    ])
}

/// The most camera rays [`accel_work`] traces.
const ACCEL_SAMPLE_SIDE: u32 = 64;

/// What the acceleration structure of a render is and how much work it does per ray.
#[derive(Clone, Debug, Serialize)]
pub struct AccelWork {
    /// `bvh`, `grid` or `none`.
    pub accel: Accel,
    /// The grid's cells along x, y and z (a grid only).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub grid_cells: Option<[usize; 3]>,
    /// The camera rays measured.
    pub measured_rays: usize,
    /// Per measured ray: wide BVH nodes or grid cells visited.
    pub nodes_per_ray: f64,
    /// Per measured ray: primitives tested.
    pub primitive_tests_per_ray: f64,
}

/// The structure `scene` renders with and its work per closest-hit query, measured
/// apart from the render (which counts nothing, for speed) on the camera rays through
/// the pixel centres of `region` in `opts`'s picture, at most
/// [`ACCEL_SAMPLE_SIDE`]² of them spread evenly over it.
pub fn accel_work(scene: &RenderScene, opts: &RenderOptions, region: &Region) -> AccelWork {
    let camera = Camera::new(scene.view(), opts);
    let pick = |from: u32, to: u32| {
        let n = (to - from).min(ACCEL_SAMPLE_SIDE);
        (0..n).map(move |k| from + ((to - from) as u64 * k as u64 / n as u64) as u32)
    };
    let mut counts = QueryCounts::default();
    let mut measured = 0usize;
    for y in pick(region.y0, region.y1) {
        for x in pick(region.x0, region.x1) {
            let ray = camera.ray_at(x as f32 + 0.5, y as f32 + 0.5);
            scene
                .accel()
                .closest_hit_counted(&ray, f32::INFINITY, &mut counts);
            measured += 1;
        }
    }
    let per_ray = |n: u64| n as f64 / measured.max(1) as f64;
    AccelWork {
        accel: scene.accel().kind(),
        grid_cells: scene.accel().grid().map(|g| g.cells()),
        measured_rays: measured,
        nodes_per_ray: per_ray(counts.nodes),
        primitive_tests_per_ray: per_ray(counts.prims),
    }
}

impl AccelWork {
    /// The structure in words: `bvh`, `none`, `grid 40x30x20`.
    pub fn structure(&self) -> String {
        match (self.accel, self.grid_cells) {
            (_, Some([x, y, z])) => format!("grid {x}x{y}x{z}"),
            (Accel::None, _) => "none".into(),
            _ => "bvh".into(),
        }
    }

    /// The work per measured ray in words.
    fn per_ray_text(&self) -> String {
        let visited = match self.accel {
            Accel::Bvh => format!("{:.1} nodes visited, ", self.nodes_per_ray),
            Accel::Grid => format!("{:.1} cells visited, ", self.nodes_per_ray),
            Accel::None => String::new(),
        };
        format!(
            "{visited}{:.1} primitive tests ({} rays through pixel centres)",
            self.primitive_tests_per_ray, self.measured_rays
        )
    }
}

/// Everything `--stats` and `--stats-json` report. The JSON keys: the settings', then
/// `primitives`, the ray counts of [`Stats`], `total_rays`, the timings in seconds and
/// `mrays_per_s` (all rays over the render time).
#[derive(Serialize)]
pub struct StatsReport {
    /// See [`settings`].
    #[serde(flatten)]
    pub settings: Settings,
    /// Primitives in the BVH (polygons counted as the triangles they are cut into).
    pub primitives: usize,
    /// The acceleration structure and its work per camera ray (measured when a
    /// report is asked for).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub accel: Option<AccelWork>,
    /// Ray counts.
    #[serde(flatten)]
    pub rays: Stats,
    /// All rays traced.
    pub total_rays: u64,
    /// Seconds spent loading: reading and parsing the scene, reading the files it names.
    pub load_s: f64,
    /// Of those, seconds spent parsing.
    pub parse_s: f64,
    /// Seconds spent building the BVH.
    pub build_s: f64,
    /// Seconds spent rendering.
    pub render_s: f64,
    /// Millions of rays per second of render time.
    pub mrays_per_s: f64,
    /// Seconds of CPU time spent decoding the skybox's faces (during the build and
    /// the render, on a thread of their own or by the rays that needed them).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub skybox_decode_s: Option<f64>,
    /// The path tracer's wavefront stages (see [`StagesReport`]).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub stages: Option<StagesReport>,
    /// Seconds of the AOV pass (`--aov`, `--denoise`), after the render.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub aov_s: Option<f64>,
    /// Seconds of the denoiser (`--denoise`), after the AOV pass.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub denoise_s: Option<f64>,
}

/// What the path tracer's wavefront stages did: per stage its items (rays for the
/// queries, vertices for shading), CPU seconds summed over the threads, and items
/// per CPU second; how many rounds; how full the eight-lane shading ran.
#[derive(Serialize)]
pub struct StagesReport {
    /// Per stage, in order.
    pub stages: Vec<StageReport>,
    /// Rounds of the wavefront, summed over its blocks.
    pub rounds: u64,
    /// Of the vertices shaded, the share shaded eight lanes at a time.
    pub lanes_share: f64,
    /// Of the lanes of the eight-lane calls, the share filled.
    pub lanes_full: f64,
}

/// One stage of [`StagesReport`].
#[derive(Serialize)]
pub struct StageReport {
    /// `camera`, `arrive`, `light`, `shadows`, `bounce` or `extend`.
    pub stage: &'static str,
    /// Rays or vertices through it.
    pub items: u64,
    /// CPU seconds, summed over the threads.
    pub cpu_s: f64,
    /// Millions of items per CPU second.
    pub m_per_s: f64,
}

impl StagesReport {
    /// The report of `s`, or `None` if no stage ran.
    pub fn of(s: &StageStats) -> Option<StagesReport> {
        if s.is_empty() {
            return None;
        }
        let stages = Stage::ALL
            .iter()
            .map(|&stage| {
                let (items, nanos) = s.stages[stage as usize];
                let cpu_s = nanos as f64 * 1e-9;
                StageReport {
                    stage: stage.name(),
                    items,
                    cpu_s,
                    m_per_s: items as f64 / cpu_s.max(1e-12) / 1e6,
                }
            })
            .collect();
        let shaded = s.stages[Stage::Bounce as usize].0;
        Some(StagesReport {
            stages,
            rounds: s.rounds,
            lanes_share: s.lanes_filled as f64 / shaded.max(1) as f64,
            lanes_full: s.lanes_filled as f64 / (8 * s.lane_calls).max(1) as f64,
        })
    }

    fn lines(&self) -> Vec<String> {
        let total: f64 = self.stages.iter().map(|s| s.cpu_s).sum();
        let mut lines = vec![line(
            "wavefront",
            &format!(
                "{} rounds; {:.0} % of the vertices shaded in lanes, lanes {:.0} % full",
                self.rounds,
                100.0 * self.lanes_share,
                100.0 * self.lanes_full
            ),
        )];
        for s in &self.stages {
            lines.push(line(
                &format!("  {}", s.stage),
                &format!(
                    "{} {}, {:.3} s CPU ({:.0} %), {:.2} M/s",
                    s.items,
                    if matches!(s.stage, "arrive" | "light" | "bounce") {
                        "vertices"
                    } else {
                        "rays"
                    },
                    s.cpu_s,
                    100.0 * s.cpu_s / total.max(1e-12),
                    s.m_per_s
                ),
            ));
        }
        lines
    }
}

impl StatsReport {
    /// The report of a render that traced `rays` in `render_s` seconds.
    pub fn new(
        settings: Settings,
        primitives: usize,
        accel: Option<AccelWork>,
        rays: Stats,
        times: [f64; 4],
    ) -> Self {
        let [load_s, parse_s, build_s, render_s] = times;
        StatsReport {
            settings,
            primitives,
            accel,
            rays,
            total_rays: rays.total_rays(),
            load_s,
            parse_s,
            build_s,
            render_s,
            mrays_per_s: rays.total_rays() as f64 / render_s.max(1e-9) / 1e6,
            skybox_decode_s: None,
            stages: None,
            aov_s: None,
            denoise_s: None,
        }
    }

    /// The `--stats-json` text.
    pub fn json(&self) -> String {
        serde_json::to_string_pretty(self).expect("plain data serializes")
    }

    /// The `--stats` text, one line per item.
    pub fn text(&self) -> String {
        let s = &self.rays;
        let mut lines: Vec<String> = self
            .settings
            .0
            .iter()
            .map(|(key, value)| line(&key.replace('_', " "), &value_text(value)))
            .collect();
        lines.extend([line("primitives", &self.primitives.to_string())]);
        if let Some(a) = &self.accel {
            lines.extend([
                line("accel", &a.structure()),
                line("per camera ray", &a.per_ray_text()),
            ]);
        }
        lines.extend([
            line("eye rays", &format!("{} ({} hit)", s.eye_rays, s.eye_hits)),
            line("reflection rays", &s.reflection_rays.to_string()),
            line("refraction rays", &s.refraction_rays.to_string()),
            line(
                "shadow rays",
                &format!("{} ({} blocked)", s.shadow_rays, s.shadow_blocked),
            ),
            line("total rays", &self.total_rays.to_string()),
            line(
                "load/build/render",
                &format!(
                    "{:.3} / {:.3} / {:.3} s (parse {:.3} s)",
                    self.load_s, self.build_s, self.render_s, self.parse_s
                ),
            ),
            line("speed", &format!("{:.2} Mrays/s", self.mrays_per_s)),
        ]);
        if let Some(seconds) = self.aov_s {
            lines.push(line("aov pass", &format!("{seconds:.3} s")));
        }
        if let Some(seconds) = self.denoise_s {
            lines.push(line("denoiser", &format!("{seconds:.3} s")));
        }
        if let Some(seconds) = self.skybox_decode_s {
            lines.push(line(
                "skybox decode",
                &format!("{seconds:.3} s of CPU during the build and render"),
            ));
        }
        if let Some(stages) = &self.stages {
            lines.extend(stages.lines());
        }
        lines.join("\n")
    }
}

fn line(label: &str, value: &str) -> String {
    format!("{label:<18} {value}")
}

/// A JSON value as the text report shows it: strings bare, arrays comma-separated.
fn value_text(v: &Value) -> String {
    match v {
        Value::String(s) => s.clone(),
        Value::Null => "none".into(),
        Value::Array(items) => items.iter().map(value_text).collect::<Vec<_>>().join(","),
        other => other.to_string(),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn both_reports_show_every_setting() {
        let opts = RenderOptions {
            width: 9,
            height: 9,
            sampling: Sampling::Stratified { spp: 4 },
            focal: Some(1.2),
            ..RenderOptions::default()
        };
        let region = Region::parse("0,0,5,5").unwrap();
        let rays = Stats {
            eye_rays: 100,
            ..Stats::default()
        };
        let accel = AccelWork {
            accel: Accel::Grid,
            grid_cells: Some([4, 5, 6]),
            measured_rays: 16,
            nodes_per_ray: 2.5,
            primitive_tests_per_ray: 3.25,
        };
        let report = StatsReport::new(
            settings(&opts, &region, 2, &nffrt::Scene::default().info(), false),
            1,
            Some(accel),
            rays,
            [0.0, 0.0, 0.0, 1.0],
        );
        let text = report.text();
        for want in [
            "region             0,0,5,5",
            "pixels             25",
            "sampling           stratified",
            "samples per pixel  4",
            "eye rays           100 (0 hit)",
            "accel              grid 4x5x6",
            "per camera ray     2.5 cells visited, 3.2 primitive tests (16 rays",
        ] {
            assert!(text.contains(want), "{want:?} in\n{text}");
        }
        let json: Value = serde_json::from_str(&report.json()).unwrap();
        assert_eq!(json["region"], json!([0, 0, 5, 5]));
        // f32 settings as the decimals they were given in, not their f64 expansion.
        assert_eq!(json["focal"], json!(1.2));
        assert!(report.json().contains(r#""focal": 1.2,"#), "{}", report.json());
        assert!(text.contains("focal              1.2\n"), "{text}");
        assert_eq!(json["samples_per_pixel"], 4);
        assert_eq!(json["eye_rays"], 100);
        assert_eq!(json["total_rays"], 100);
        assert_eq!(json["accel"]["accel"], "grid");
        assert_eq!(json["accel"]["grid_cells"], json!([4, 5, 6]));
    }
}
