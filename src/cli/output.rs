//! Safe output files: written to a temporary file beside the destination and renamed
//! into place only when complete, so a failed or interrupted run never leaves a
//! partial file and never clobbers an existing one.

use std::fs::File;
use std::io::{BufWriter, Write};
use std::path::{Path, PathBuf};

use super::{interrupt, CliError};

/// A destination file being written through a temporary sibling.
pub struct AtomicOutput {
    dest: PathBuf,
    temp: PathBuf,
    file: Option<BufWriter<File>>,
}

impl AtomicOutput {
    /// Creates the temporary file now, so an unwritable destination is reported
    /// before any expensive work starts.
    pub fn create(dest: &Path) -> Result<AtomicOutput, CliError> {
        if dest.is_dir() {
            return Err(CliError::io(format!("{}: is a directory", dest.display())));
        }
        let name = dest
            .file_name()
            .ok_or_else(|| CliError::io(format!("{}: not a file name", dest.display())))?;
        let dir = dest
            .parent()
            .filter(|p| !p.as_os_str().is_empty())
            .unwrap_or(Path::new("."));
        let temp = dir.join(format!(
            ".{}.nffrt-tmp-{}",
            name.to_string_lossy(),
            std::process::id()
        ));
        let file = File::create(&temp).map_err(|e| cannot_write(dest.display(), &e))?;
        interrupt::register_temp(temp.clone());
        Ok(AtomicOutput {
            dest: dest.to_path_buf(),
            temp,
            file: Some(BufWriter::new(file)),
        })
    }

    /// A writer into the temporary file.
    pub fn writer(&mut self) -> &mut BufWriter<File> {
        self.file.as_mut().expect("writer used after commit")
    }

    /// Flushes, syncs and renames the temporary file onto the destination.
    pub fn commit(mut self) -> Result<(), CliError> {
        let fail = |e: std::io::Error| cannot_write(self.dest.display(), &e);
        let mut w = self.file.take().expect("committed twice");
        w.flush().map_err(fail)?;
        let f = w.into_inner().map_err(|e| fail(e.into_error()))?;
        f.sync_all().map_err(fail)?;
        drop(f);
        interrupt::check()?;
        std::fs::rename(&self.temp, &self.dest).map_err(fail)?;
        interrupt::unregister_temp(&self.temp);
        Ok(())
    }
}

impl Drop for AtomicOutput {
    fn drop(&mut self) {
        if self.file.take().is_some() {
            let _ = std::fs::remove_file(&self.temp);
            interrupt::unregister_temp(&self.temp);
        }
    }
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
