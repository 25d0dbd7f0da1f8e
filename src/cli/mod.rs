//! Subcommands of the `nffrt` binary and the shared plumbing: loading scenes,
//! reporting errors with their exit codes.

/// `println!` for command output: a closed standard output (e.g. piped into `head`)
/// ends the program quietly with success instead of panicking; any other write
/// failure is an I/O error.
macro_rules! outln {
    ($($arg:tt)*) => {{
        use std::io::Write as _;
        if let Err(e) = writeln!(std::io::stdout(), $($arg)*) {
            $crate::cli::stdout_failed(e)
        }
    }};
}

mod animation;
mod bench;
mod convert;
mod diff;
mod finish;
mod frames;
mod gen;
mod image_out;
mod info;
mod interrupt;
mod limits;
mod load;
mod merge;
mod output;
mod pixel;
mod progress;
mod render;
mod stats;
mod values;
#[cfg(feature = "cli")]
mod view;

use clap::{Parser, Subcommand};

/// Exit codes, documented in `docs/command-line.md`.
pub mod exit {
    /// Success.
    pub const OK: i32 = 0;
    /// `diff`: a picture is farther from the reference than `--tolerance` allows.
    pub const ABOVE_TOLERANCE: i32 = 1;
    /// Command-line usage error (unknown option, bad value).
    pub const USAGE: i32 = 2;
    /// The scene file is malformed or unusable.
    pub const BAD_SCENE: i32 = 3;
    /// Reading or writing a file failed.
    pub const IO: i32 = 4;
    /// Interrupted by Ctrl-C or SIGTERM.
    pub const INTERRUPTED: i32 = 130;
}

/// An error that ends the program: its message and exit code.
#[derive(Debug)]
pub struct CliError {
    /// The one-line message (without the `nffrt: error:` prefix).
    pub message: String,
    /// The process exit code.
    pub code: i32,
}

impl CliError {
    /// An I/O failure.
    pub fn io(message: impl Into<String>) -> Self {
        CliError {
            message: message.into(),
            code: exit::IO,
        }
    }
    /// A bad scene file.
    pub fn scene(message: impl Into<String>) -> Self {
        CliError {
            message: message.into(),
            code: exit::BAD_SCENE,
        }
    }
    /// A bad combination of command-line values.
    pub fn usage(message: impl Into<String>) -> Self {
        CliError {
            message: message.into(),
            code: exit::USAGE,
        }
    }
}

/// nffrt: a fast, correct ray tracer for NFF scenes (the Standard Procedural Databases)
/// and P3F scenes (the IST course's extended NFF).
#[derive(Parser, Debug)]
#[command(name = "nffrt", version, about, long_about = None, propagate_version = true)]
#[command(
    after_help = "Exit codes: 0 success, 1 diff above --tolerance, 2 usage error, 3 bad scene file, 4 I/O error, 130 interrupted.\n\
Examples:\n  nffrt gen balls -o balls.nff\n  nffrt info scene.nff\n  nffrt render scene.nff -o scene.png --stats\n  nffrt render scene.nff --region 0,0,256,512 -o left.png\n  nffrt merge left.png right.png -o scene.png\n  nffrt diff scene.png reference.png -o heat.png\n  nffrt view scene.nff"
)]
struct Cli {
    #[command(subcommand)]
    command: Command,
}

#[derive(Subcommand, Debug)]
enum Command {
    /// Write one of the SPD's classic scenes (balls, gears, mount, rings, teapot, tetra, tree) as NFF.
    Gen(gen::GenArgs),
    /// Write a scene as NFF: an AFF scene's frame (`--frame N`) flattened into plain
    /// geometry, a P3F scene without what NFF cannot say.
    Convert(convert::ConvertArgs),
    /// Summarize a scene: primitive counts, lights, materials, resolution, bounds, warnings.
    Info(info::InfoArgs),
    /// Render a scene to an image (PNG, PPM, PFM or OpenEXR), a tile of it, or trace one
    /// pixel.
    Render(render::RenderArgs),
    /// Assemble the PNG tiles of `render --region` into the full image.
    Merge(merge::MergeArgs),
    /// Time the acceleration structure alone: closest-hit and occlusion queries on
    /// primary, random and file-supplied rays (no shading), and closest hits in
    /// packets of 8 consecutive rays.
    Bench(bench::BenchArgs),
    /// Measure how far pictures are from a reference: NVIDIA's FLIP (the default),
    /// MSE, RMSE, relative MSE, MAE or PSNR; the error map on request.
    Diff(diff::DiffArgs),
    /// Preview a scene live in the browser: progressive frames, an orbiting camera,
    /// each pixel's ray tree; the file is watched and rendered again when it changes.
    #[cfg(feature = "cli")]
    View(view::ViewArgs),
}

