//! tabula: a per-thread budget for one expansion (a deadline and the largest text a
//! substitution may produce), so that an expansion that runs away stops by itself
//! instead of only being abandoned by its caller (which, in a long-lived process,
//! would leave it allocating).

use std::cell::Cell;
use std::time::Instant;

thread_local! {
    static DEADLINE: Cell<Option<Instant>> = const { Cell::new(None) };
    static MAX_TEXT: Cell<usize> = const { Cell::new(usize::MAX) };
    static NODES_LEFT: Cell<u64> = const { Cell::new(u64::MAX) };
}

/// Sets this thread's budget for the expansions it runs next: a deadline, the largest
/// text a substitution may produce, and how many XML nodes may be expanded in all.
pub fn set(deadline: Option<Instant>, max_text_bytes: usize, max_nodes: u64) {
    DEADLINE.with(|d| d.set(deadline));
    MAX_TEXT.with(|m| m.set(max_text_bytes));
    NODES_LEFT.with(|n| n.set(max_nodes));
}

/// [`check`] for one more expanded node, counted against the node budget.
pub(crate) fn check_node() -> Result<(), crate::XacroError> {
    let left = NODES_LEFT.with(|n| {
        let v = n.get().saturating_sub(1);
        n.set(v);
        v
    });
    if left == 0 {
        return Err(crate::XacroError::Include(
            "the expansion visits more XML nodes than a robot description has (macros that multiply?)".into(),
        ));
    }
    check(0)
}

/// An error when the deadline has passed or `text_len` is over the budget.
pub(crate) fn check(text_len: usize) -> Result<(), crate::XacroError> {
    if DEADLINE.with(Cell::get).is_some_and(|d| Instant::now() > d) {
        return Err(crate::XacroError::Include(
            "the expansion ran out of time (macros or properties that multiply?)".into(),
        ));
    }
    let max = MAX_TEXT.with(Cell::get);
    if text_len > max {
        return Err(crate::XacroError::Include(format!(
            "a substitution produced {text_len} bytes, over the {max}-byte limit"
        )));
    }
    Ok(())
}
