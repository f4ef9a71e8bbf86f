//! What every entry point does at the boundary: catch panics, record the last error for the
//! calling thread, check pointers and sizes before reading through them.

use super::types::*;
use crate::Error;
use std::any::Any;
use std::cell::RefCell;
use std::panic::{AssertUnwindSafe, catch_unwind};

thread_local! {
    /// Message of the last failed call on this thread; empty after a successful one.
    static LAST_ERROR: RefCell<String> = const { RefCell::new(String::new()) };
}

/// A failed call: its status and what exactly was wrong.
#[derive(Debug)]
pub(crate) struct Failure {
    pub status: DvhStatus,
    pub message: String,
}

impl Failure {
    pub fn new(status: DvhStatus, message: impl Into<String>) -> Failure {
        Failure {
            status,
            message: message.into(),
        }
    }

    pub fn null(name: &str) -> Failure {
        Failure::new(
            DVH_STATUS_NULL_ARGUMENT,
            format!("argument `{name}` is NULL"),
        )
    }

    pub fn invalid(message: impl Into<String>) -> Failure {
        Failure::new(DVH_STATUS_INVALID_ARGUMENT, message)
    }

    /// The error, its message prefixed with what it is about (`"pose_a: ..."`).
    pub fn about(context: &str, e: Error) -> Failure {
        let f = Failure::from(e);
        Failure::new(f.status, format!("{context}: {}", f.message))
    }
}

impl From<Error> for Failure {
    fn from(e: Error) -> Failure {
        Failure::new(status_of(&e), e.to_string())
    }
}

/// The status that reports `e`: an error about one object reports as the error itself.
fn status_of(e: &Error) -> DvhStatus {
    match e {
        Error::NoTriangles
        | Error::PositionsLength { .. }
        | Error::TrianglesLength { .. }
        | Error::TooManyVertices { .. }
        | Error::TooManyTriangles { .. }
        | Error::VertexCountMismatch { .. }
        | Error::ZeroBudget
        | Error::InvalidDistance { .. }
        | Error::UnsupportedMode { .. }
        | Error::ForeignCurves { .. }
        | Error::CurvesKind { .. }
        | Error::GradientLength { .. }
        | Error::InvalidDistanceOption { .. }
        | Error::ResultLength { .. } => DVH_STATUS_INVALID_ARGUMENT,
        Error::NotClosed { .. } => DVH_STATUS_NOT_CLOSED,
        Error::IndexOutOfRange { .. } => DVH_STATUS_INDEX_OUT_OF_RANGE,
        Error::NonFiniteCoordinate { .. }
        | Error::NonFinitePose { .. }
        | Error::NonFinitePoint { .. } => DVH_STATUS_NON_FINITE_COORDINATE,
        Error::NonRigidPose { .. } => DVH_STATUS_NON_RIGID_POSE,
        Error::OutOfMemory { .. } => DVH_STATUS_OUT_OF_MEMORY,
        Error::PoseOutOfRange { .. } | Error::ObjectPoseOutOfRange { .. } => {
            DVH_STATUS_POSE_OUT_OF_RANGE
        }
        Error::UnknownObject { .. }
        | Error::WrongObjectKind { .. }
        | Error::RigidSelfContact { .. }
        | Error::SameObject { .. } => DVH_STATUS_INVALID_ARGUMENT,
        Error::Object { error, .. } | Error::Motion { error, .. } => status_of(error),
    }
}

pub(crate) fn set_last_error(message: &str) {
    // `try_with`: during thread teardown the slot may be gone; the message is then dropped.
    let _ = LAST_ERROR.try_with(|m| {
        let mut m = m.borrow_mut();
        m.clear();
        m.push_str(message);
    });
}

pub(crate) fn with_last_error<R>(f: impl FnOnce(&str) -> R) -> R {
    let mut f = Some(f);
    let mut call = |m: &str| (f.take().expect("called once"))(m);
    match LAST_ERROR.try_with(|m| call(&m.borrow())) {
        Ok(r) => r,
        Err(_) => call(""),
    }
}

fn panic_message(payload: &(dyn Any + Send)) -> &str {
    if let Some(s) = payload.downcast_ref::<&str>() {
        s
    } else if let Some(s) = payload.downcast_ref::<String>() {
        s
    } else {
        "(no message)"
    }
}

