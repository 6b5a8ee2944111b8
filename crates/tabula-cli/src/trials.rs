//! Where a benchmark's trials run: on this machine's cores, or spread over `tabula
//! worker` processes on any machines a zenoh network reaches. A trial is a pure function
//! of its seed, so both give the same rows for the same seeds (timings aside).

use anyhow::{Result, bail};
use serde::{Deserialize, Serialize, de::DeserializeOwned};

/// The flags that spread a benchmark over workers.
#[derive(clap::Args, Clone, Debug, Default)]
pub struct TrialArgs {
    /// Run the trials on this many `tabula worker` processes instead of here (they
    /// connect to the same zenoh network: `--connect` a router, or `--listen` and let
    /// them connect here).
    #[arg(long, value_parser = crate::args::count)]
    pub workers: Option<usize>,
    /// A zenoh router (or `tabula serve`) the workers are connected to.
    #[arg(long, value_name = "ENDPOINT")]
    pub connect: Vec<String>,
    /// Listen here as a router for workers to connect to.
    #[arg(long, value_name = "ENDPOINT")]
    pub listen: Vec<String>,
    /// ROS_DOMAIN_ID of the workers.
    #[arg(long, default_value_t = 0, value_parser = clap::value_parser!(u32).range(0..=232))]
    pub domain: u32,
}

/// One trial, as a worker is asked to run it.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct TrialSpec {
    /// `place` or `clear`.
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

/// Runs `local(seed)` for every seed, here (both cores) or on the workers (each
/// runs [`trial`] of `spec(seed)`); the rows come back in seed order.
pub fn run<R>(
    args: &TrialArgs,
    seeds: std::ops::Range<u64>,
    spec: impl Fn(u64) -> TrialSpec + Sync,
    local: impl Fn(u64) -> Result<R> + Sync,
    progress: &indicatif::ProgressBar,
) -> Result<Vec<R>>
where
    R: Serialize + DeserializeOwned + Send,
{
    use rayon::prelude::*;
    match args.workers {
        None => seeds
            .into_par_iter()
            .map(|s| {
                let _tick = crate::progress::Tick(progress);
                local(s)
            })
            .collect(),
        Some(n) => {
            #[cfg(feature = "ros")]
            {
                crate::worker::spread(args, n, seeds, spec, progress)
            }
            #[cfg(not(feature = "ros"))]
            {
                let _ = (n, spec);
                bail!("this tabula was built without ROS 2 support (feature `ros`)")
            }
        }
    }
}

/// One trial of a benchmark, as its row in JSON: what a worker answers.
#[cfg(feature = "ros")]
pub fn trial(spec: &TrialSpec) -> Result<serde_json::Value> {
    Ok(match spec.bench.as_str() {
        "place" => serde_json::to_value(crate::place::trial_of(spec)?)?,
        "clear" => serde_json::to_value(crate::clear::trial_of(spec)?)?,
        other => bail!("no benchmark `{other}` runs on workers"),
    })
}
