//! Turning panics inside third-party code (truck, the STEP parser) into errors.
//!
//! truck panics on some malformed data (unsorted knots, unexpected references). We run such
//! calls under [`catch`], which returns the panic message as an error. The default panic hook
//! would still print the message to stderr; [`install_quiet_hook`] (called by the binary)
//! replaces it with one that stays silent for panics that [`catch`] is about to handle and
//! behaves as before for every other panic, so real bugs are still reported.

use std::cell::Cell;
use std::panic::{self, AssertUnwindSafe};
use std::sync::Once;

thread_local! {
    static GUARDED: Cell<u32> = const { Cell::new(0) };
}

/// Runs `f`; a panic inside it becomes `Err(message)`.
pub fn catch<T>(f: impl FnOnce() -> T) -> Result<T, String> {
    GUARDED.with(|g| g.set(g.get() + 1));
    let r = panic::catch_unwind(AssertUnwindSafe(f));
    GUARDED.with(|g| g.set(g.get() - 1));
    r.map_err(|payload| {
        if let Some(s) = payload.downcast_ref::<&str>() {
            (*s).to_string()
        } else if let Some(s) = payload.downcast_ref::<String>() {
            s.clone()
        } else {
            "unknown panic".to_string()
        }
    })
}

/// Installs (once) a panic hook that is silent for panics caught by [`catch`].
pub fn install_quiet_hook() {
    static ONCE: Once = Once::new();
    ONCE.call_once(|| {
        let previous = panic::take_hook();
        panic::set_hook(Box::new(move |info| {
            if GUARDED.with(|g| g.get()) == 0 {
                previous(info);
            }
        }));
    });
}