/// Runs the body of a fallible entry point: a panic becomes `DVH_STATUS_INTERNAL_PANIC`, and the
/// thread's last error is set (or cleared on success).
pub(crate) fn guard(body: impl FnOnce() -> Result<(), Failure>) -> DvhStatus {
    match catch_unwind(AssertUnwindSafe(body)) {
        Ok(Ok(())) => {
            set_last_error("");
            DVH_STATUS_OK
        }
        Ok(Err(failure)) => {
            set_last_error(&failure.message);
            failure.status
        }
        Err(payload) => {
            set_last_error(&format!(
                "internal panic in dvh: {}",
                panic_message(payload.as_ref())
            ));
            DVH_STATUS_INTERNAL_PANIC
        }
    }
}

/// Runs the body of an entry point that returns a value rather than a status: a panic yields
/// `fallback` and sets the last error.
pub(crate) fn guard_value<T>(fallback: T, body: impl FnOnce() -> T) -> T {
    match catch_unwind(AssertUnwindSafe(body)) {
        Ok(v) => v,
        Err(payload) => {
            set_last_error(&format!(
                "internal panic in dvh: {}",
                panic_message(payload.as_ref())
            ));
            fallback
        }
    }
}

/// A slice of `len` elements at `ptr`, after checking what can be checked: not NULL, aligned,
/// and a size that fits in memory.
///
/// # Safety
/// If `ptr` is non-NULL it must point to `len` initialised elements, readable and not written by
/// anyone else for `'a`.
pub(crate) unsafe fn slice_from<'a, T>(
    ptr: *const T,
    len: usize,
    name: &str,
) -> Result<&'a [T], Failure> {
    if ptr.is_null() {
        return Err(Failure::null(name));
    }
    if !ptr.is_aligned() {
        return Err(Failure::invalid(format!(
            "argument `{name}` is not aligned to {} bytes",
            std::mem::align_of::<T>()
        )));
    }
    if len
        .checked_mul(std::mem::size_of::<T>())
        .is_none_or(|bytes| bytes > isize::MAX as usize)
    {
        return Err(Failure::invalid(format!(
            "argument `{name}`: {len} elements do not fit in memory"
        )));
    }
    // SAFETY: non-NULL and aligned (checked), size within isize::MAX (checked); the caller
    // guarantees `len` readable, initialised elements for 'a.
    Ok(unsafe { std::slice::from_raw_parts(ptr, len) })
}

/// A writable slice of `len` elements at `ptr`, checked as [`slice_from`] checks.
///
/// # Safety
/// If `ptr` is non-NULL it must point to `len` initialised elements, writable and used by no
/// one else for `'a`.
pub(crate) unsafe fn slice_from_mut<'a, T>(
    ptr: *mut T,
    len: usize,
    name: &str,
) -> Result<&'a mut [T], Failure> {
    // SAFETY: the checks are `slice_from`'s; the caller's contract gives write access.
    let checked = unsafe { slice_from(ptr.cast_const(), len, name) }?;
    // SAFETY: as above: `checked` covers exactly the caller's `len` writable elements.
    Ok(unsafe { std::slice::from_raw_parts_mut(checked.as_ptr().cast_mut(), len) })
}

/// The Rust value paired with `value` of the C enumeration field `options->{field}` (whose
/// constants are `{family}_*`, numbered consecutively), or an invalid-argument failure naming the
/// field, the value and the valid range.
pub(crate) fn choice<T: Copy>(
    field: &str,
    family: &str,
    value: u32,
    choices: &[(u32, T)],
) -> Result<T, Failure> {
    if let Some(&(_, t)) = choices.iter().find(|(v, _)| *v == value) {
        return Ok(t);
    }
    let low = choices.iter().map(|c| c.0).min().unwrap_or(0);
    let high = choices.iter().map(|c| c.0).max().unwrap_or(0);
    let range = if high == low + 1 {
        format!("{low} or {high}")
    } else {
        format!("{low} to {high}")
    };
    Err(Failure::invalid(format!(
        "options->{field} = {value} is not a {family}_* value ({range})"
    )))
}

