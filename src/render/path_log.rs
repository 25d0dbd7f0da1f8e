//! `--pixel` for the path tracer: one path's events as they happened (its vertices,
//! the light sample and the BSDF sample at each, their MIS weights and the
//! throughput), printed one line per fact and serialized for `nffrt view`.

use std::fmt;

use super::integrator::PathEvent;
use crate::geometry::SourceKind;
use crate::math::Vec3;

/// One event of a path, as kept.
#[derive(Clone, Debug, PartialEq, serde::Serialize)]
pub enum PathStep {
    /// A segment from `origin` along `dir` met the surface of entity `kind` at file
    /// line `line` at distance `t`: the vertex `point`, its normal facing the
    /// segment; `throughput` the path's weight arriving.
    Vertex {
        /// Where the segment starts.
        origin: Vec3,
        /// Its direction.
        dir: Vec3,
        /// What was met.
        kind: SourceKind,
        /// Its line in the scene file.
        line: u32,
        /// Its material's index.
        material: u32,
        /// The distance.
        t: f32,
        /// The vertex.
        point: Vec3,
        /// The normal facing the segment.
        normal: Vec3,
        /// The segment crosses into the object.
        entering: bool,
        /// The path's weight arriving.
        throughput: Vec3,
    },
    /// The vertex emits `radiance`, counted with MIS `weight`.
    Emitted {
        /// The emitted radiance.
        radiance: Vec3,
        /// The MIS weight.
        weight: f32,
    },
    /// A light sample: the point on the light, what it adds before the throughput
    /// (weighted), its MIS weight; or blocked.
    Light {
        /// The point on the light.
        point: Vec3,
        /// What it adds, weighted.
        contribution: Vec3,
        /// The MIS weight.
        weight: f32,
        /// A shadow ray found a blocker.
        blocked: bool,
    },
    /// The BSDF sample that continues the path.
    Bsdf {
        /// The new direction.
        dir: Vec3,
        /// `f cos / pdf`.
        weight: Vec3,
        /// The pdf (for a perfectly specular sample, its lobe's probability).
        pdf: f32,
        /// Perfectly specular.
        delta: bool,
        /// Through the surface.
        transmitted: bool,
        /// The throughput after it.
        throughput: Vec3,
    },
    /// The path left the scene from `origin` along `dir` and sees `radiance`.
    Escape {
        /// Where the last segment starts.
        origin: Vec3,
        /// Its direction.
        dir: Vec3,
        /// The background's radiance.
        radiance: Vec3,
        /// The path's weight.
        throughput: Vec3,
    },
}

impl PathStep {
    /// The step an event is kept as.
    pub fn of(event: PathEvent) -> PathStep {
        match event {
            PathEvent::Vertex {
                ray,
                primitive,
                t,
                point,
                normal,
                entering,
                throughput,
            } => PathStep::Vertex {
                origin: ray.origin,
                dir: ray.dir,
                kind: primitive.kind,
                line: primitive.line,
                material: primitive.material,
                t,
                point,
                normal,
                entering,
                throughput,
            },
            PathEvent::Emitted { radiance, weight } => PathStep::Emitted { radiance, weight },
            PathEvent::Light {
                point,
                contribution,
                weight,
                blocked,
            } => PathStep::Light {
                point,
                contribution,
                weight,
                blocked,
            },
            PathEvent::Bsdf {
                dir,
                sample,
                throughput,
            } => PathStep::Bsdf {
                dir,
                weight: sample.weight,
                pdf: sample.pdf,
                delta: sample.delta,
                transmitted: sample.transmitted,
                throughput,
            },
            PathEvent::Escape {
                ray,
                radiance,
                throughput,
            } => PathStep::Escape {
                origin: ray.origin,
                dir: ray.dir,
                radiance,
                throughput,
            },
        }
    }
}

/// Prints a path's steps, one per line, indented by `pad`, each vertex named with
/// `name` (the entity's keyword in the scene's language).
pub fn write_path(
    f: &mut fmt::Formatter<'_>,
    steps: &[PathStep],
    pad: &str,
    name: impl Fn(SourceKind) -> &'static str,
    v: impl Fn(Vec3) -> String,
) -> fmt::Result {
    let mut segment = 0;
    for step in steps {
        match step {
            PathStep::Vertex {
                origin,
                dir,
                kind,
                line,
                material,
                t,
                point,
                normal,
                entering,
                throughput,
            } => {
                segment += 1;
                let side = if *entering { "entering" } else { "leaving" };
                writeln!(f, "{pad}segment {segment} from {} dir {}", v(*origin), v(*dir))?;
                writeln!(
                    f,
                    "{pad}  hit {} at line {line}, t = {t:.4}, {side}, material #{material}",
                    name(*kind)
                )?;
                writeln!(
                    f,
                    "{pad}  point {}  normal {}  throughput {}",
                    v(*point),
                    v(*normal),
                    v(*throughput)
                )?;
            }
            PathStep::Emitted { radiance, weight } => {
                writeln!(f, "{pad}  emits {} (MIS weight {weight:.4})", v(*radiance))?;
            }
            PathStep::Light {
                point,
                contribution,
                weight,
                blocked,
            } => {
                if *blocked {
                    writeln!(f, "{pad}  light sample at {}: blocked", v(*point))?;
                } else {
                    writeln!(
                        f,
                        "{pad}  light sample at {}: adds {} (MIS weight {weight:.4}) before the throughput",
                        v(*point),
                        v(*contribution)
                    )?;
                }
            }
            PathStep::Bsdf {
                dir,
                weight,
                pdf,
                delta,
                transmitted,
                throughput,
            } => {
                let how = match (delta, transmitted) {
                    (true, true) => "specular refraction",
                    (true, false) => "specular reflection",
                    (false, true) => "refraction",
                    (false, false) => "reflection",
                };
                writeln!(
                    f,
                    "{pad}  BSDF sample ({how}): dir {}, pdf {pdf:.4}, weight {} -> throughput {}",
                    v(*dir),
                    v(*weight),
                    v(*throughput)
                )?;
            }
            PathStep::Escape {
                origin,
                dir,
                radiance,
                throughput,
            } => {
                segment += 1;
                writeln!(f, "{pad}segment {segment} from {} dir {}", v(*origin), v(*dir))?;
                writeln!(
                    f,
                    "{pad}  leaves the scene: background {} times throughput {}",
                    v(*radiance),
                    v(*throughput)
                )?;
            }
        }
    }
    Ok(())
}
