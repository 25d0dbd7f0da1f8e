//! The frames of an animated (AFF) scene that `nffrt render` renders: `--frame N`,
//! `--time T` or `--frames A..B`, the printf-style output pattern that names each
//! frame's picture (`out_%04d.png`), and `--motion-blur K`, each frame the mean of K
//! sub-frames over its interval. Without them a render shows frame 0.

use std::path::{Path, PathBuf};

use clap::Args;

use super::finish::beside_path;
use super::output::{refuse_overwriting, Named};
use super::CliError;
use nffrt::aff::{AffScene, FramePart, MeshMode};
use nffrt::limits::MAX_MOTION_BLUR_SUBFRAMES;
use nffrt::load::Loaded;
use nffrt::render::Aov;

/// Which frames of an animated scene to render (AFF scenes only).
#[derive(Args, Debug, Clone, Default)]
pub struct FrameArgs {
    /// Render frame N of an AFF scene's animation (0 is its start; frame n shows
    /// time START + n (END - START) / FRAMES). `-o` may name it by a printf-style
    /// field: `-o out_%04d.png`.
    #[arg(long, value_name = "N", allow_negative_numbers = true,
          value_parser = super::values::whole_number::<u32>(0, u32::MAX as u64),
          conflicts_with_all = ["time", "frames"])]
    pub frame: Option<u32>,
    /// Render an AFF scene at time T (any finite time; the curves hold their end
    /// keys outside them).
    #[arg(long, value_name = "T", allow_negative_numbers = true, value_parser = finite_time,
          conflicts_with = "frames")]
    pub time: Option<f64>,
    /// Render frames A to B of an AFF scene, both included, each to the picture `-o`
    /// names by a printf-style field (`-o out_%04d.png`; default: the scene's stem +
    /// `_%04d.png`). Not with --region, --pixel, --stats or --stats-json.
    #[arg(long, value_name = "A..B", value_parser = frame_range,
          conflicts_with_all = ["region", "pixel", "stats", "stats_json"])]
    pub frames: Option<(u32, u32)>,
    /// With --frames: flatten and build the whole scene for every frame, as a
    /// comparison for benchmarks (default: the objects under no keyframed transform
    /// are built once, and each frame builds only what moves).
    #[arg(long, requires = "frames")]
    pub rebuild_whole: bool,
    /// Copy every mesh of an AFF scene into world space each frame, as the
    /// comparison for benchmarks and memory (default: a mesh placed more than once,
    /// or moved by keyframes, is an instance of one built once in its own space).
    #[arg(long)]
    pub flatten_meshes: bool,
    #[arg(long, value_name = "K", allow_negative_numbers = true,
          help = format!("Motion blur across each frame's interval (an AFF scene's): the frame shown at \
                          time t is the mean, in linear floats, of K sub-frames flattened at t + (i + 0.5) \
                          / K * STEP (STEP the time between frames), an accumulation buffer; 1 to \
                          {MAX_MOTION_BLUR_SUBFRAMES}. With --frame, --time, --frames or alone (frame 0); \
                          not with --region, --pixel, --stats, --stats-json, --denoise or --aov"),
          value_parser = super::values::whole_number::<u32>(1, MAX_MOTION_BLUR_SUBFRAMES as u64),
          conflicts_with_all = ["region", "pixel", "stats", "stats_json", "denoise", "aov"])]
    pub motion_blur: Option<u32>,
}

impl FrameArgs {
    /// True if any of the options is given.
    pub fn any(&self) -> bool {
        self.frame.is_some()
            || self.time.is_some()
            || self.frames.is_some()
            || self.motion_blur.is_some()
            || self.flatten_meshes
    }

    /// The flag given, for messages.
    fn flag(&self) -> &'static str {
        match (self.frame, self.time, self.frames) {
            (Some(_), _, _) => "--frame",
            (_, Some(_), _) => "--time",
            (_, _, Some(_)) => "--frames",
            _ if self.motion_blur.is_some() => "--motion-blur",
            _ => "--flatten-meshes",
        }
    }
}

