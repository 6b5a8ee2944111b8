//! Judges: what physics says a task achieved, from ground truth the task never sees.
//! One file per task; the older tasks' judges are in [`crate::verdict`].

pub mod tidy;
