//! Fuzz target: see `drivers::ccd_mesh`.
#![no_main]

#[path = "../drivers/mod.rs"]
mod drivers;

libfuzzer_sys::fuzz_target!(|data: &[u8]| drivers::ccd_mesh(data));
