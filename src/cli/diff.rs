//! `nffrt diff`: how far pictures are from a reference, by NVIDIA's FLIP or a classic
//! metric ([`nffrt::compare`]): one line for one picture, a table from the closest
//! to the farthest for several, JSON for scripts, the error map on request, and exit
//! code 1 when a picture is farther than `--tolerance` allows.

use std::path::{Path, PathBuf};

use clap::builder::{PossibleValuesParser, TypedValueParser};
use clap::Args;
use serde_json::json;

use super::image_out::{display_name, format_of, is_stdout, Destination};
use super::output::{refuse_overwriting, Named};
use super::{exit, interrupt, CliError};
use nffrt::compare::flip::default_ppd;
use nffrt::compare::{compare, CompareError, Comparison, Metric, Picture, ReadError};
use nffrt::image::{Encoding, ImageFormat, SOFTWARE_TEXT};
use nffrt::words::shortest_f64;

/// Arguments of `nffrt diff`.
#[derive(Args, Debug)]
pub struct DiffArgs {
    /// The pictures to measure (PNG, PPM, PFM or OpenEXR); without --ref, exactly
    /// two: TEST and REF.
    #[arg(required = true, value_name = "TEST")]
    pub pictures: Vec<PathBuf>,
    /// The reference picture, for one or more TEST pictures.
    #[arg(long = "ref", value_name = "REF")]
    pub reference: Option<PathBuf>,
    /// The metric: NVIDIA's FLIP (LDR-FLIP for 8-bit pictures, HDR-FLIP for float
    /// ones), mean squared error, its root, pbrt's relative MSE, mean absolute error,
    /// or PSNR in dB.
    #[arg(long, value_name = "METRIC", default_value = "flip", value_parser = metric_parser())]
    pub metric: Metric,
    /// Write the error map of the one TEST: .png or .ppm in FLIP's magma colours
    /// (FLIP from 0 to 1, the other metrics from 0 to their largest pixel error),
    /// .pfm or .exr its values.
    #[arg(short, long, value_name = "MAP")]
    pub output: Option<PathBuf>,
    /// Print the results as one JSON object.
    #[arg(long)]
    pub json: bool,
    /// Exit with code 1 when a picture's error is above X (for PSNR, below X).
    #[arg(long, value_name = "X", value_parser = tolerance, allow_negative_numbers = true)]
    pub tolerance: Option<f64>,
    /// No line saying where the map went.
    #[arg(short, long)]
    pub quiet: bool,
}

fn metric_parser() -> impl TypedValueParser<Value = Metric> {
    PossibleValuesParser::new(Metric::ALL.map(Metric::name))
        .map(|name| Metric::from_name(&name).expect("one of the possible values"))
}

fn tolerance(s: &str) -> Result<f64, String> {
    s.trim()
        .parse::<f64>()
        .ok()
        .filter(|v| v.is_finite())
        .ok_or_else(|| "must be a number".into())
}

/// One measured picture.
struct Measured {
    test: PathBuf,
    comparison: Comparison,
}

