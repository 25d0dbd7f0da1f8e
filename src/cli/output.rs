//! Safe output files for the command line: [`nffrt::output::AtomicFile`] (a
//! temporary beside the destination, renamed into place only when complete, so a
//! failed or interrupted run never leaves a partial file and never clobbers an
//! existing one), its temporary registered for removal on a second Ctrl-C, and its
//! errors worded as every command words them.

use std::io::Write;
use std::path::Path;

use nffrt::output::AtomicFile;

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

/// The one error for an output that cannot be written: `NAME: cannot write output:
/// REASON`.
pub fn cannot_write(name: impl std::fmt::Display, e: &std::io::Error) -> CliError {
    CliError::io(format!("{name}: cannot write output: {}", brief(e)))
}

/// A short description of an I/O error.
pub fn brief(e: &std::io::Error) -> String {
    nffrt::io_reason(e)
}
