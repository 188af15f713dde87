//! The FMU-state handles this library has handed out and not yet freed, so that a pointer a master passes
//! as an `fmi2FMUstate` is used only if it is one of them.
//!
//! An `fmi2FMUstate` is an opaque `void*` and `fmi2FreeFMUstate` takes a `fmi2FMUstate*`; C converts one
//! into the other without a warning. The Reference-FMUs' `fmusim` (`FMISaveFMUStateToFile`, used by
//! `--final-fmu-state-file`) calls `fmi2FreeFMUstate(c, FMUstate)` with the state itself instead of its
//! address, and a master may pass a state twice to `fmi2FreeFMUstate`, or an uninitialised variable to
//! `fmi2GetFMUstate`. Without this registry the FMU would read the state's first bytes as a pointer and free
//! it (a segmentation fault), or write a snapshot into foreign memory. With it, a pointer that is not a live
//! handle is never dereferenced as a snapshot: see [`crate::fmi2::api`].
//!
//! The registry is process-wide (one mutex-guarded set), so a state taken of one instance may still be set
//! into another instance of the same FMU, as before. Each handle is registered with the type name of its
//! snapshot, so that handles of different models (in tests, which run several models in one process) are
//! never confused.

use std::collections::BTreeSet;
use std::sync::{Mutex, MutexGuard};

static LIVE: Mutex<BTreeSet<(usize, &'static str)>> = Mutex::new(BTreeSet::new());

/// The set; a panic while it was held cannot leave it half-updated (each operation is one insert or
/// remove), so a poisoned lock is used as it is.
fn live() -> MutexGuard<'static, BTreeSet<(usize, &'static str)>> {
    LIVE.lock().unwrap_or_else(|poisoned| poisoned.into_inner())
}

/// Registers a new handle to a value of type `T`.
pub fn register<T>(ptr: *const T) {
    live().insert((ptr as usize, std::any::type_name::<T>()));
}

/// Whether `ptr` is a live handle to a value of type `T`.
pub fn is_live<T>(ptr: *const T) -> bool {
    live().contains(&(ptr as usize, std::any::type_name::<T>()))
}

/// Unregisters `ptr`; true if it was a live handle to a value of type `T` (the caller then owns it).
pub fn release<T>(ptr: *const T) -> bool {
    live().remove(&(ptr as usize, std::any::type_name::<T>()))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn handles_are_live_from_registration_to_release_and_typed() {
        let x = Box::into_raw(Box::new(7u64));
        assert!(!is_live(x));
        register(x);
        assert!(is_live(x));
        assert!(!is_live(x as *const u32), "another type's handle");
        assert!(release(x));
        assert!(!release(x), "released twice");
        assert!(!is_live(x));
        drop(unsafe { Box::from_raw(x) });
    }
}
