//! Fuzz target: see `drivers::c_abi`.
#![no_main]

#[path = "../drivers/mod.rs"]
mod drivers;

libfuzzer_sys::fuzz_target!(|data: &[u8]| drivers::c_abi(data));
