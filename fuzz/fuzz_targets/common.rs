//! What the targets share: the one-thread pool their renders run on (fuzzing runs
//! one job beside other work, and rayon's global pool would take every core), and
//! the write-and-parse-back check of a parsed scene.

// Each target uses a different subset of it.
#![allow(dead_code)]

use std::sync::OnceLock;

/// A pool of one thread, made once.
pub fn one_thread() -> &'static rayon::ThreadPool {
    static POOL: OnceLock<rayon::ThreadPool> = OnceLock::new();
    POOL.get_or_init(|| {
        rayon::ThreadPoolBuilder::new()
            .num_threads(1)
            .build()
            .expect("a one-thread pool starts")
    })
}

/// Writes `scene` with `write`, parses that with `parse` and writes the result
/// again: the second parse must succeed with the same primitive and light counts
/// and camera, and the second text must be the first (writing is a fixpoint after
/// one round trip).
pub fn assert_round_trip(
    scene: &nffrt::Scene,
    parse: impl Fn(&[u8]) -> Result<nffrt::Scene, nffrt::nff::ParseError>,
    write: impl Fn(&nffrt::Scene, &mut Vec<u8>) -> std::io::Result<()>,
) {
    let mut first = Vec::new();
    write(scene, &mut first).expect("writing to memory cannot fail");
    let again = parse(&first).unwrap_or_else(|e| {
        panic!(
            "written scene does not parse: {e}\n{}",
            String::from_utf8_lossy(&first)
        )
    });
    assert_eq!(
        scene.primitive_count(),
        again.primitive_count(),
        "primitive count changed"
    );
    assert_eq!(scene.lights.len(), again.lights.len(), "light count changed");
    assert_eq!(scene.view, again.view, "camera changed");
    let mut second = Vec::new();
    write(&again, &mut second).expect("writing to memory cannot fail");
    if first != second {
        let (a, b) = (String::from_utf8_lossy(&first), String::from_utf8_lossy(&second));
        let diff = a.lines().zip(b.lines()).enumerate().find(|(_, (x, y))| x != y);
        panic!(
            "write is not a fixpoint after one round trip; first difference (line, first, second): {diff:?}"
        );
    }
}