/// Runs `nffrt diff`.
pub fn run(args: DiffArgs) -> Result<(), CliError> {
    let (tests, reference) = match &args.reference {
        Some(r) => (&args.pictures[..], r),
        None if args.pictures.len() == 2 => (&args.pictures[..1], &args.pictures[1]),
        None => {
            return Err(CliError::usage(format!(
                "give TEST REF, or the reference with --ref (got {} picture{} and no --ref)",
                args.pictures.len(),
                if args.pictures.len() == 1 { "" } else { "s" }
            )))
        }
    };
    let output = match &args.output {
        Some(path) => Some((path, map_format(path, tests)?)),
        None => None,
    };
    if let Some((path, _)) = output {
        let mut inputs = vec![(reference.as_path(), "the reference")];
        inputs.extend(tests.iter().map(|t| (t.as_path(), "the test picture")));
        refuse_overwriting(&[Named::flag("-o", path)], &inputs)?;
    }
    let destination = output.map(|(path, _)| Destination::create(path)).transpose()?;
    let reference_picture = read(reference)?;
    let mut measured = Vec::with_capacity(tests.len());
    for test in tests {
        // Ctrl-C stops a batch between two pictures (exit 130).
        interrupt::check()?;
        let mut comparison = compare(&read(test)?, &reference_picture, args.metric)
            .map_err(|e| comparison_error(e, test, reference))?;
        if output.is_none() {
            // A batch keeps each picture's value, not its map.
            comparison.map = Vec::new();
        }
        measured.push(Measured {
            test: test.clone(),
            comparison,
        });
    }
    // Closest first; equal errors keep the order given.
    measured.sort_by(|a, b| args.metric.closest_first(a.comparison.value, b.comparison.value));
    if args.json {
        report_json(&args, reference, &measured);
    } else {
        report_text(&args, reference, &measured);
    }
    if let (Some(destination), Some((path, format))) = (destination, output) {
        write_map(destination, path, format, &measured[0].comparison, args.quiet)?;
    }
    check_tolerance(&args, &measured)
}

/// The format of the map's file; one map, so one TEST.
fn map_format(path: &Path, tests: &[PathBuf]) -> Result<ImageFormat, CliError> {
    if is_stdout(path) {
        return Err(CliError::usage("-o -: diff writes its map to a file; name one"));
    }
    if tests.len() > 1 {
        return Err(CliError::usage(format!(
            "-o {}: the error map is of one picture, and {} were given",
            path.display(),
            tests.len()
        )));
    }
    format_of(path)
}

/// Reads one picture; the error says which and exits as its kind: 4 for a file
/// that cannot be read, 2 for an unknown extension, 3 for a file that is no picture.
fn read(path: &Path) -> Result<Picture, CliError> {
    let name = path.display();
    Picture::read(path).map_err(|e| match e {
        ReadError::Io(_) => CliError::io(format!("{name}: {e}")),
        ReadError::UnknownFormat => CliError::usage(ImageFormat::unknown(path)),
        ReadError::Malformed(_) => CliError::scene(format!("{name}: {e}")),
    })
}

fn comparison_error(e: CompareError, test: &Path, reference: &Path) -> CliError {
    let message = format!("{} against {}: {e}", test.display(), reference.display());
    match e {
        CompareError::BlackReference => CliError::scene(message),
        CompareError::Size { .. } | CompareError::Range { .. } => CliError::usage(message),
    }
}

/// How FLIP saw the pictures, for people: `LDR-FLIP` or `HDR-FLIP, exposures A to
/// B in N steps`; nothing for the other metrics.
fn flip_mode(c: &Comparison) -> Option<String> {
    if c.metric != Metric::Flip {
        return None;
    }
    Some(match c.exposures {
        None => "LDR-FLIP".to_string(),
        Some(e) => format!(
            "HDR-FLIP, exposures {:.2} to {:.2} in {} steps",
            e.start, e.stop, e.count
        ),
    })
}

/// `value` with six significant digits (`inf` for equal pictures' PSNR).
fn significant(value: f64) -> String {
    if value == 0.0 || !value.is_finite() {
        return format!("{value}");
    }
    let decimals = (5 - value.abs().log10().floor() as i32).max(0) as usize;
    format!("{value:.decimals$}")
}

fn exceeds(args: &DiffArgs, value: f64) -> bool {
    args.tolerance.is_some_and(|t| args.metric.exceeds(value, t))
}

