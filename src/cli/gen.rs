//! `nffrt gen`: writes one of the SPD's classic scenes as NFF, to standard output
//! or, through a temporary file renamed when complete, to a file.

use std::fs::{File, OpenOptions};
use std::io::{self, BufWriter, Write};
use std::path::{Path, PathBuf};

use clap::Args;
use nffrt::gen::{generate, SpdScene, MAX_PRIMITIVES};
use nffrt::nff::write_nff;
use nffrt::Scene;

use super::{exit, interrupt, CliError};

/// Arguments of `nffrt gen`.
#[derive(Args, Debug)]
#[command(after_help = size_table())]
pub struct GenArgs {
    /// Scene to make: balls, gears, mount, rings, teapot, tetra or tree.
    #[arg(value_name = "NAME", value_parser = parse_scene)]
    pub name: SpdScene,
    /// Size factor with the SPD's meaning (see below); default: the SPD's default.
    #[arg(short, long, value_name = "N")]
    pub size: Option<u32>,
    /// Write to FILE instead of standard output (`-` is standard output).
    #[arg(short, long, value_name = "FILE")]
    pub output: Option<PathBuf>,
}

fn parse_scene(s: &str) -> Result<SpdScene, String> {
    SpdScene::from_name(s).ok_or_else(|| {
        let names: Vec<&str> = SpdScene::ALL.iter().map(|s| s.name()).collect();
        format!("no SPD scene called '{s}' (try {})", names.join(", "))
    })
}

/// The table of sizes shown after `nffrt gen --help`.
fn size_table() -> String {
    let mut t = String::from("Sizes (as in the SPD; the limit keeps every scene within ");
    t.push_str(&format!("{MAX_PRIMITIVES} primitives):\n"));
    for s in SpdScene::ALL {
        t.push_str(&format!(
            "  {:<7} {:<42} default {:>2}, at most {:>3}\n",
            s.name(),
            s.size_meaning(),
            s.default_size(),
            s.max_size()
        ));
    }
    t.push_str("Examples:\n  nffrt gen balls | nffrt render - -o balls.png\n  nffrt gen mount --size 9 -o mount9.nff");
    t
}

/// Runs `nffrt gen`.
pub fn run(args: GenArgs) -> Result<(), CliError> {
    let size = args.size.unwrap_or(args.name.default_size());
    let scene = generate(args.name, size).map_err(|e| CliError::usage(e.to_string()))?;
    match args.output.as_deref() {
        None => write_stdout(&scene),
        Some(p) if p == Path::new("-") => write_stdout(&scene),
        Some(p) => write_file(&scene, p),
    }
}

fn write_stdout(scene: &Scene) -> Result<(), CliError> {
    let mut w = BufWriter::with_capacity(1 << 16, io::stdout().lock());
    match write_nff(scene, &mut w).and_then(|()| w.flush()) {
        Ok(()) => Ok(()),
        // The reader stopped early (`nffrt gen balls | head`): not our failure.
        Err(e) if e.kind() == io::ErrorKind::BrokenPipe => Ok(()),
        Err(e) => Err(CliError::io(format!("writing standard output: {e}"))),
    }
}

/// Writes beside `dest` and renames into place, so `dest` is never half-written.
fn write_file(scene: &Scene, dest: &Path) -> Result<(), CliError> {
    let name = dest.display();
    if dest.is_dir() {
        return Err(CliError::io(format!("{name}: is a directory")));
    }
    let Some(file_name) = dest.file_name() else {
        return Err(CliError::io(format!("{name}: not a file name")));
    };
    let dir = dest
        .parent()
        .filter(|d| !d.as_os_str().is_empty())
        .unwrap_or(Path::new("."));
    let tmp = dir.join(format!(
        ".{}.{}.tmp",
        file_name.to_string_lossy(),
        std::process::id()
    ));
    let written = (|| -> io::Result<()> {
        let file = OpenOptions::new().write(true).create_new(true).open(&tmp)?;
        interrupt::register_temp(tmp.clone());
        let mut w = BufWriter::with_capacity(1 << 16, file);
        write_nff(scene, &mut w)?;
        let file: File = w.into_inner().map_err(|e| e.into_error())?;
        file.sync_all()?;
        drop(file);
        // Ctrl-C or SIGTERM while writing: leave the destination as it was.
        if interrupt::interrupted() {
            return Err(io::Error::new(io::ErrorKind::Interrupted, "interrupted"));
        }
        std::fs::rename(&tmp, dest)
    })();
    interrupt::unregister_temp(&tmp);
    written.map_err(|e| {
        let _ = std::fs::remove_file(&tmp);
        if interrupt::interrupted() {
            return CliError {
                message: "interrupted".into(),
                code: exit::INTERRUPTED,
            };
        }
        CliError::io(format!("{name}: cannot write: {e}"))
    })
}
