//! Files written whole or not at all: the bytes go to a temporary file beside the
//! destination, which is flushed, synced and renamed over the destination only once
//! complete. A failed or abandoned write (an error, a dropped [`AtomicFile`]) removes
//! the temporary and leaves the destination as it was. The command line's images,
//! scenes and statistics and the Python module's `save` all go through here.
//!
//! Each temporary is made with `create_new` (`O_EXCL`) under a name unique to the
//! call — `.NAME.nffrt-tmp-PID-COUNT-NANOS` — so two writers of one destination, in
//! one process or in two, never share or truncate each other's temporary; the last
//! to commit wins, whole.

use std::fs::{File, OpenOptions};
use std::io::{self, BufWriter, Write};
use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicU64, Ordering};
use std::time::{SystemTime, UNIX_EPOCH};

/// The mark in every temporary's name (what a cleanup or a test looks for).
pub const TEMP_MARK: &str = ".nffrt-tmp-";

/// How many names are tried before giving up (each taken one is skipped).
const NAME_TRIES: u32 = 16;

/// A destination file being written through a temporary sibling; [`AtomicFile::commit`]
/// puts it in place, dropping it without a commit removes the temporary.
pub struct AtomicFile {
    dest: PathBuf,
    temp: PathBuf,
    file: Option<BufWriter<File>>,
}

impl AtomicFile {
    /// Creates the temporary file now, so that an unwritable destination (a missing
    /// folder, a directory, no permission) is reported before any expensive work.
    pub fn create(dest: &Path) -> io::Result<AtomicFile> {
        if dest.is_dir() {
            return Err(io::Error::new(io::ErrorKind::IsADirectory, "is a directory"));
        }
        let name = dest
            .file_name()
            .ok_or_else(|| io::Error::new(io::ErrorKind::InvalidInput, "not a file name"))?;
        let dir = dest
            .parent()
            .filter(|p| !p.as_os_str().is_empty())
            .unwrap_or(Path::new("."));
        let mut tries = 0;
        loop {
            let temp = dir.join(format!(
                ".{}{TEMP_MARK}{}",
                name.to_string_lossy(),
                unique_suffix()
            ));
            match OpenOptions::new().write(true).create_new(true).open(&temp) {
                Ok(file) => {
                    return Ok(AtomicFile {
                        dest: dest.to_path_buf(),
                        temp,
                        file: Some(BufWriter::new(file)),
                    })
                }
                Err(e) if e.kind() == io::ErrorKind::AlreadyExists && tries < NAME_TRIES => tries += 1,
                Err(e) => return Err(e),
            }
        }
    }

    /// The destination.
    pub fn dest(&self) -> &Path {
        &self.dest
    }

    /// The temporary file being written (removed by a commit or a drop).
    pub fn temp_path(&self) -> &Path {
        &self.temp
    }

    /// Flushes and syncs the temporary and renames it onto the destination. On an
    /// error the temporary is removed and the destination left as it was.
    pub fn commit(mut self) -> io::Result<()> {
        let w = self.file.take().expect("an uncommitted file has its writer");
        let file = w.into_inner().map_err(|e| e.into_error())?;
        let done = file
            .sync_all()
            .and_then(|()| std::fs::rename(&self.temp, &self.dest));
        if done.is_err() {
            let _ = std::fs::remove_file(&self.temp);
        }
        done
    }

    fn writer(&mut self) -> &mut BufWriter<File> {
        self.file.as_mut().expect("an uncommitted file has its writer")
    }
}

impl Write for AtomicFile {
    fn write(&mut self, buf: &[u8]) -> io::Result<usize> {
        self.writer().write(buf)
    }

    fn write_all(&mut self, buf: &[u8]) -> io::Result<()> {
        self.writer().write_all(buf)
    }

    fn flush(&mut self) -> io::Result<()> {
        self.writer().flush()
    }
}

impl Drop for AtomicFile {
    fn drop(&mut self) {
        // Not committed (an error or an abandoned write): the temporary goes.
        if self.file.take().is_some() {
            let _ = std::fs::remove_file(&self.temp);
        }
    }
}