fn report_text(args: &DiffArgs, reference: &Path, measured: &[Measured]) {
    let first = &measured[0].comparison;
    let mut about = vec![format!("{}x{}", first.width, first.height)];
    about.extend(flip_mode(first));
    let about = about.join(", ");
    let name = args.metric.name();
    let mark = |value: f64| match args.tolerance {
        Some(t) if exceeds(args, value) => {
            let side = if args.metric.higher_is_closer() {
                "below"
            } else {
                "above"
            };
            format!("  {side} --tolerance {t}")
        }
        _ => String::new(),
    };
    if let [one] = measured {
        let v = one.comparison.value;
        outln!(
            "{}: {name} {} against {} ({about}){}",
            one.test.display(),
            significant(v),
            reference.display(),
            mark(v)
        );
        return;
    }
    outln!("{name} against {} ({about}), closest first:", reference.display());
    let values: Vec<String> = measured.iter().map(|m| significant(m.comparison.value)).collect();
    let width = values.iter().map(String::len).max().unwrap_or(0);
    for (m, v) in measured.iter().zip(&values) {
        outln!("  {v:>width$}  {}{}", m.test.display(), mark(m.comparison.value));
    }
}

fn report_json(args: &DiffArgs, reference: &Path, measured: &[Measured]) {
    let first = &measured[0].comparison;
    let results: Vec<_> = measured
        .iter()
        .map(|m| {
            json!({
                "test": m.test.display().to_string(),
                "value": m.comparison.value,
                "exceeds_tolerance": exceeds(args, m.comparison.value),
            })
        })
        .collect();
    let flip = (args.metric == Metric::Flip).then(|| match first.exposures {
        None => json!({ "mode": "ldr", "ppd": shortest_f64(default_ppd()) }),
        Some(e) => json!({
            "mode": "hdr",
            "ppd": shortest_f64(default_ppd()),
            "start_exposure": shortest_f64(e.start),
            "stop_exposure": shortest_f64(e.stop),
            "exposures": e.count,
        }),
    });
    let j = json!({
        "metric": args.metric.name(),
        "reference": reference.display().to_string(),
        "width": first.width,
        "height": first.height,
        "flip": flip,
        "tolerance": args.tolerance,
        "passed": !measured.iter().any(|m| exceeds(args, m.comparison.value)),
        "results": results,
        "map": args.output.as_ref().map(|p| p.display().to_string()),
    });
    outln!("{}", serde_json::to_string(&j).expect("plain data serializes"));
}

fn write_map(
    destination: Destination,
    path: &Path,
    format: ImageFormat,
    c: &Comparison,
    quiet: bool,
) -> Result<(), CliError> {
    let (image, scale) = if format.is_8bit() {
        (c.heat_map(), format!("magma from 0 to {}", c.heat_top()))
    } else {
        (c.value_map(), "its values".to_string())
    };
    let text = [(SOFTWARE_TEXT.0, SOFTWARE_TEXT.1.to_string())];
    destination.write_image(&image, format, Encoding::Linear, &text)?;
    if !quiet {
        eprintln!(
            "wrote the {} map to {} ({scale})",
            c.metric.name(),
            display_name(path)
        );
    }
    Ok(())
}

/// Exit code 1, naming the pictures, when any is farther than `--tolerance`.
fn check_tolerance(args: &DiffArgs, measured: &[Measured]) -> Result<(), CliError> {
    let Some(t) = args.tolerance else { return Ok(()) };
    let far: Vec<&Measured> = measured
        .iter()
        .filter(|m| exceeds(args, m.comparison.value))
        .collect();
    if far.is_empty() {
        return Ok(());
    }
    let side = if args.metric.higher_is_closer() {
        "below"
    } else {
        "above"
    };
    let name = args.metric.name();
    let message = match &far[..] {
        [one] if measured.len() == 1 => format!(
            "{}: {name} {} is {side} --tolerance {t}",
            one.test.display(),
            significant(one.comparison.value)
        ),
        _ => {
            let names: Vec<String> = far.iter().map(|m| m.test.display().to_string()).collect();
            format!(
                "{} of {} pictures are {side} --tolerance {t} by {name}: {}",
                far.len(),
                measured.len(),
                names.join(", ")
            )
        }
    };
    Err(CliError {
        message,
        code: exit::ABOVE_TOLERANCE,
    })
}
