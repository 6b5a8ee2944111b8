//! Panics of third-party code on hostile input (V-HACD, the URDF reader) are errors to
//! our callers, caught where they can happen, and never printed: [`catch_quietly`]
//! marks the thread while it runs, and the process's panic hook stays silent for
//! marked threads. Any other panic is a bug, reported by the hook the binary installs.

use std::cell::Cell;
use std::panic::{UnwindSafe, catch_unwind};
use std::sync::Once;

thread_local! {
    static QUIET: Cell<u32> = const { Cell::new(0) };
}

/// Whether this thread is inside [`catch_quietly`].
pub fn is_quiet() -> bool {
    QUIET.with(|q| q.get() > 0)
}

/// `f()`, or the panic's message when it panics — without printing the panic.
pub fn catch_quietly<R>(f: impl FnOnce() -> R + UnwindSafe) -> Result<R, String> {
    static SILENCE_MARKED_THREADS: Once = Once::new();
    SILENCE_MARKED_THREADS.call_once(|| {
        let previous = std::panic::take_hook();
        std::panic::set_hook(Box::new(move |info| {
            if !is_quiet() {
                previous(info);
            }
        }));
    });
    QUIET.with(|q| q.set(q.get() + 1));
    let out = catch_unwind(f);
    QUIET.with(|q| q.set(q.get() - 1));
    out.map_err(|payload| panic_message(payload.as_ref()))
}

/// The text a panic was raised with (`panic!("…")`), or "panic" when it carried none.
pub fn panic_message(payload: &(dyn std::any::Any + Send)) -> String {
    payload
        .downcast_ref::<&str>()
        .map(|s| s.to_string())
        .or_else(|| payload.downcast_ref::<String>().cloned())
        .unwrap_or_else(|| "panic".into())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_caught_panic_is_its_message() {
        assert_eq!(catch_quietly(|| 3), Ok(3));
        assert_eq!(
            catch_quietly(|| -> u8 { panic!("boom {}", 1) }),
            Err("boom 1".to_string())
        );
        assert!(!is_quiet());
    }
}
