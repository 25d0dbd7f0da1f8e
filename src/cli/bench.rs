//! `nffrt bench`: times the acceleration structure alone (no shading) on primary,
//! random and file-supplied rays, for comparison with other ray tracing kernels; with
//! `--accel all`, the BVH, the uniform grid and the scan of every primitive side by
//! side, with the work each does per ray.

use std::path::PathBuf;
use std::time::Instant;

use clap::Args;
use rayon::prelude::*;

use super::limits::RenderLimitArgs;
use super::load::{load_scene, Need};
use super::output::brief;
use super::render::render_error;
use super::values::{self, whole_number};
use super::CliError;
use nffrt::accel::{Aggregate, Bvh, Coherence, QueryCounts, Ray8, PACKET};
use nffrt::image::Region;
use nffrt::limits::MAX_THREADS;
use nffrt::load::Loaded;
use nffrt::math::{Ray, Vec3};
use nffrt::options::{RenderOptions, RenderRequest};
use nffrt::prepare::{prepare_with, scene_geometry, PrepareOptions};
use nffrt::render::{render, Camera};
use nffrt::scene::{Accel, IntegratorKind};
use nffrt::words::count;

/// Arguments of `nffrt bench`.
#[derive(Args, Debug)]
#[command(mut_arg("max_pixels", |a| a.help(
    "Refuse more than N primary rays (the scene's width x height) or --random rays"
)))]
pub struct BenchArgs {
    /// Scene file, NFF, P3F or AFF (by its extension or --format); `-` reads standard input.
    pub scene: PathBuf,
    /// Also trace the rays in FILE: raw little-endian float32 rows `ox oy oz dx dy dz`,
    /// 24 bytes a ray (BENCHMARKS.md shows how to dump another tracer's rays).
    #[arg(long, value_name = "FILE")]
    pub rays: Option<PathBuf>,
    #[arg(long, value_name = "N", default_value_t = 1, allow_negative_numbers = true,
          help = format!("Worker threads for the timed queries, 1 to {MAX_THREADS}"),
          value_parser = whole_number::<u32>(1, MAX_THREADS as u64))]
    pub threads: u32,
    /// Timed passes per query, 1 to 1000; the median is reported (and the best, as
    /// `*_best_*`).
    #[arg(long, value_name = "N", default_value_t = 5, allow_negative_numbers = true,
          value_parser = whole_number::<u32>(1, 1000))]
    pub repeat: u32,
    /// Random rays to trace (default: width x height of the scene).
    #[arg(long, value_name = "N", allow_negative_numbers = true,
          value_parser = whole_number::<usize>(0, u64::MAX))]
    pub random: Option<usize>,
    /// With `--rays`: trace only the file's rays (skip the primary and random sets).
    #[arg(long, requires = "rays")]
    pub rays_only: bool,
    /// Seed of the random ray set (the same seed, the same rays).
    #[arg(long, value_name = "N", default_value_t = 1, allow_negative_numbers = true,
          value_parser = whole_number::<u64>(0, u64::MAX))]
    pub seed: u64,
    /// The acceleration structure to time: `bvh` (with packets), `grid`, `none` (every
    /// primitive tested for every ray: slow on big scenes, try a small --random) or
    /// `all` (the three side by side, with nodes or cells visited and primitives tested
    /// per ray).
    #[arg(long, value_enum, value_name = "NAME", default_value = "bvh")]
    pub accel: BenchAccel,
    /// Also time whole renders of the scene (shading included) with this light
    /// transport, `whitted` or `path`, at the file's size and samples (path tracing's
    /// default without them: 16), on --threads threads; with the first structure of
    /// --accel.
    #[arg(long, value_name = "NAME", value_parser = values::integrator())]
    pub integrator: Option<IntegratorKind>,
    /// Resource limits (see "Limits" in docs/command-line.md); the primary and random ray sets
    /// count as pixels.
    #[command(flatten)]
    pub limits: RenderLimitArgs,
}