/// `--time`'s value: a finite number.
pub fn finite_time(s: &str) -> Result<f64, String> {
    match s.trim().parse::<f64>() {
        Ok(t) if t.is_finite() => Ok(t),
        _ => Err(format!("expected a finite number of time units, found {s:?}")),
    }
}

/// `--frames`' value: `A..B` with `A <= B`, both whole numbers.
fn frame_range(s: &str) -> Result<(u32, u32), String> {
    let bad = || format!("expected A..B, two frame numbers with A <= B (e.g. 0..99), found {s:?}");
    let (a, b) = s.split_once("..").ok_or_else(bad)?;
    let (a, b) = (a.trim().parse::<u32>(), b.trim().parse::<u32>());
    match (a, b) {
        (Ok(a), Ok(b)) if a <= b => Ok((a, b)),
        _ => Err(bad()),
    }
}

/// One frame to render: its number (none for `--time`), its time, and its picture.
/// (With `--motion-blur`, the time the frame's interval starts at.)
#[derive(Clone, Debug, PartialEq)]
pub struct FrameJob {
    /// The frame's number.
    pub number: Option<u32>,
    /// The scene's time.
    pub time: f64,
    /// Where its picture goes.
    pub output: PathBuf,
    /// How its meshes are placed.
    pub meshes: MeshMode,
}

/// An output name with at most one printf-style integer field: `%d`, `%4d` or
/// `%04d` (a width up to 9, zero-padded or not); `%%` is a literal `%`.
#[derive(Clone, Debug, PartialEq)]
pub struct OutputPattern {
    before: String,
    /// The field's width and whether it pads with zeros, and the text after it.
    field: Option<(usize, bool, String)>,
}

impl OutputPattern {
    /// Reads `text`; a `%` that starts neither a field nor `%%`, or a second field, is
    /// refused.
    pub fn parse(text: &str) -> Result<OutputPattern, String> {
        let mut parts = vec![String::new()];
        let mut field = None;
        let mut chars = text.chars().peekable();
        while let Some(c) = chars.next() {
            if c != '%' {
                parts.last_mut().expect("one part at least").push(c);
                continue;
            }
            if chars.peek() == Some(&'%') {
                chars.next();
                parts.last_mut().expect("one part at least").push('%');
                continue;
            }
            let zero = chars.next_if_eq(&'0').is_some();
            let width = chars
                .next_if(|c| c.is_ascii_digit())
                .map_or(0, |d| d as usize - '0' as usize);
            if chars.next() != Some('d') {
                return Err(format!(
                    "{text:?}: a % in an output name starts a frame number field (%d, %4d, %04d; width 1 to 9) or %% (a literal %)"
                ));
            }
            if field.is_some() {
                return Err(format!("{text:?} has two frame number fields; give it one"));
            }
            field = Some((width, zero));
            parts.push(String::new());
        }
        let after = parts.pop().expect("one part at least");
        Ok(match field {
            None => OutputPattern {
                before: after,
                field: None,
            },
            Some((width, zero)) => OutputPattern {
                before: parts.pop().expect("the part before the field"),
                field: Some((width, zero, after)),
            },
        })
    }

    /// True if the pattern has a frame number field.
    pub fn has_field(&self) -> bool {
        self.field.is_some()
    }

    /// The name of frame `n`.
    pub fn expand(&self, n: u32) -> PathBuf {
        match &self.field {
            None => PathBuf::from(&self.before),
            Some((width, true, after)) => PathBuf::from(format!("{}{n:0width$}{after}", self.before)),
            Some((width, false, after)) => PathBuf::from(format!("{}{n:width$}{after}", self.before)),
        }
    }
}

