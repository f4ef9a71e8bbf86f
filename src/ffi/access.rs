//! Misuse from C, detected: which calls may run on one handle at a time.
//!
//! Rust's borrows keep a refit from running beside a query; C has only documentation. Each
//! handle carries an [`Access`] state, taken atomically at every entry point that reads or
//! changes the object: any number of readers, or one writer. A call that would break the rule
//! is refused with `DVH_STATUS_BUSY` (which call, on which argument) instead of racing: the
//! object is not touched, so nothing is lost, and the caller may retry. A change interrupted by
//! an internal panic leaves the object refused for good (its state half-updated).
//!
//! Each handle also carries a tag naming its kind. A pointer to something else (another
//! allocator's memory, a different kind of handle) or to a handle already released is refused
//! when the tag read through it is not the live tag; this is best effort: memory that was freed
//! may have been reused, and reading it is outside what C or Rust define, so such a check can
//! only ever catch some of these mistakes (see `ROBUSTNESS.md`).

use super::boundary::{Failure, set_last_error};
use super::types::{DVH_STATUS_BUSY, DVH_STATUS_INTERNAL_PANIC, DVH_STATUS_INVALID_ARGUMENT};
use std::cell::UnsafeCell;
use std::ops::{Deref, DerefMut};
use std::sync::atomic::{AtomicU32, AtomicU64, Ordering};

/// Set while a call that changes the object runs.
const WRITER: u32 = 1 << 31;
/// Set for good when a change panicked: the object may be half-updated.
const POISONED: u32 = 1 << 30;
/// The readers' count, in the low bits.
const READERS: u32 = POISONED - 1;

/// Readers-or-one-writer state of one handle.
#[derive(Debug, Default)]
pub(crate) struct Access(AtomicU32);

impl Access {
    /// Starts a call (`call`, the entry point) that only reads the object (`what` names it in
    /// messages: "DvhMesh `a`"). Refused while a change runs.
    pub fn read(&self, what: &dyn Fn() -> String, call: &str) -> Result<Reading<'_>, Failure> {
        // One atomic add on the uncontended path: as cheap as a check can be.
        let before = self.0.fetch_add(1, Ordering::Acquire);
        if before & (WRITER | POISONED) != 0 || before & READERS == READERS {
            self.0.fetch_sub(1, Ordering::Release);
            return Err(refusal(before, what, call));
        }
        Ok(Reading(&self.0))
    }

    /// Starts a call that changes the object. Refused while any other call on it runs.
    pub fn write(&self, what: &dyn Fn() -> String, call: &str) -> Result<Writing<'_>, Failure> {
        match self
            .0
            .compare_exchange(0, WRITER, Ordering::Acquire, Ordering::Relaxed)
        {
            Ok(_) => Ok(Writing(&self.0)),
            Err(now) => Err(refusal(now, what, call)),
        }
    }
}

/// Why a call on an object in state `state` is refused.
#[cold]
fn refusal(state: u32, what: &dyn Fn() -> String, call: &str) -> Failure {
    let what = what();
    if state & POISONED != 0 {
        return Failure::new(
            DVH_STATUS_INTERNAL_PANIC,
            format!(
                "{what} is unusable: an internal panic interrupted an earlier call that changed it"
            ),
        );
    }
    let running = if state & WRITER != 0 {
        "a call that changes it is running on another thread".to_string()
    } else {
        let n = state & READERS;
        format!("{n} call(s) reading it are running on other threads")
    };
    Failure::new(
        DVH_STATUS_BUSY,
        format!("{call}: {what} is busy: {running}; it was not touched"),
    )
}

/// A reading call in progress; ends when dropped.
pub(crate) struct Reading<'a>(&'a AtomicU32);

impl Drop for Reading<'_> {
    fn drop(&mut self) {
        self.0.fetch_sub(1, Ordering::Release);
    }
}

/// A changing call in progress; ends when dropped, poisoning the object if it panicked.
pub(crate) struct Writing<'a>(&'a AtomicU32);

impl Drop for Writing<'_> {
    fn drop(&mut self) {
        // Clear the writer bit alone, never store: a refused reader may have added its 1 and
        // not yet taken it back, and a store would make its late subtraction wrap the state.
        let end = if std::thread::panicking() {
            WRITER | POISONED
        } else {
            WRITER
        };
        self.0.fetch_xor(end, Ordering::Release);
    }
}

