//! Safe output files for the command line: [`nffrt::output::AtomicFile`] (a
//! temporary beside the destination, renamed into place only when complete, so a
//! failed or interrupted run never leaves a partial file and never clobbers an
//! existing one), its temporary registered for removal on a second Ctrl-C, and its
//! errors worded as every command words them.

use std::io::{self, BufWriter, Write};
use std::path::Path;

use nffrt::output::AtomicFile;

use super::image_out::is_stdout;
use super::{interrupt, CliError};

/// A destination file being written through a temporary sibling.
pub struct AtomicOutput {
    /// `None` once committed.
    file: Option<AtomicFile>,
}

impl AtomicOutput {
    /// Creates the temporary file now, so an unwritable destination is reported
    /// before any expensive work starts.
    pub fn create(dest: &Path) -> Result<AtomicOutput, CliError> {
        let file = AtomicFile::create(dest).map_err(|e| cannot_write(dest.display(), &e))?;
        interrupt::register_temp(file.temp_path().to_path_buf());
        Ok(AtomicOutput { file: Some(file) })
    }

    /// A writer into the temporary file.
    pub fn writer(&mut self) -> &mut impl Write {
        self.file.as_mut().expect("written before the commit")
    }

    /// Puts the complete file in place, unless a signal has asked the run to stop.
    pub fn commit(mut self) -> Result<(), CliError> {
        interrupt::check()?;
        let file = self.file.take().expect("committed once");
        let dest = file.dest().display().to_string();
        let temp = file.temp_path().to_path_buf();
        let done = file.commit();
        interrupt::unregister_temp(&temp);
        done.map_err(|e| cannot_write(dest, &e))
    }
}

impl Drop for AtomicOutput {
    fn drop(&mut self) {
        if let Some(file) = self.file.take() {
            let temp = file.temp_path().to_path_buf();
            drop(file); // removes the temporary
            interrupt::unregister_temp(&temp);
        }
    }
}

/// Writes data (an image, scene text, JSON) to standard output through `write`.
/// Any failure, a reader that closed the pipe early included, is an output error:
/// the data did not all arrive. (Reports for people, `outln!`, end quietly instead.)
pub fn write_stdout(write: impl FnOnce(&mut dyn Write) -> io::Result<()>) -> Result<(), CliError> {
    let mut out = BufWriter::with_capacity(1 << 16, io::stdout().lock());
    write(&mut out)
        .and_then(|()| out.flush())
        .map_err(|e| cannot_write("standard output", &e))
}

/// The one error for an output that cannot be written: `NAME: cannot write output:
/// REASON`.
pub fn cannot_write(name: impl std::fmt::Display, e: &std::io::Error) -> CliError {
    CliError::io(format!("{name}: cannot write output: {}", brief(e)))
}

/// A short description of an I/O error.
pub fn brief(e: &std::io::Error) -> String {
    nffrt::io_reason(e)
}

/// One file a command writes, as the command line named it: `-o a.png`, `the
/// default output a.png`, `--stats-json s.json`.
pub struct Named<'a> {
    /// The path.
    pub path: &'a Path,
    /// How it was named, for the message.
    pub named: String,
}

impl<'a> Named<'a> {
    /// The file given to `flag`.
    pub fn flag(flag: &str, path: &'a Path) -> Named<'a> {
        Named {
            path,
            named: format!("{flag} {}", path.display()),
        }
    }
}

/// Refuses outputs that would replace one of the command's inputs (`(path, what it
/// is)`, e.g. the scene file) or each other: the same file, whatever it is called
/// (compared by device and inode on Unix), or the same name for two outputs. `-`
/// (standard input or output) is no file here. A usage error, before anything is read or
/// written.
pub fn refuse_overwriting(outputs: &[Named<'_>], inputs: &[(&Path, &str)]) -> Result<(), CliError> {
    let outputs: Vec<&Named<'_>> = outputs.iter().filter(|o| !is_stdout(o.path)).collect();
    for out in &outputs {
        for &(input, what) in inputs.iter().filter(|(p, _)| !is_stdout(p)) {
            if same_file(out.path, input) {
                let also = if out.path == input { "" } else { " (the same file)" };
                return Err(CliError::usage(format!(
                    "{} would overwrite {what} {}{also}; name another output",
                    out.named,
                    input.display()
                )));
            }
        }
    }
    for (i, a) in outputs.iter().enumerate() {
        if let Some(b) = outputs[i + 1..]
            .iter()
            .find(|b| a.path == b.path || same_file(a.path, b.path))
        {
            return Err(CliError::usage(format!(
                "{} and {} name the same file; give each its own",
                a.named, b.named
            )));
        }
    }
    Ok(())
}

/// True if both paths exist and are one file (the same device and inode on Unix;
/// elsewhere, the same canonical path).
fn same_file(a: &Path, b: &Path) -> bool {
    #[cfg(unix)]
    {
        use std::os::unix::fs::MetadataExt;
        match (std::fs::metadata(a), std::fs::metadata(b)) {
            (Ok(x), Ok(y)) => (x.dev(), x.ino()) == (y.dev(), y.ino()),
            _ => false,
        }
    }
    #[cfg(not(unix))]
    {
        match (a.canonicalize(), b.canonicalize()) {
            (Ok(x), Ok(y)) => x == y,
            _ => false,
        }
    }
}
