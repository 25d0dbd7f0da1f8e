//! Ctrl-C and SIGTERM: the first signal asks the running work to stop (it then cleans
//! up and exits with code 130); a second one removes the registered temporary files
//! and exits at once.

use std::path::PathBuf;
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::Mutex;

use super::{exit, CliError};

static INTERRUPTED: AtomicBool = AtomicBool::new(false);
static TEMP_FILES: Mutex<Vec<PathBuf>> = Mutex::new(Vec::new());

/// Installs the handler (once; later calls do nothing).
pub fn install() {
    let _ = ctrlc::set_handler(|| {
        if INTERRUPTED.swap(true, Ordering::SeqCst) {
            if let Ok(files) = TEMP_FILES.lock() {
                for f in files.iter() {
                    let _ = std::fs::remove_file(f);
                }
            }
            std::process::exit(exit::INTERRUPTED);
        }
    });
}

/// True once a signal has arrived.
pub fn interrupted() -> bool {
    INTERRUPTED.load(Ordering::Relaxed)
}

/// `Err` with the interrupted exit code once a signal has arrived.
pub fn check() -> Result<(), CliError> {
    if interrupted() {
        Err(error())
    } else {
        Ok(())
    }
}

/// The error of a run a signal ended.
pub fn error() -> CliError {
    CliError {
        message: "interrupted".into(),
        code: exit::INTERRUPTED,
    }
}

/// Remembers a temporary file to delete on a second signal.
pub fn register_temp(path: PathBuf) {
    if let Ok(mut files) = TEMP_FILES.lock() {
        files.push(path);
    }
}

/// Forgets a temporary file (renamed into place or removed).
pub fn unregister_temp(path: &std::path::Path) {
    if let Ok(mut files) = TEMP_FILES.lock() {
        files.retain(|f| f != path);
    }
}
