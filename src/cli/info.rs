//! `nffrt info`: a human or JSON summary of a scene.

use std::path::PathBuf;

use clap::Args;
use serde::Serialize;

use super::limits::SceneLimitArgs;
use super::{load::load_scene_with, load::print_warnings, CliError};

/// Arguments of `nffrt info`.
#[derive(Args, Debug)]
pub struct InfoArgs {
    /// Scene file (NFF); `-` reads standard input.
    pub scene: PathBuf,
    /// Print one JSON object instead of the human summary.
    #[arg(long)]
    pub json: bool,
    /// Resource limits.
    #[command(flatten)]
    pub limits: SceneLimitArgs,
}

#[derive(Serialize)]
struct InfoJson {
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
}

/// Runs `nffrt info`.
pub fn run(args: InfoArgs) -> Result<(), CliError> {
    let loaded = load_scene_with(&args.scene, &args.limits)?;
    let s = &loaded.scene;
    let b = s.bounds();
    let bounds = (!b.is_empty()).then_some((b.min.to_array(), b.max.to_array()));
    if args.json {
        let j = InfoJson {
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
        };
        println!("{}", serde_json::to_string(&j).expect("plain data serializes"));
        return Ok(());
    }
    let v = &s.view;
    println!("scene       {}", loaded.name);
    println!("resolution  {} x {}", v.width, v.height);
    println!(
        "camera      from {} {} {}  at {} {} {}  up {} {} {}  angle {}",
        v.from.x, v.from.y, v.from.z, v.at.x, v.at.y, v.at.z, v.up.x, v.up.y, v.up.z, v.angle
    );
    println!("lights      {}", s.lights.len());
    println!("materials   {}", s.materials.len());
    println!("primitives  {}", s.primitive_count());
    for (name, n) in [
        ("spheres", s.spheres.len()),
        ("polygons", s.polygons.len()),
        ("patches", s.patches.len()),
        ("cones", s.cones.len()),
        ("planes", s.planes.len()),
        ("boxes", s.boxes.len()),
    ] {
        if n > 0 {
            println!("  {name:<10}{n}");
        }
    }
    match bounds {
        Some((lo, hi)) => println!("bounds      {lo:?} .. {hi:?}"),
        None => println!("bounds      (no bounded primitive)"),
    }
    println!("parse time  {:.1} ms", loaded.parse_s * 1e3);
    println!("warnings    {}", s.warnings.len());
    print_warnings(&loaded, 20);
    Ok(())
}
