//! The C ABI, exported from the `cdylib` and `staticlib` builds and declared in `include/dvh.h`
//! (generated from this module by cbindgen; `tests/header.rs` checks the committed header).
//!
//! Conventions, following the project's C ABI rules: names `dvh_<object>_<verb>`, types
//! `Dvh<Name>`, constants `DVH_<ENUM>_<VALUE>`; every fallible call returns a `DvhStatus`, writes
//! its out-parameters (last in the argument list) only on success, and leaves a message for
//! `dvh_last_error_message`; handles are opaque, created by `_create`/`_new`, released by
//! `_free`, which accept NULL; every entry point checks its pointers and catches panics. All the
//! crate's `unsafe` code is here, each block with its justification.

mod access;
mod boundary;
mod calls;
mod ccd;
mod curves;
mod distance;
mod handles;
mod mesh;
mod nearest;
mod query;
mod results;
mod scene;
mod types;

pub use ccd::*;
pub use curves::*;
pub use distance::*;
pub use handles::*;
pub use mesh::*;
pub use nearest::*;
pub use query::*;
pub use scene::*;
pub use types::*;

use boundary::{guard_value, with_last_error};
use std::ffi::{CStr, c_char};

/// The name of a status code, such as `"DVH_STATUS_NULL_ARGUMENT"`, or `"DVH_STATUS_UNKNOWN"`.
/// A static string: never freed.
///
/// Thread safety: any thread, any time.
#[unsafe(no_mangle)]
pub extern "C" fn dvh_status_name(status: DvhStatus) -> *const c_char {
    guard_value(c"DVH_STATUS_UNKNOWN".as_ptr(), || {
        status_name(status).as_ptr()
    })
}

fn status_name(status: DvhStatus) -> &'static CStr {
    match status {
        DVH_STATUS_OK => c"DVH_STATUS_OK",
        DVH_STATUS_NULL_ARGUMENT => c"DVH_STATUS_NULL_ARGUMENT",
        DVH_STATUS_INVALID_ARGUMENT => c"DVH_STATUS_INVALID_ARGUMENT",
        DVH_STATUS_NON_FINITE_COORDINATE => c"DVH_STATUS_NON_FINITE_COORDINATE",
        DVH_STATUS_INDEX_OUT_OF_RANGE => c"DVH_STATUS_INDEX_OUT_OF_RANGE",
        DVH_STATUS_NON_RIGID_POSE => c"DVH_STATUS_NON_RIGID_POSE",
        DVH_STATUS_OUT_OF_MEMORY => c"DVH_STATUS_OUT_OF_MEMORY",
        DVH_STATUS_INTERNAL_PANIC => c"DVH_STATUS_INTERNAL_PANIC",
        DVH_STATUS_POSE_OUT_OF_RANGE => c"DVH_STATUS_POSE_OUT_OF_RANGE",
        DVH_STATUS_INVARIANT_BROKEN => c"DVH_STATUS_INVARIANT_BROKEN",
        DVH_STATUS_BUSY => c"DVH_STATUS_BUSY",
        DVH_STATUS_NOT_CLOSED => c"DVH_STATUS_NOT_CLOSED",
        _ => c"DVH_STATUS_UNKNOWN",
    }
}

/// Copies the message of the last failed call on the calling thread (which index, which value,
/// which argument was wrong) into `buffer`, NUL-terminated, truncated to `capacity - 1` bytes.
/// Returns the message's full length in bytes, without the NUL: call with `capacity` 0 (and
/// `buffer` NULL) to size a buffer. A successful call clears the message (length 0).
///
/// Thread safety: any thread; each thread has its own message.
///
/// # Safety
/// `buffer` is NULL or writable for `capacity` bytes.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn dvh_last_error_message(buffer: *mut c_char, capacity: usize) -> usize {
    guard_value(0, || {
        with_last_error(|message| {
            let bytes = message.as_bytes();
            if !buffer.is_null() && capacity > 0 {
                let n = bytes.len().min(capacity - 1);
                // SAFETY: `buffer` is writable for `capacity` bytes (contract) and n + 1 <= capacity;
                // the message is a separate Rust allocation, so the ranges do not overlap.
                unsafe {
                    std::ptr::copy_nonoverlapping(bytes.as_ptr().cast::<c_char>(), buffer, n);
                    buffer.add(n).write(0);
                }
            }
            bytes.len()
        })
    })
}

/// The library's version, such as `"0.3.0"`. A static string: never freed.
///
/// Thread safety: any thread, any time.
#[unsafe(no_mangle)]
pub extern "C" fn dvh_version() -> *const c_char {
    const VERSION: &CStr =
        match CStr::from_bytes_with_nul(concat!(env!("CARGO_PKG_VERSION"), "\0").as_bytes()) {
            Ok(v) => v,
            Err(_) => panic!("the package version contains a NUL byte"),
        };
    guard_value(VERSION.as_ptr(), || VERSION.as_ptr())
}