/// A field of every handle: which kind it is while it lives.
#[derive(Debug)]
#[repr(transparent)]
pub(crate) struct Tag(AtomicU64);

/// Tags of live handles ("dvh" and the kind, as bytes) and of released ones.
pub(crate) const MESH_TAG: u64 = u64::from_le_bytes(*b"dvh:mesh");
pub(crate) const SCENE_TAG: u64 = u64::from_le_bytes(*b"dvh:scen");
pub(crate) const PAIRS_TAG: u64 = u64::from_le_bytes(*b"dvh:pair");
pub(crate) const CONTACTS_TAG: u64 = u64::from_le_bytes(*b"dvh:cont");
pub(crate) const IMPACTS_TAG: u64 = u64::from_le_bytes(*b"dvh:impa");
pub(crate) const NEAR_PAIRS_TAG: u64 = u64::from_le_bytes(*b"dvh:near");
pub(crate) const SCENE_IMPACTS_TAG: u64 = u64::from_le_bytes(*b"dvh:simp");
pub(crate) const SCENE_NEAR_PAIRS_TAG: u64 = u64::from_le_bytes(*b"dvh:snea");
pub(crate) const CURVES_TAG: u64 = u64::from_le_bytes(*b"dvh:curv");
const FREED_TAG: u64 = u64::from_le_bytes(*b"dvh:free");

impl Tag {
    /// A live handle's tag.
    pub const fn new(tag: u64) -> Tag {
        Tag(AtomicU64::new(tag))
    }

    /// Refuses a handle that is not a live one of kind `tag` (`name`: the argument).
    pub fn check(&self, tag: u64, name: &str) -> Result<(), Failure> {
        let what = || format!("{} `{name}`", kind(tag));
        match self.0.load(Ordering::Relaxed) {
            t if t == tag => Ok(()),
            FREED_TAG => Err(Failure::new(
                DVH_STATUS_INVALID_ARGUMENT,
                format!("{} was already released (a dangling handle)", what()),
            )),
            _ => Err(Failure::new(
                DVH_STATUS_INVALID_ARGUMENT,
                format!(
                    "{} is not a live handle of that kind (another kind, memory from elsewhere, \
                     or a released one)",
                    what()
                ),
            )),
        }
    }

    /// Marks the handle released, just before its memory is.
    pub fn release(&self) {
        self.0.store(FREED_TAG, Ordering::Relaxed);
    }
}

/// A C handle: a tag, an access state and the object.
pub(crate) trait Handle {
    /// The object behind the handle.
    type Inner;
    /// The tag of a live handle of this kind.
    const TAG: u64;
    /// The handle's parts.
    fn parts(&self) -> (&Tag, &Access, &UnsafeCell<Self::Inner>);
}

/// The object behind a handle, for a call that reads it.
pub(crate) struct Read<'a, T> {
    inner: &'a T,
    _reading: Reading<'a>,
}

impl<T> Deref for Read<'_, T> {
    type Target = T;
    fn deref(&self) -> &T {
        self.inner
    }
}

/// The object behind a handle, for a call that changes it.
pub(crate) struct Write<'a, T> {
    inner: &'a mut T,
    _writing: Writing<'a>,
}

impl<T> Deref for Write<'_, T> {
    type Target = T;
    fn deref(&self) -> &T {
        self.inner
    }
}

impl<T> DerefMut for Write<'_, T> {
    fn deref_mut(&mut self) -> &mut T {
        self.inner
    }
}

/// The object behind handle `h` (argument `name` of entry point `call`), to read: refused when
/// NULL, not a live handle of its kind, or being changed.
///
/// # Safety
/// `h` is NULL or points to a handle of type `H` that stays allocated during the call.
pub(crate) unsafe fn read<'a, H: Handle + 'a>(
    h: *const H,
    name: &str,
    call: &str,
) -> Result<Read<'a, H::Inner>, Failure> {
    // SAFETY: as this function's contract.
    let (_, access, cell) = unsafe { live(h, name)? }.parts();
    let reading = access.read(&describe(H::TAG, name), call)?;
    Ok(Read {
        // SAFETY: while `reading` lives no call may change the object (every change takes the
        // access state first), so a shared reference is sound.
        inner: unsafe { &*cell.get() },
        _reading: reading,
    })
}