/// Writes `bytes` to `dest` atomically (see the module docs).
pub fn write_atomically(dest: &Path, bytes: &[u8]) -> io::Result<()> {
    let mut file = AtomicFile::create(dest)?;
    file.write_all(bytes)?;
    file.commit()
}

/// `PID-COUNT-NANOS`: the process, a count of this process's temporaries, and the
/// clock, so a name is not reused within a process nor, in practice, across them.
fn unique_suffix() -> String {
    static COUNT: AtomicU64 = AtomicU64::new(0);
    let count = COUNT.fetch_add(1, Ordering::Relaxed);
    let nanos = SystemTime::now()
        .duration_since(UNIX_EPOCH)
        .map(|d| d.subsec_nanos())
        .unwrap_or(0);
    format!("{}-{count}-{nanos}", std::process::id())
}

#[cfg(test)]
mod tests {
    use super::*;

    fn scratch(name: &str) -> PathBuf {
        let dir = std::env::temp_dir().join(format!("nffrt-output-{name}-{}", std::process::id()));
        let _ = std::fs::remove_dir_all(&dir);
        std::fs::create_dir_all(&dir).unwrap();
        dir
    }

    fn temporaries(dir: &Path) -> Vec<String> {
        std::fs::read_dir(dir)
            .unwrap()
            .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
            .filter(|n| n.contains(TEMP_MARK))
            .collect()
    }

    #[test]
    fn two_writers_of_one_destination_keep_their_own_temporaries() {
        let dir = scratch("two");
        let dest = dir.join("x.png");
        let mut a = AtomicFile::create(&dest).unwrap();
        let mut b = AtomicFile::create(&dest).unwrap();
        assert_ne!(a.temp_path(), b.temp_path());
        // Interleaved writes: neither truncates nor adds to the other's bytes.
        a.write_all(b"first writer, ").unwrap();
        b.write_all(b"second").unwrap();
        a.write_all(b"whole").unwrap();
        b.commit().unwrap();
        assert_eq!(std::fs::read(&dest).unwrap(), b"second");
        a.commit().unwrap();
        assert_eq!(std::fs::read(&dest).unwrap(), b"first writer, whole");
        assert!(temporaries(&dir).is_empty(), "{:?}", temporaries(&dir));
        std::fs::remove_dir_all(&dir).unwrap();
    }

    #[test]
    fn many_threads_writing_one_destination_leave_one_whole_file() {
        let dir = scratch("threads");
        let dest = dir.join("x.nff");
        let contents: Vec<Vec<u8>> = (0..8u8).map(|i| vec![b'a' + i; 100_000]).collect();
        std::thread::scope(|s| {
            for c in &contents {
                let dest = &dest;
                s.spawn(move || write_atomically(dest, c).unwrap());
            }
        });
        let got = std::fs::read(&dest).unwrap();
        assert!(contents.contains(&got), "a mixed or partial file");
        assert!(temporaries(&dir).is_empty(), "{:?}", temporaries(&dir));
        std::fs::remove_dir_all(&dir).unwrap();
    }

    #[test]
    fn a_dropped_write_leaves_the_destination_as_it_was() {
        let dir = scratch("drop");
        let dest = dir.join("keep.png");
        std::fs::write(&dest, b"the user's file").unwrap();
        let mut f = AtomicFile::create(&dest).unwrap();
        f.write_all(b"half a pic").unwrap();
        assert_eq!(temporaries(&dir).len(), 1);
        drop(f);
        assert_eq!(std::fs::read(&dest).unwrap(), b"the user's file");
        assert!(temporaries(&dir).is_empty());
        std::fs::remove_dir_all(&dir).unwrap();
    }

    #[test]
    fn unwritable_destinations_are_refused_at_creation() {
        let dir = scratch("refused");
        let reason = |dest: &Path| crate::io_reason(&AtomicFile::create(dest).err().unwrap());
        assert_eq!(reason(&dir.join("missing/x.png")), "no such file or directory");
        assert_eq!(reason(&dir), "is a directory");
        assert!(temporaries(&dir).is_empty());
        std::fs::remove_dir_all(&dir).unwrap();
    }
}