/// The values of `nffrt bench --accel`.
#[derive(clap::ValueEnum, Clone, Copy, Debug, PartialEq, Eq)]
pub enum BenchAccel {
    /// Every primitive tested for every ray.
    None,
    /// A uniform grid.
    Grid,
    /// The bounding volume hierarchy.
    Bvh,
    /// The three, side by side.
    All,
}

impl BenchAccel {
    /// The structures to time, in the order they are printed.
    fn structures(self) -> Vec<Accel> {
        match self {
            BenchAccel::None => vec![Accel::None],
            BenchAccel::Grid => vec![Accel::Grid],
            BenchAccel::Bvh => vec![Accel::Bvh],
            BenchAccel::All => vec![Accel::Bvh, Accel::Grid, Accel::None],
        }
    }
}

/// The most rays of a set whose work per ray is counted.
const COUNTED_RAYS: usize = 4096;

/// One row of the side-by-side table.
struct Row {
    structure: String,
    set: &'static str,
    closest_mrays: f64,
    occlusion_mrays: f64,
    per_ray: (f64, f64),
}

/// Median and best timing of one query over one ray set.
struct Timing {
    hits: usize,
    median_mrays: f64,
    best_mrays: f64,
}

/// Runs `nffrt bench`.
pub fn run(args: BenchArgs) -> Result<(), CliError> {
    // The rays file first: a bad one is reported before anything is built or printed.
    let file_rays = args.rays.as_ref().map(read_rays).transpose()?;
    let need = if args.integrator.is_some() {
        Need::Render
    } else {
        Need::Summary
    };
    let loaded = load_scene(&args.scene, &args.limits.scene, need)?;
    let scene = &loaded.scene;
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(args.threads as usize)
        .build()
        .map_err(|e| CliError::io(format!("cannot start threads: {e}")))?;

    // Whole builds (the scene's conversion to primitives, instances' prototypes
    // built, then `Bvh::new`), and `Bvh::new` alone: the part a peer given
    // triangles in its buffers also does.
    let (mut builds, mut bvh_builds) = (Vec::new(), Vec::new());
    let mut bvh = None;
    for _ in 0..args.repeat.max(3) {
        let t0 = Instant::now();
        let b = pool.install(|| {
            let geometry = scene_geometry(scene);
            let t1 = Instant::now();
            let b = Bvh::new(geometry);
            bvh_builds.push(t1.elapsed().as_secs_f64() * 1e3);
            b
        });
        builds.push(t0.elapsed().as_secs_f64() * 1e3);
        bvh = Some(b);
    }
    let bvh = bvh.expect("at least one build");
    let build_best_ms = builds.iter().cloned().fold(f64::INFINITY, f64::min);
    let bvh_best_ms = bvh_builds.iter().cloned().fold(f64::INFINITY, f64::min);
    let build_ms = median(&mut builds);
    let st = bvh.stats();
    outln!(
        "{}: {}, build {:.2} ms (median), {}, depth {}, leaves {:.2} prims avg, SAH cost {:.2}",
        loaded.name,
        count(st.primitives, "primitive", "primitives"),
        build_ms,
        count(st.nodes, "node", "nodes"),
        st.depth,
        st.mean_leaf,
        st.sah_cost
    );

    let (w, h) = (scene.view.width, scene.view.height);
    let primary_opts = RenderOptions::from_view(&scene.view);
    args.limits.check(&primary_opts, &Region::full(w, h), false)?;
    let n_random = args.random.unwrap_or((w * h) as usize);
    if n_random as u64 > args.limits.max_pixels {
        return Err(CliError::usage(format!(
            "--random {n_random} is more than the limit of {} rays (--max-pixels raises it)",
            args.limits.max_pixels
        )));
    }
    let camera = Camera::new(&scene.view, &primary_opts);
    let primary: Vec<Ray> = (0..h)
        .flat_map(|j| (0..w).map(move |i| (i, j)))
        .map(|(i, j)| camera.ray_at(i as f32 + 0.5, j as f32 + 0.5))
        .collect();
    let random = random_rays(&bvh, n_random, args.seed);

    let mut summary = vec![
        format!("build_ms={build_ms:.3}"),
        format!("build_best_ms={build_best_ms:.3}"),
        format!("bvh_best_ms={bvh_best_ms:.3}"),
        format!("sah_cost={:.3}", st.sah_cost),
        format!("kernels={}", bvh.kernels().name()),
    ];
    let mut sets = if args.rays_only {
        Vec::new()
    } else {
        vec![("primary", primary), ("random", random)]
    };
    if let Some(rays) = file_rays {
        sets.push(("rays", rays));
    }
    let mut rows = Vec::new();
    for kind in args.accel.structures() {
        let t0 = Instant::now();
        let structure = Aggregate::new(bvh.clone(), kind);
        let extra_build_ms = t0.elapsed().as_secs_f64() * 1e3;
        let label = match structure.grid() {
            Some(g) => {
                let [x, y, z] = g.cells();
                format!("grid {x}x{y}x{z}")
            }
            None => structure_name(kind).to_string(),
        };
        if kind != Accel::Bvh {
            outln!("{label}: built in {extra_build_ms:.2} ms more (over the BVH's primitive order)");
        }
        for (name, rays) in &sets {
            let row = time_structure(&pool, &structure, &label, name, rays, args.repeat, &mut summary)?;
            rows.push(row);
        }
    }
    if rows.len() > 3 || args.accel == BenchAccel::All {
        print_table(&rows);
    }
    if let Some(integrator) = args.integrator {
        let accel = args.accel.structures()[0];
        time_renders(&pool, &loaded, integrator, accel, args.repeat, &mut summary)?;
    }
    summary.push(format!("threads={}", args.threads));
    outln!("{}", summary.join(" "));
    Ok(())
}