/// The frames `args` ask of `loaded` with pictures named by `output` (the `-o`
/// given, or `None` for the default), or `None` without frame options (a render of
/// frame 0 as of old). Refused: frame options on a scene that is not AFF, a frame
/// past the animation, more than one frame to a name without a field, and a name
/// that is one of the scene's files (the scene, its includes, its textures), the
/// names of the `aovs` files beside each picture included.
pub fn plan(
    args: &FrameArgs,
    loaded: &Loaded,
    scene_path: &Path,
    output: Option<&Path>,
    aovs: &[Aov],
) -> Result<Option<Vec<FrameJob>>, CliError> {
    if !args.any() {
        return Ok(None);
    }
    let Some(aff) = loaded.aff.as_deref() else {
        return Err(CliError::usage(format!(
            "{}: {} is not an AFF scene (it reads as {}) and does not move; --frame, --time and --frames are for AFF scenes",
            args.flag(),
            loaded.name,
            loaded.scene.dialect.name()
        )));
    };
    let numbers: Vec<Option<u32>> = match (args.frame, args.time, args.frames) {
        (Some(n), _, _) => vec![Some(n)],
        (_, Some(_), _) => vec![None],
        (_, _, Some((a, b))) => (a..=b).map(Some).collect(),
        // --motion-blur or --flatten-meshes alone: frame 0, as a render without
        // frame options.
        _ => vec![Some(0)],
    };
    if args.motion_blur.is_some() && aff.span.is_none() {
        return Err(CliError::usage(format!(
            "--motion-blur: {} has no animation (`a START END FRAMES`), so its one frame has no interval to blur over",
            loaded.name
        )));
    }
    let last = aff.frames() - 1;
    if let Some(n) = numbers.iter().flatten().find(|&&n| n > last) {
        return Err(CliError::usage(format!(
            "{} {n}: {} has {} (0 to {last})",
            args.flag(),
            loaded.name,
            nffrt::words::count(aff.frames() as usize, "frame", "frames")
        )));
    }
    let pattern = match output {
        Some(path) => path.to_string_lossy().into_owned(),
        None => default_pattern(scene_path, numbers.len() > 1),
    };
    let pattern = OutputPattern::parse(&pattern).map_err(|e| CliError::usage(format!("-o {e}")))?;
    if numbers.len() > 1 && !pattern.has_field() {
        return Err(CliError::usage(format!(
            "--frames renders {} frames, but -o {} names one file: put a frame number field in it (out_%04d.png)",
            numbers.len(),
            pattern.expand(0).display()
        )));
    }
    let jobs: Vec<FrameJob> = numbers
        .into_iter()
        .map(|number| FrameJob {
            number,
            time: number.map_or_else(|| args.time.unwrap_or_default(), |n| aff.time_of_frame(n)),
            // `--time` has no frame number: its field shows 0.
            output: pattern.expand(number.unwrap_or(0)),
            meshes: match args.flatten_meshes {
                true => MeshMode::Copied,
                false => MeshMode::Instanced,
            },
        })
        .collect();
    refuse_inputs(&jobs, aovs, aff, scene_path)?;
    Ok(Some(jobs))
}

/// The scene of `loaded` (an AFF scene's) at `job`'s time: a frame that cannot be
/// made (a sphere under a stretch, say) is a bad scene, named with its frame.
pub fn flatten(loaded: &Loaded, job: &FrameJob) -> Result<nffrt::Scene, CliError> {
    flatten_part(loaded, job, FramePart::All)
}

/// [`flatten`] keeping only the objects of `part`.
pub fn flatten_part(loaded: &Loaded, job: &FrameJob, part: FramePart) -> Result<nffrt::Scene, CliError> {
    let aff = loaded
        .aff
        .as_deref()
        .expect("frames are planned for AFF scenes only");
    aff.flatten_part(job.time, part, job.meshes)
        .map_err(|e| CliError::scene(format!("{}: {e}", job.name())))
}

/// A scene's fingerprint `scene` made that of the scene at time `t`.
pub fn fingerprint_at(scene: u64, t: f64) -> u64 {
    // A multiply by an odd constant (the golden ratio's bits) mixes the time's bits in.
    (scene ^ t.to_bits()).wrapping_mul(0x9E37_79B9_7F4A_7C15)
}