/// The object behind handle `h`, to change: refused as [`read`], and while any other call on
/// it runs.
///
/// # Safety
/// As [`read`].
pub(crate) unsafe fn write<'a, H: Handle + 'a>(
    h: *const H,
    name: &str,
    call: &str,
) -> Result<Write<'a, H::Inner>, Failure> {
    // SAFETY: as this function's contract.
    let (_, access, cell) = unsafe { live(h, name)? }.parts();
    let writing = access.write(&describe(H::TAG, name), call)?;
    Ok(Write {
        // SAFETY: `writing` excludes every other call on the object while it lives.
        inner: unsafe { &mut *cell.get() },
        _writing: writing,
    })
}

/// Releases handle `h` (allocated by `Box`), unless it is NULL, not a live handle of its kind,
/// or in use by another call: those leave it alone and say why in the last error message
/// (release functions return nothing).
///
/// # Safety
/// `h` is NULL or points to a handle of type `H` allocated by `Box` and owned by the caller.
pub(crate) unsafe fn release<H: Handle>(h: *mut H, name: &str, call: &str) {
    if h.is_null() {
        return;
    }
    // SAFETY: as this function's contract.
    let taken = unsafe { live(h, name) }.and_then(|handle| {
        let (tag, access, _) = handle.parts();
        Ok((tag, access.write(&describe(H::TAG, name), call)?))
    });
    match taken {
        Ok((tag, writing)) => {
            tag.release();
            // The state stays "being changed" until the memory goes: a late call is refused.
            std::mem::forget(writing);
            // SAFETY: allocated by `Box` and owned by the caller (contract); no other call is
            // using it (the access state was free).
            drop(unsafe { Box::from_raw(h) });
        }
        Err(f) => set_last_error(&format!("{}; not released", f.message)),
    }
}

/// The handle behind `h` (argument `name`), refused when NULL or not a live handle of its kind.
///
/// # Safety
/// `h` is NULL or points to a handle of type `H` that stays allocated for `'a`.
unsafe fn live<'a, H: Handle + 'a>(h: *const H, name: &str) -> Result<&'a H, Failure> {
    // SAFETY: NULL or allocated (contract).
    let handle = unsafe { h.as_ref() }.ok_or_else(|| Failure::null(name))?;
    handle.parts().0.check(H::TAG, name)?;
    Ok(handle)
}

/// How messages name argument `name`, a handle of the kind `tag` names: "DvhMesh `a`".
fn describe(tag: u64, name: &str) -> impl Fn() -> String + '_ {
    move || format!("{} `{name}`", kind(tag))
}

