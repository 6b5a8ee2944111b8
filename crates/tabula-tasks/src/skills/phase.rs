//! One phase recorder for every task: each stage's name, how long it took and whether
//! it succeeded, as MoveIt Task Constructor's stages report themselves.

use std::time::Instant;
use tabula_motion::group::thread_cpu;

/// One stage: its name, how long it took (planning stages: CPU ms; execution stages:
/// wall-clock ms), whether it succeeded.
#[derive(Debug, Clone, serde::Serialize)]
pub struct Phase {
    pub name: String,
    pub ms: f64,
    pub ok: bool,
    /// For a motion: CPU ms spent planning it.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub plan_ms: Option<f64>,
}

/// How a phase is timed.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Clock {
    /// This thread's CPU time (decisions).
    Cpu,
    /// Wall-clock time (motions, waiting for the robot).
    Wall,
}

/// Runs `f` as phase `name` of `task`, logs it and records it in `phases`.
pub fn timed<T, E>(
    phases: &mut Vec<Phase>,
    task: &str,
    name: &str,
    clock: Clock,
    f: impl FnOnce() -> Result<T, E>,
) -> Result<T, E> {
    let (t0, c0) = (Instant::now(), thread_cpu());
    let out = f();
    let ms = match clock {
        Clock::Cpu => (thread_cpu() - c0) * 1e3,
        Clock::Wall => t0.elapsed().as_secs_f64() * 1e3,
    };
    tracing::info!(phase = name, ms, ok = out.is_ok(), "{task}");
    phases.push(Phase {
        name: name.into(),
        ms,
        ok: out.is_ok(),
        plan_ms: None,
    });
    out
}
