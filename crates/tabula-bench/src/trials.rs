//! Where a benchmark's trials run: on this machine's cores, or spread over `tabula
//! worker` processes on any machines a zenoh network reaches. A trial is a pure function
//! of its seed, so both give the same rows for the same seeds (timings aside).

use anyhow::{Result, bail};
use serde::{Deserialize, Serialize, de::DeserializeOwned};

/// Where to spread trials: on `workers` worker processes reached through a zenoh
/// router (`connect`) or by listening for them (`listen`), on ROS domain `domain`;
/// `workers: None` runs them here.
#[derive(Clone, Debug, Default)]
pub struct Spread {
    pub workers: Option<usize>,
    pub connect: Vec<String>,
    pub listen: Vec<String>,
    pub domain: u32,
}

/// One trial, as a worker is asked to run it.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct TrialSpec {
    /// The benchmark: `place` or `clear`.
    pub bench: String,
    pub suite: String,
    /// The parameters file's text (TOML), if one was given.
    pub params: Option<String>,
    pub seed: u64,
}

/// The parameters file's text, to send along with every trial.
pub fn params_text(path: Option<&std::path::Path>) -> Result<Option<String>> {
    path.map(|p| tabula_geom::input::read_text(p, tabula_geom::input::Format::Params))
        .transpose()
        .map_err(Into::into)
}

/// Runs `local(seed)` for every seed, here (both cores) or on the workers (each runs
/// [`trial`] of `spec(seed)`); `tick` is called as each ends. The rows in seed order.
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
                bail!("this tabula was built without ROS 2 support (feature `ros`)")
            }
        }
    }
}

/// One trial of a benchmark, as its row in JSON: what a worker answers. The one
/// registry of benchmarks that run on workers.
pub fn trial(spec: &TrialSpec) -> Result<serde_json::Value> {
    Ok(match spec.bench.as_str() {
        "place" => serde_json::to_value(crate::place::trial_of(spec)?)?,
        "clear" => serde_json::to_value(crate::clear::trial_of(spec)?)?,
        other => bail!("no benchmark `{other}` runs on workers"),
    })
}
