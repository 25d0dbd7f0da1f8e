//! Any bytes into the NFF parser: it must return a scene or an error, never panic,
//! hang or allocate out of proportion to the input. A parsed scene must survive
//! `write_nff` and a second parse, and writing that again must give the same text.

#![no_main]

use libfuzzer_sys::fuzz_target;
use nffrt::nff::{parse_bytes, write_nff};

fuzz_target!(|data: &[u8]| {
    let Ok(scene) = parse_bytes(data) else {
        return;
    };
    let mut first = Vec::new();
    write_nff(&scene, &mut first).expect("writing to memory cannot fail");
    let again = parse_bytes(&first).unwrap_or_else(|e| {
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
    write_nff(&again, &mut second).expect("writing to memory cannot fail");
    if first != second {
        let (a, b) = (String::from_utf8_lossy(&first), String::from_utf8_lossy(&second));
        let diff = a.lines().zip(b.lines()).enumerate().find(|(_, (x, y))| x != y);
        panic!(
            "write is not a fixpoint after one round trip; first difference (line, first, second): {diff:?}"
        );
    }
});