/// Times closest-hit and occlusion queries of `structure` on `rays` (and packets, for
/// the BVH), prints them, counts the work per ray, and adds the figures to `summary`
/// (the BVH's keys unprefixed, as before the other structures existed).
fn time_structure(
    pool: &rayon::ThreadPool,
    structure: &Aggregate,
    label: &str,
    name: &'static str,
    rays: &[Ray],
    repeat: u32,
    summary: &mut Vec<String>,
) -> Result<Row, CliError> {
    let kind = structure.kind();
    #[cfg(feature = "counters")]
    if kind == Accel::Bvh {
        print_counts(structure.bvh(), name, rays);
    }
    let per_ray = counted(structure, rays);
    let closest = time_query(pool, rays, repeat, |r| {
        structure.closest_hit(r, f32::INFINITY).is_some()
    });
    let occl = time_query(pool, rays, repeat, |r| structure.occluded(r, f32::INFINITY));
    let prefix = if kind == Accel::Bvh {
        String::new()
    } else {
        format!("{}_", structure_name(kind))
    };
    outln!(
        "{name:>8}: {}{}, {}; closest hit {:.2} Mrays/s (best {:.2}); occlusion {:.2} Mrays/s (best {:.2}), {} occluded",
        if kind == Accel::Bvh { String::new() } else { format!("{label}, ") },
        count(rays.len(), "ray", "rays"),
        count(closest.hits, "hit", "hits"),
        closest.median_mrays,
        closest.best_mrays,
        occl.median_mrays,
        occl.best_mrays,
        occl.hits
    );
    summary.push(format!("{prefix}{name}_mrays={:.3}", closest.median_mrays));
    summary.push(format!("{prefix}{name}_occl_mrays={:.3}", occl.median_mrays));
    summary.push(format!("{prefix}{name}_best_mrays={:.3}", closest.best_mrays));
    summary.push(format!("{prefix}{name}_occl_best_mrays={:.3}", occl.best_mrays));
    if kind == Accel::Bvh {
        for coherence in [Coherence::Coherent, Coherence::Mixed] {
            let (walk, key) = match coherence {
                Coherence::Coherent => ("coherent walk", "packet"),
                Coherence::Mixed => ("mixed walk", "mixed_packet"),
            };
            let packets = time_packets(pool, rays, repeat, structure.bvh(), coherence);
            let blocked = time_packets_occlusion(pool, rays, repeat, structure.bvh(), coherence);
            outln!(
                "{:>8}  packets of {PACKET} consecutive rays, {walk}: closest hit {:.2} Mrays/s (best {:.2}), {}; \
                 occlusion {:.2} Mrays/s (best {:.2})",
                "",
                packets.median_mrays,
                packets.best_mrays,
                count(packets.hits, "hit", "hits"),
                blocked.median_mrays,
                blocked.best_mrays,
            );
            if packets.hits != closest.hits || blocked.hits != occl.hits {
                return Err(CliError::io(format!(
                    "{name} rays: packets ({walk}) found {} hits and {} blockers, single rays {} and {}: \
                     a traversal bug",
                    packets.hits, blocked.hits, closest.hits, occl.hits
                )));
            }
            summary.push(format!("{name}_{key}_mrays={:.3}", packets.median_mrays));
            summary.push(format!("{name}_{key}_occl_mrays={:.3}", blocked.median_mrays));
        }
    }
    summary.push(format!("{prefix}{name}_hits={}", closest.hits));
    Ok(Row {
        structure: label.to_string(),
        set: name,
        closest_mrays: closest.median_mrays,
        occlusion_mrays: occl.median_mrays,
        per_ray,
    })
}

