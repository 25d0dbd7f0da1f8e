//! The report of `nffrt render --stats` (text) and `--stats-json` (JSON): the
//! settings that shaped the render, its ray counts and its timings.
//!
//! The settings are listed once, in [`settings`]; both reports show every entry, so
//! an effect added later (a lens, area lights) is one more line there.

use serde::ser::{SerializeMap, Serializer};
use serde::Serialize;
use serde_json::{json, Value};

use nffrt::image::Region;
use nffrt::render::{RenderOptions, Sampling, Stats};
use nffrt::scene::SceneInfo;
use nffrt::words::shortest_f64;

/// The settings of a render, in report order: `(JSON key, value)`; the text report
/// labels each with its key, underscores as spaces.
#[derive(Clone, Debug, Default)]
pub struct Settings(Vec<(&'static str, Value)>);

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
    let shading = if scene.dialect.is_p3f() { "p3f" } else { "nff" };
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
}

impl StatsReport {
    /// The report of a render that traced `rays` in `render_s` seconds.
    pub fn new(settings: Settings, primitives: usize, rays: Stats, times: [f64; 4]) -> Self {
        let [load_s, parse_s, build_s, render_s] = times;
        StatsReport {
            settings,
            primitives,
            rays,
            total_rays: rays.total_rays(),
            load_s,
            parse_s,
            build_s,
            render_s,
            mrays_per_s: rays.total_rays() as f64 / render_s.max(1e-9) / 1e6,
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
        lines.extend([
            line("primitives", &self.primitives.to_string()),
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
        let report = StatsReport::new(
            settings(&opts, &region, 2, &nffrt::Scene::default().info(), false),
            1,
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
    }
}
