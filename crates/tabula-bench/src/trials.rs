//! Where a benchmark's trials run: on this machine's cores, or spread over `tabula
//! worker` processes on any machines a zenoh network reaches. A trial is a pure function
//! of its seed, so both give the same rows for the same seeds (timings aside).

pub use crate::spec::{Spread, TrialSpec};
use anyhow::Result;
use serde::{Serialize, de::DeserializeOwned};

/// The parameters file's text, to send along with every trial.
pub fn params_text(path: Option<&std::path::Path>) -> Result<Option<String>> {
    path.map(|p| tabula_geom::input::read_text(p, tabula_geom::input::Format::Params))
        .transpose()
        .map_err(Into::into)
}

/// Runs `local(seed)` for every seed, here (both cores) or on the workers (each runs
/// `registry::trial` of `spec(seed)`); `tick` is called as each ends. The rows in seed order.
pub fn run<R>(
    spread: &Spread,
    seeds: std::ops::Range<u64>,
    (spec, local): (
        impl Fn(u64) -> TrialSpec + Sync,
        impl Fn(u64) -> Result<R> + Sync,
    ),
    tick: &(dyn Fn() + Sync),
) -> Result<Vec<R>>
where
    R: Serialize + DeserializeOwned + Send,
{
    match spread.workers {
        None => on_this_machine(seeds, &local, tick),
        Some(n) => {
            #[cfg(feature = "ros")]
            {
                crate::worker::spread(spread, n, seeds, spec, tick)
            }
            #[cfg(not(feature = "ros"))]
            {
                let _ = (n, spec);
                anyhow::bail!("this tabula was built without ROS 2 support (feature `ros`)")
            }
        }
    }
}

/// Stack of a thread running one trial (virtual memory; pages are used as touched).
const TRIAL_STACK: usize = 64 << 20;

/// Every seed's trial on plain threads, one per core, each taking the next seed.
///
/// Why not rayon's pool: a trial waits on pools of its own (perception runs in a
/// one-thread pool), and a rayon worker that waits steals other jobs of its pool — here
/// whole trials — and runs them on top of its stack, so 50 clearing scenes nested
/// until the stack overflowed and the process aborted.
fn on_this_machine<R: Send>(
    seeds: std::ops::Range<u64>,
    local: &(impl Fn(u64) -> Result<R> + Sync),
    tick: &(dyn Fn() + Sync),
) -> Result<Vec<R>> {
    use std::sync::Mutex;
    use std::sync::atomic::{AtomicUsize, Ordering};
    let seeds: Vec<u64> = seeds.collect();
    let rows: Mutex<Vec<Option<Result<R>>>> = Mutex::new((0..seeds.len()).map(|_| None).collect());
    let next = AtomicUsize::new(0);
    let cores = std::thread::available_parallelism().map_or(1, |n| n.get());
    std::thread::scope(|scope| -> Result<()> {
        let worker = || loop {
            let k = next.fetch_add(1, Ordering::Relaxed);
            let Some(&seed) = seeds.get(k) else { break };
            let row = local(seed);
            tick();
            if let Ok(mut rows) = rows.lock() {
                rows[k] = Some(row);
            }
        };
        for _ in 0..cores.min(seeds.len()) {
            std::thread::Builder::new()
                .name("trial".into())
                .stack_size(TRIAL_STACK)
                .spawn_scoped(scope, worker)?;
        }
        Ok(())
    })?;
    rows.into_inner()
        .map_err(|_| anyhow::anyhow!("a trial thread panicked"))?
        .into_iter()
        .map(|row| row.unwrap_or_else(|| Err(anyhow::anyhow!("a trial did not run"))))
        .collect()
}
