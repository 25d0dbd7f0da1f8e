//! Where Open Image Denoise's library is looked for, in order:
//!
//! 1. `$NFFRT_OIDN` ([`ENV_VAR`]): the library file itself, or a folder holding it;
//! 2. the folders a caller adds (the Python module adds the one of the `pyoidn`
//!    package its own interpreter imports);
//! 3. the `pyoidn` package of the Python environments a `pip install pyoidn` most
//!    likely went into: the active virtual environment (`$VIRTUAL_ENV`), the user's
//!    site (`~/.local/lib/python3.*/site-packages`), the system's
//!    (`/usr/local/lib/python3.*/dist-packages`, `/usr/lib/python3/dist-packages`);
//! 4. the system's own search for the library's name (`LD_LIBRARY_PATH`, the
//!    loader's cache), where a package manager or a build from source puts it.
//!
//! pip's `pyoidn` (version 2.x) ships the library with its CPU device and trained
//! weights in `pyoidn/oidn/lib/`.

use std::path::{Path, PathBuf};

/// The environment variable naming the library or its folder.
pub const ENV_VAR: &str = "NFFRT_OIDN";

/// The library's file name, as version 2 installs it.
#[cfg(target_os = "linux")]
pub const LIBRARY: &str = "libOpenImageDenoise.so.2";
/// The library's file name, as version 2 installs it.
#[cfg(target_os = "macos")]
pub const LIBRARY: &str = "libOpenImageDenoise.2.dylib";
/// The library's file name, as version 2 installs it.
#[cfg(not(any(target_os = "linux", target_os = "macos")))]
pub const LIBRARY: &str = "OpenImageDenoise.dll";

/// Where pip's `pyoidn` keeps the library, under the package's folder.
const PYOIDN_LIB: &str = "pyoidn/oidn/lib";

/// The places to try, in order (see the module's text): files that may not exist,
/// then the bare [`LIBRARY`] name for the system's search.
pub fn candidates(extra_dirs: &[PathBuf]) -> Vec<PathBuf> {
    let mut found = Vec::new();
    if let Some(given) = std::env::var_os(ENV_VAR).filter(|v| !v.is_empty()) {
        let given = PathBuf::from(given);
        if given.is_dir() {
            found.push(given.join(LIBRARY));
        } else {
            found.push(given);
        }
    }
    found.extend(extra_dirs.iter().map(|d| d.join(LIBRARY)));
    for site in python_sites() {
        found.push(site.join(PYOIDN_LIB).join(LIBRARY));
    }
    found.push(PathBuf::from(LIBRARY));
    found
}

/// The site-packages folders of the Python environments `pip install pyoidn` most
/// likely went into.
fn python_sites() -> Vec<PathBuf> {
    let mut roots: Vec<PathBuf> = Vec::new();
    if let Some(venv) = std::env::var_os("VIRTUAL_ENV") {
        roots.push(PathBuf::from(venv).join("lib"));
    }
    if let Some(home) = std::env::var_os("HOME") {
        roots.push(PathBuf::from(home).join(".local/lib"));
    }
    roots.push(PathBuf::from("/usr/local/lib"));
    let mut sites = Vec::new();
    for root in roots {
        sites.extend(versioned_sites(&root));
    }
    sites.push(PathBuf::from("/usr/lib/python3/dist-packages"));
    sites
}

/// `ROOT/python3.*/{site,dist}-packages`, the newest Python first.
fn versioned_sites(root: &Path) -> Vec<PathBuf> {
    let Ok(entries) = std::fs::read_dir(root) else {
        return Vec::new();
    };
    let mut pythons: Vec<(u32, PathBuf)> = entries
        .filter_map(Result::ok)
        .filter_map(|e| {
            let name = e.file_name().into_string().ok()?;
            let minor = name.strip_prefix("python3.")?.parse().ok()?;
            Some((minor, e.path()))
        })
        .collect();
    pythons.sort_by_key(|p| std::cmp::Reverse(p.0));
    pythons
        .into_iter()
        .flat_map(|(_, p)| [p.join("site-packages"), p.join("dist-packages")])
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_system_search_comes_last_and_extra_folders_before_the_guesses() {
        let extra = PathBuf::from("/somewhere/pyoidn/oidn/lib");
        let found = candidates(std::slice::from_ref(&extra));
        assert_eq!(found.last(), Some(&PathBuf::from(LIBRARY)));
        let at = found.iter().position(|p| p == &extra.join(LIBRARY)).unwrap();
        // (After $NFFRT_OIDN, when it is set: it comes first.)
        let given = usize::from(std::env::var_os(ENV_VAR).is_some_and(|v| !v.is_empty()));
        assert_eq!(at, given, "{found:?}");
        let guessed = |p: &&PathBuf| p.ends_with(Path::new(PYOIDN_LIB).join(LIBRARY));
        assert!(found.iter().skip(given + 1).any(|p| guessed(&p)), "{found:?}");
    }

    #[test]
    fn sites_are_found_newest_python_first() {
        let root = std::env::temp_dir().join(format!("nffrt-sites-{}", std::process::id()));
        for v in ["python3.9", "python3.12", "python3.11", "perl5"] {
            std::fs::create_dir_all(root.join(v)).unwrap();
        }
        let sites = versioned_sites(&root);
        std::fs::remove_dir_all(&root).unwrap();
        let names: Vec<String> = sites
            .iter()
            .map(|p| p.strip_prefix(&root).unwrap().display().to_string())
            .collect();
        assert_eq!(
            names,
            [
                "python3.12/site-packages",
                "python3.12/dist-packages",
                "python3.11/site-packages",
                "python3.11/dist-packages",
                "python3.9/site-packages",
                "python3.9/dist-packages"
            ]
        );
    }
}