/// Ends the program after a failed write to standard output (see `outln!`).
pub fn stdout_failed(e: std::io::Error) -> ! {
    if e.kind() == std::io::ErrorKind::BrokenPipe {
        std::process::exit(exit::OK);
    }
    eprintln!("nffrt: error: writing standard output: {e}");
    std::process::exit(exit::IO);
}

/// Parses the command line, runs the subcommand, prints any error, returns the exit code.
pub fn run() -> i32 {
    let cli = match Cli::try_parse() {
        Ok(c) => c,
        Err(e) if e.use_stderr() => {
            let suggestion = suggestion(&e).map(|s| format!("; {s}")).unwrap_or_default();
            eprintln!(
                "nffrt: error: {}{suggestion} (see {} --help)",
                usage_line(&e),
                command_named()
            );
            return exit::USAGE;
        }
        Err(e) if e.kind() == clap::error::ErrorKind::DisplayVersion => {
            // The same line after `nffrt --version` and `nffrt render --version`.
            outln!("nffrt {}", env!("CARGO_PKG_VERSION"));
            return exit::OK;
        }
        Err(e) => {
            // --help.
            let _ = e.print();
            return exit::OK;
        }
    };
    if let Err(message) = nffrt::accel::simd::requested() {
        eprintln!("nffrt: error: {message}");
        return exit::USAGE;
    }
    interrupt::install();
    let result = match cli.command {
        Command::Gen(a) => gen::run(a),
        Command::Convert(a) => convert::run(a),
        Command::Info(a) => info::run(a),
        Command::Render(a) => render::run(a),
        Command::Merge(a) => merge::run(a),
        Command::Bench(a) => bench::run(a),
        Command::Diff(a) => diff::run(a),
        #[cfg(feature = "cli")]
        Command::View(a) => view::run(a),
    };
    match result {
        Ok(()) => exit::OK,
        Err(e) => {
            eprintln!("nffrt: error: {}", e.message);
            e.code
        }
    }
}

/// `nffrt SUBCOMMAND` when the command line names one (its help lists its options),
/// otherwise `nffrt`.
fn command_named() -> String {
    let first = std::env::args_os().nth(1);
    let first = first.as_ref().and_then(|a| a.to_str()).unwrap_or_default();
    match <Cli as clap::CommandFactory>::command().find_subcommand(first) {
        Some(sub) => format!("nffrt {}", sub.get_name()),
        None => "nffrt".to_string(),
    }
}

/// Clap's "did you mean" for a mistyped option, subcommand or value.
fn suggestion(e: &clap::Error) -> Option<String> {
    use clap::error::{ContextKind, ContextValue};
    let kinds = [
        ContextKind::SuggestedArg,
        ContextKind::SuggestedSubcommand,
        ContextKind::SuggestedValue,
    ];
    let names: Vec<String> = kinds.into_iter().find_map(|kind| match e.get(kind)? {
        ContextValue::String(s) => Some(vec![s.clone()]),
        ContextValue::Strings(v) if !v.is_empty() => Some(v.clone()),
        ContextValue::StyledStr(s) => Some(vec![s.to_string()]),
        ContextValue::StyledStrs(v) if !v.is_empty() => Some(v.iter().map(|s| s.to_string()).collect()),
        _ => None,
    })?;
    let quoted: Vec<String> = names.iter().map(|n| format!("'{n}'")).collect();
    Some(format!("did you mean {}?", quoted.join(" or ")))
}

/// The first line of clap's message, without its `error: ` prefix: one line per
/// mistake, like every other error. A first line ending in a colon introduces the
/// indented lines after it (the arguments missing), which join it.
fn usage_line(e: &clap::Error) -> String {
    use clap::error::ErrorKind;
    if matches!(
        e.kind(),
        ErrorKind::MissingSubcommand | ErrorKind::DisplayHelpOnMissingArgumentOrSubcommand
    ) {
        // (clap's message is then the whole help text.)
        let commands: Vec<String> = <Cli as clap::CommandFactory>::command()
            .get_subcommands()
            .map(|c| c.get_name().to_string())
            .filter(|name| name != "help")
            .collect();
        return format!("no command given: {}", commands.join(", "));
    }
    let text = e.render().to_string();
    let mut lines = text.lines().skip_while(|l| l.trim().is_empty());
    let first = lines.next().unwrap_or("bad command line");
    let first = first.strip_prefix("error: ").unwrap_or(first).trim();
    if let Some(head) = first.strip_suffix(':') {
        let items: Vec<&str> = lines.take_while(|l| l.starts_with("  ")).map(str::trim).collect();
        if !items.is_empty() {
            return format!("{head}: {}", items.join(", "));
        }
    }
    first.to_string()
}