fn kind(tag: u64) -> &'static str {
    match tag {
        MESH_TAG => "DvhMesh",
        SCENE_TAG => "DvhScene",
        PAIRS_TAG => "DvhPairs",
        IMPACTS_TAG => "DvhImpacts",
        NEAR_PAIRS_TAG => "DvhNearPairs",
        SCENE_IMPACTS_TAG => "DvhSceneImpacts",
        SCENE_NEAR_PAIRS_TAG => "DvhSceneNearPairs",
        CURVES_TAG => "DvhCurves",
        _ => "DvhContacts",
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn readers_or_one_writer() {
        let a = Access::default();
        let mesh = describe(MESH_TAG, "mesh");
        let r1 = a.read(&mesh, "query").unwrap();
        let r2 = a.read(&mesh, "query").unwrap();
        let busy = a.write(&mesh, "dvh_mesh_refit").err().unwrap();
        assert_eq!(busy.status, DVH_STATUS_BUSY);
        assert!(
            busy.message.contains("2 call(s) reading"),
            "{}",
            busy.message
        );
        drop((r1, r2));
        let w = a.write(&mesh, "dvh_mesh_refit").unwrap();
        let busy = a.read(&mesh, "dvh_collide").err().unwrap();
        assert_eq!(busy.status, DVH_STATUS_BUSY);
        assert!(
            busy.message
                .starts_with("dvh_collide: DvhMesh `mesh` is busy"),
            "{}",
            busy.message
        );
        assert_eq!(
            a.write(&mesh, "dvh_mesh_refit").err().unwrap().status,
            DVH_STATUS_BUSY
        );
        drop(w);
        assert_eq!(a.0.load(Ordering::Relaxed), 0);
        drop(a.read(&mesh, "query").unwrap());
        assert_eq!(a.0.load(Ordering::Relaxed), 0);
    }

    #[test]
    fn a_refused_reader_racing_the_end_of_a_change_leaves_no_trace() {
        // The interleaving, step by step: a reader adds its 1 while the writer holds the
        // object, the writer ends, then the reader takes its 1 back.
        let a = Access::default();
        let mesh = describe(MESH_TAG, "mesh");
        let w = a.write(&mesh, "dvh_mesh_refit").unwrap();
        let before = a.0.fetch_add(1, Ordering::Acquire);
        assert_eq!(before, WRITER);
        drop(w);
        a.0.fetch_sub(1, Ordering::Release);
        assert_eq!(a.0.load(Ordering::Relaxed), 0);
        drop(a.read(&mesh, "query").unwrap());
        drop(a.write(&mesh, "dvh_mesh_refit").unwrap());
        assert_eq!(a.0.load(Ordering::Relaxed), 0);
    }

    #[test]
    fn readers_and_writers_on_many_threads_end_free() {
        const ROUNDS: usize = 200_000;
        let a = Access::default();
        let mesh = describe(MESH_TAG, "mesh");
        std::thread::scope(|s| {
            for _ in 0..2 {
                s.spawn(|| {
                    for _ in 0..ROUNDS {
                        if let Ok(r) = a.read(&mesh, "query") {
                            std::hint::black_box(&r);
                        }
                    }
                });
            }
            for _ in 0..ROUNDS {
                if let Err(f) = a.write(&mesh, "dvh_mesh_refit") {
                    assert_eq!(f.status, DVH_STATUS_BUSY, "{}", f.message);
                }
            }
        });
        assert_eq!(a.0.load(Ordering::Relaxed), 0);
    }

    #[test]
    fn a_panicking_change_poisons_for_good() {
        let a = Access::default();
        let mesh = describe(MESH_TAG, "mesh");
        let r = std::panic::catch_unwind(std::panic::AssertUnwindSafe(|| {
            let _w = a.write(&mesh, "dvh_mesh_refit").unwrap();
            panic!("in the middle of a refit");
        }));
        assert!(r.is_err());
        for f in [a.read(&mesh, "q").err(), a.write(&mesh, "r").err()] {
            assert_eq!(f.unwrap().status, DVH_STATUS_INTERNAL_PANIC);
        }
    }

    #[test]
    fn tags_tell_kinds_and_released_handles_apart() {
        let t = Tag::new(MESH_TAG);
        assert!(t.check(MESH_TAG, "mesh").is_ok());
        let e = t.check(SCENE_TAG, "scene").unwrap_err();
        assert!(
            e.message
                .starts_with("DvhScene `scene` is not a live handle"),
            "{}",
            e.message
        );
        t.release();
        let e = t.check(MESH_TAG, "mesh").unwrap_err();
        assert!(e.message.contains("already released"), "{}", e.message);
    }

    #[test]
    fn every_kind_has_its_own_tag_and_name() {
        let kinds = [
            (MESH_TAG, "DvhMesh"),
            (SCENE_TAG, "DvhScene"),
            (PAIRS_TAG, "DvhPairs"),
            (CONTACTS_TAG, "DvhContacts"),
            (IMPACTS_TAG, "DvhImpacts"),
            (NEAR_PAIRS_TAG, "DvhNearPairs"),
            (SCENE_IMPACTS_TAG, "DvhSceneImpacts"),
            (SCENE_NEAR_PAIRS_TAG, "DvhSceneNearPairs"),
            (CURVES_TAG, "DvhCurves"),
        ];
        for (i, &(tag, name)) in kinds.iter().enumerate() {
            assert_eq!(kind(tag), name);
            assert_ne!(tag, FREED_TAG);
            assert!(
                kinds[i + 1..].iter().all(|&(other, _)| other != tag),
                "{name}"
            );
            let e = Tag::new(tag).check(SCENE_IMPACTS_TAG, "impacts_out");
            assert_eq!(e.is_ok(), tag == SCENE_IMPACTS_TAG);
        }
        let e = Tag::new(IMPACTS_TAG)
            .check(SCENE_IMPACTS_TAG, "impacts_out")
            .unwrap_err();
        assert!(
            e.message
                .starts_with("DvhSceneImpacts `impacts_out` is not a live handle"),
            "{}",
            e.message
        );
    }
}