impl FrameJob {
    /// `frame N (time T)`, or `time T`, for messages.
    pub fn name(&self) -> String {
        match self.number {
            Some(n) => format!("frame {n} (time {})", self.time),
            None => format!("time {}", self.time),
        }
    }
}

/// The default pictures: the scene's stem + `.png`, or + `_%04d.png` for several.
fn default_pattern(scene: &Path, several: bool) -> String {
    let stem = scene.file_stem().filter(|_| scene != Path::new("-"));
    let stem = stem.map_or_else(|| "stdin".into(), |s| s.to_string_lossy().replace('%', "%%"));
    if several {
        format!("{stem}_%04d.png")
    } else {
        format!("{stem}.png")
    }
}

/// The files an AFF scene was read from, as [`refuse_overwriting`] names them: the
/// scene file, its includes, its textures.
pub fn aff_inputs<'a>(aff: &'a AffScene, scene_path: &'a Path) -> Vec<(&'a Path, &'static str)> {
    let mut inputs: Vec<(&Path, &str)> = vec![(scene_path, "the scene file")];
    inputs.extend(
        aff.files
            .iter()
            .filter_map(|f| f.path.as_deref())
            .map(|p| (p, "a file the scene includes")),
    );
    inputs.extend(
        aff.textures
            .iter()
            .map(|t| (t.path.as_path(), "a texture of the scene")),
    );
    inputs
}

/// Refuses a picture that would overwrite one of the files the scene was read from.
fn refuse_inputs(jobs: &[FrameJob], aovs: &[Aov], aff: &AffScene, scene_path: &Path) -> Result<(), CliError> {
    let inputs = aff_inputs(aff, scene_path);
    for job in jobs {
        let beside: Vec<PathBuf> = aovs.iter().map(|&a| beside_path(&job.output, a)).collect();
        let named = Named {
            path: &job.output,
            named: format!("the picture {}", job.output.display()),
        };
        let beside = beside.iter().map(|path| Named {
            path,
            named: format!("the AOV picture {}", path.display()),
        });
        refuse_overwriting(&std::iter::once(named).chain(beside).collect::<Vec<_>>(), &inputs)?;
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn patterns_expand_printf_fields() {
        let p = OutputPattern::parse("out_%04d.png").unwrap();
        assert_eq!(p.expand(7), PathBuf::from("out_0007.png"));
        assert_eq!(p.expand(12345), PathBuf::from("out_12345.png"));
        assert_eq!(
            OutputPattern::parse("f%d").unwrap().expand(42),
            PathBuf::from("f42")
        );
        assert_eq!(
            OutputPattern::parse("f%3d.png").unwrap().expand(4),
            PathBuf::from("f  4.png")
        );
        let literal = OutputPattern::parse("100%%_%d.png").unwrap();
        assert_eq!(literal.expand(3), PathBuf::from("100%_3.png"));
        let plain = OutputPattern::parse("still.png").unwrap();
        assert!(!plain.has_field());
        assert_eq!(plain.expand(9), PathBuf::from("still.png"));
    }

    #[test]
    fn bad_patterns_are_refused() {
        for bad in ["a%s.png", "a%", "%d_%d.png", "a%x", "%010d"] {
            assert!(OutputPattern::parse(bad).is_err(), "{bad}");
        }
    }

    #[test]
    fn ranges_read_a_to_b() {
        assert_eq!(frame_range("3..7"), Ok((3, 7)));
        assert_eq!(frame_range("5..5"), Ok((5, 5)));
        for bad in ["7..3", "3-7", "..4", "a..b", "-1..2"] {
            assert!(frame_range(bad).is_err(), "{bad}");
        }
        assert!(finite_time("inf").is_err() && finite_time("nan").is_err());
        assert_eq!(finite_time("-0.5"), Ok(-0.5));
    }
}