/// Times `repeat` whole renders of `loaded` with `integrator` (after one untimed) and
/// prints the median's time, samples per second and rays per second.
fn time_renders(
    pool: &rayon::ThreadPool,
    loaded: &Loaded,
    integrator: IntegratorKind,
    accel: Accel,
    repeat: u32,
    summary: &mut Vec<String>,
) -> Result<(), CliError> {
    let info = loaded.scene.info();
    let request = RenderRequest {
        integrator: Some(integrator),
        ..RenderRequest::default()
    };
    let opts = request.resolve(&info).map_err(CliError::usage)?.opts;
    let prepare = PrepareOptions {
        accel: Some(accel),
        ..PrepareOptions::default()
    };
    let scene = pool.install(|| prepare_with(loaded.scene.clone(), &loaded.assets, &prepare));
    let render = || {
        pool.install(|| render(&scene, scene.view(), &opts))
            .map_err(|e| render_error(e, false))
    };
    let (_, stats) = render()?;
    let mut seconds = Vec::new();
    for _ in 0..repeat {
        let t0 = Instant::now();
        render()?;
        seconds.push(t0.elapsed().as_secs_f64());
    }
    let s = median(&mut seconds);
    let samples = opts.width as f64 * opts.height as f64 * opts.sampling.samples_per_pixel() as f64;
    let name = integrator.name();
    outln!(
        "  render: {name}, {}x{}, {}, max depth {}: {s:.3} s (median of {repeat}), {:.2} M samples/s, {:.2} Mrays/s",
        opts.width,
        opts.height,
        opts.sampling,
        opts.max_depth,
        samples / s / 1e6,
        stats.total_rays() as f64 / s / 1e6
    );
    summary.push(format!("render_{name}_s={s:.4}"));
    summary.push(format!(
        "render_{name}_mrays={:.3}",
        stats.total_rays() as f64 / s / 1e6
    ));
    Ok(())
}

/// Nodes or cells visited and primitives tested per closest-hit query, over at most
/// [`COUNTED_RAYS`] rays spread evenly over `rays`.
fn counted(structure: &Aggregate, rays: &[Ray]) -> (f64, f64) {
    let step = rays.len().div_ceil(COUNTED_RAYS).max(1);
    let mut counts = QueryCounts::default();
    let mut n = 0;
    for r in rays.iter().step_by(step) {
        structure.closest_hit_counted(r, f32::INFINITY, &mut counts);
        n += 1;
    }
    let n = n.max(1) as f64;
    (counts.nodes as f64 / n, counts.prims as f64 / n)
}

