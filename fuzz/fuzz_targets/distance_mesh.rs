//! Fuzz target: see `drivers::distance_mesh`.
#![no_main]

#[path = "../drivers/mod.rs"]
mod drivers;

libfuzzer_sys::fuzz_target!(|data: &[u8]| drivers::distance_mesh(data));
