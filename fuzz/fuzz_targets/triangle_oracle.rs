//! Fuzz target: see `drivers::triangle_oracle`.
#![no_main]

#[path = "../drivers/mod.rs"]
mod drivers;

libfuzzer_sys::fuzz_target!(|data: &[u8]| drivers::triangle_oracle(data));
