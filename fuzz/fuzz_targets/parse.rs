//! Any bytes into the NFF parser: it must return a scene or an error, never panic,
//! hang or allocate out of proportion to the input. A parsed scene must survive
//! `write_nff` and a second parse, and writing that again must give the same text.

#![no_main]

mod common;

use libfuzzer_sys::fuzz_target;
use nffrt::nff::{parse_bytes, write_nff};

fuzz_target!(|data: &[u8]| {
    let Ok(scene) = parse_bytes(data) else {
        return;
    };
    common::assert_round_trip(&scene, parse_bytes, |s, w| write_nff(s, w));
});