/// The structures side by side.
fn print_table(rows: &[Row]) {
    outln!(
        "{:<16} {:>8} {:>16} {:>18} {:>15} {:>15}",
        "structure",
        "rays",
        "closest Mrays/s",
        "occlusion Mrays/s",
        "nodes|cells/ray",
        "prim tests/ray"
    );
    for r in rows {
        outln!(
            "{:<16} {:>8} {:>16.2} {:>18.2} {:>15.1} {:>15.1}",
            r.structure,
            r.set,
            r.closest_mrays,
            r.occlusion_mrays,
            r.per_ray.0,
            r.per_ray.1
        );
    }
}

fn structure_name(kind: Accel) -> &'static str {
    match kind {
        Accel::None => "none",
        Accel::Grid => "grid",
        Accel::Bvh => "bvh",
    }
}

fn median(v: &mut [f64]) -> f64 {
    v.sort_by(f64::total_cmp);
    let n = v.len();
    if n % 2 == 1 {
        v[n / 2]
    } else {
        0.5 * (v[n / 2 - 1] + v[n / 2])
    }
}

/// Traces every ray once to warm up, then `repeat` timed passes.
fn time_query(
    pool: &rayon::ThreadPool,
    rays: &[Ray],
    repeat: u32,
    query: impl Fn(&Ray) -> bool + Sync,
) -> Timing {
    let pass = || -> usize {
        pool.install(|| {
            rays.par_chunks(4096)
                .map(|c| c.iter().filter(|r| query(r)).count())
                .sum::<usize>()
        })
    };
    time_passes(rays.len(), repeat, pass)
}

/// [`time_query`] for closest hits traced [`PACKET`] consecutive rays at a time,
/// with the walk `coherence` names.
fn time_packets(
    pool: &rayon::ThreadPool,
    rays: &[Ray],
    repeat: u32,
    bvh: &Bvh,
    coherence: Coherence,
) -> Timing {
    time_packet_passes(pool, rays, repeat, |packet| {
        let mut out = [None; PACKET];
        let active = (1 << packet.len()) - 1;
        bvh.closest_hits8(&Ray8::new(packet), f32::INFINITY, active, coherence, &mut out);
        out.iter().filter(|h| h.is_some()).count()
    })
}

/// [`time_packets`] for occlusion queries.
fn time_packets_occlusion(
    pool: &rayon::ThreadPool,
    rays: &[Ray],
    repeat: u32,
    bvh: &Bvh,
    coherence: Coherence,
) -> Timing {
    time_packet_passes(pool, rays, repeat, |packet| {
        let active = (1 << packet.len()) - 1;
        let limits = [f32::INFINITY; PACKET];
        bvh.occluded8(&Ray8::new(packet), &limits, active, coherence)
            .count_ones() as usize
    })
}

/// Passes over `rays` [`PACKET`] consecutive rays at a time, `query` giving each
/// packet's hits, timed as [`time_passes`] times them.
fn time_packet_passes(
    pool: &rayon::ThreadPool,
    rays: &[Ray],
    repeat: u32,
    query: impl Fn(&[Ray]) -> usize + Sync,
) -> Timing {
    let pass = || -> usize {
        pool.install(|| {
            rays.par_chunks(4096)
                .map(|c| c.chunks(PACKET).map(&query).sum::<usize>())
                .sum::<usize>()
        })
    };
    time_passes(rays.len(), repeat, pass)
}

/// Runs `pass` (tracing `n_rays` rays, returning the hits) once to warm up, then
/// `repeat` timed times.
fn time_passes(n_rays: usize, repeat: u32, pass: impl Fn() -> usize) -> Timing {
    let rays = n_rays;
    let hits = pass();
    let mut rates: Vec<f64> = (0..repeat)
        .map(|_| {
            let t0 = Instant::now();
            let n = pass();
            debug_assert_eq!(n, hits);
            rays as f64 / t0.elapsed().as_secs_f64() / 1e6
        })
        .collect();
    let best = rates.iter().cloned().fold(0.0, f64::max);
    Timing {
        hits,
        median_mrays: median(&mut rates),
        best_mrays: best,
    }
}

