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
    use rayon::prelude::*;
    match spread.workers {
        None => seeds
            .into_par_iter()
            .map(|s| {
                let row = local(s);
                tick();
                row
            })
            .collect(),
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