/// `3 * count`, or an invalid-argument failure naming `name`.
pub(crate) fn times_three(count: usize, name: &str) -> Result<usize, Failure> {
    count
        .checked_mul(3)
        .ok_or_else(|| Failure::invalid(format!("argument `{name}` = {count} is too large")))
}

/// Writes `value` to the optional out-parameter `out` unless it is NULL.
///
/// # Safety
/// `out` is NULL or writable.
pub(crate) unsafe fn write_unless_null<T>(out: *mut T, value: T) {
    if !out.is_null() {
        // SAFETY: non-NULL and writable (contract).
        unsafe { out.write(value) };
    }
}

/// A box allocated without aborting on failure.
pub(crate) fn try_box<T>(value: T) -> Result<*mut T, Failure> {
    let layout = std::alloc::Layout::new::<T>();
    // SAFETY: T is a non-zero-sized type (every boxed type here holds vectors), so the layout has
    // a non-zero size as `alloc` requires.
    let ptr = unsafe { std::alloc::alloc(layout) }.cast::<T>();
    if ptr.is_null() {
        return Err(Failure::new(
            DVH_STATUS_OUT_OF_MEMORY,
            format!("out of memory: could not allocate {} bytes", layout.size()),
        ));
    }
    // SAFETY: freshly allocated with T's layout, so valid for a write of T; `Box::from_raw`
    // accepts it later because the global allocator and `Layout::new::<T>()` are what Box uses.
    unsafe { ptr.write(value) };
    Ok(ptr)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn panics_become_a_status_and_a_message() {
        let status = guard(|| panic!("boom {}", 42));
        assert_eq!(status, DVH_STATUS_INTERNAL_PANIC);
        with_last_error(|m| assert_eq!(m, "internal panic in dvh: boom 42"));
        assert_eq!(guard(|| Ok(())), DVH_STATUS_OK);
        with_last_error(|m| assert_eq!(m, ""));
        assert_eq!(guard_value(7, || -> i32 { panic!("static message") }), 7);
        with_last_error(|m| assert_eq!(m, "internal panic in dvh: static message"));
    }

    #[test]
    fn every_error_maps_to_its_status() {
        let f = Failure::from(Error::IndexOutOfRange {
            triangle: 1,
            corner: 2,
            index: 9,
            vertex_count: 3,
        });
        assert_eq!(f.status, DVH_STATUS_INDEX_OUT_OF_RANGE);
        assert_eq!(
            Failure::from(Error::NoTriangles).status,
            DVH_STATUS_INVALID_ARGUMENT
        );
        assert_eq!(
            Failure::from(Error::OutOfMemory { bytes: 1 }).status,
            DVH_STATUS_OUT_OF_MEMORY
        );
        let f = Failure::about(
            "pose_b",
            Error::NonRigidPose {
                deviation: 0.1,
                determinant: 1.0,
            },
        );
        assert_eq!(f.status, DVH_STATUS_NON_RIGID_POSE);
        assert!(
            f.message
                .starts_with("pose_b: pose rotation is not a rotation")
        );
    }

    #[test]
    fn slices_are_checked() {
        let v = [1.0f64, 2.0, 3.0];
        // SAFETY: a valid array of 3 elements.
        assert_eq!(unsafe { slice_from(v.as_ptr(), 3, "v") }.unwrap(), &v);
        // SAFETY: NULL is rejected before any read.
        let e = unsafe { slice_from::<f64>(std::ptr::null(), 3, "v") }.unwrap_err();
        assert_eq!(e.status, DVH_STATUS_NULL_ARGUMENT);
        // SAFETY: a misaligned pointer is rejected before any read.
        let e = unsafe { slice_from(v.as_ptr().cast::<u8>().add(1).cast::<f64>(), 1, "v") }
            .unwrap_err();
        assert_eq!(e.status, DVH_STATUS_INVALID_ARGUMENT);
        assert!(e.message.contains("aligned"));
        // SAFETY: an impossible size is rejected before any read.
        let e = unsafe { slice_from(v.as_ptr(), usize::MAX / 4, "v") }.unwrap_err();
        assert!(e.message.contains("do not fit"));
    }
}
