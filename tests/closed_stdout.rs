//! Command output into a pipe whose reader has gone away (`nffrt info ... | head -1`)
//! ends quietly with success: no panic, no error message.

use std::process::{Command, Stdio};

fn example() -> String {
    concat!(env!("CARGO_MANIFEST_DIR"), "/examples/showcase.nff").to_string()
}

#[test]
fn commands_survive_a_closed_standard_output() {
    for args in [
        vec!["info", "--bvh"],
        vec!["render", "--pixel", "320,240"],
        vec!["bench", "--repeat", "1"],
    ] {
        let mut child = Command::new(env!("CARGO_BIN_EXE_nffrt"))
            .args(&args)
            .arg(example())
            .stdout(Stdio::piped())
            .stderr(Stdio::piped())
            .spawn()
            .unwrap();
        // Close the read end before the program has printed anything.
        drop(child.stdout.take());
        let out = child.wait_with_output().unwrap();
        let stderr = String::from_utf8_lossy(&out.stderr);
        assert!(!stderr.contains("panicked"), "{args:?}: {stderr}");
        assert_eq!(out.status.code(), Some(0), "{args:?}: {stderr}");
    }
}