/// Origins uniform in the scene's bounds, directions uniform on the sphere
/// (a fixed-seed SplitMix64 stream, so every run traces the same rays).
fn random_rays(bvh: &Bvh, n: usize, seed: u64) -> Vec<Ray> {
    let (lo, hi) = bvh.bounds().unwrap_or((Vec3::splat(-1.0), Vec3::ONE));
    let mut state = seed;
    let mut next = move || {
        state = state.wrapping_add(0x9E37_79B9_7F4A_7C15);
        let mut z = state;
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        ((z ^ (z >> 31)) >> 40) as f32 / (1u64 << 24) as f32
    };
    (0..n)
        .map(|_| {
            let o = Vec3::new(
                lo.x + (hi.x - lo.x) * next(),
                lo.y + (hi.y - lo.y) * next(),
                lo.z + (hi.z - lo.z) * next(),
            );
            // Uniform on the sphere: z uniform in [-1, 1], azimuth uniform.
            let z = 2.0 * next() - 1.0;
            let phi = std::f32::consts::TAU * next();
            let r = (1.0 - z * z).max(0.0).sqrt();
            Ray::new(o, Vec3::new(r * phi.cos(), r * phi.sin(), z))
        })
        .collect()
}

/// Reads raw little-endian float32 rays, six floats each.
fn read_rays(path: &PathBuf) -> Result<Vec<Ray>, CliError> {
    let bytes = std::fs::read(path)
        .map_err(|e| CliError::io(format!("{}: cannot read rays: {}", path.display(), brief(&e))))?;
    if bytes.is_empty() {
        return Err(CliError::scene(format!(
            "{}: no rays in the file",
            path.display()
        )));
    }
    if bytes.len() % 24 != 0 {
        return Err(CliError::scene(format!(
            "{}: {} bytes is not a whole number of 24-byte rays",
            path.display(),
            bytes.len()
        )));
    }
    let f = |c: &[u8], i: usize| f32::from_le_bytes([c[4 * i], c[4 * i + 1], c[4 * i + 2], c[4 * i + 3]]);
    bytes
        .chunks_exact(24)
        .enumerate()
        .map(|(k, c)| {
            let o = Vec3::new(f(c, 0), f(c, 1), f(c, 2));
            let d = Vec3::new(f(c, 3), f(c, 4), f(c, 5));
            if !(o.is_finite() && d.is_finite()) || d.length_squared() == 0.0 {
                return Err(CliError::scene(format!(
                    "{}: ray {k} is not finite or has no direction",
                    path.display()
                )));
            }
            Ok(Ray::new(o, d))
        })
        .collect()
}

/// Prints wide nodes visited and primitives tested per ray (feature `counters`).
#[cfg(feature = "counters")]
fn print_counts(bvh: &Bvh, name: &str, rays: &[Ray]) {
    use nffrt::accel::counters::{NODES, PRIMS};
    use std::sync::atomic::Ordering::Relaxed;
    let per_ray = |f: &dyn Fn(&Ray) -> bool| {
        NODES.store(0, Relaxed);
        PRIMS.store(0, Relaxed);
        for r in rays {
            f(r);
        }
        let n = rays.len() as f64;
        (NODES.load(Relaxed) as f64 / n, PRIMS.load(Relaxed) as f64 / n)
    };
    let (cn, cp) = per_ray(&|r| bvh.closest_hit(r, f32::INFINITY).is_some());
    let (on, op) = per_ray(&|r| bvh.occluded(r, f32::INFINITY));
    outln!("{name:>8}: per ray: closest {cn:.1} nodes {cp:.1} prims; occlusion {on:.1} nodes {op:.1} prims");
}
