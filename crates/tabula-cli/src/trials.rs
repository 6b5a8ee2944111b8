//! The flags that say where a benchmark's trials run (here, or on `tabula worker`s;
//! see `tabula_bench::trials`), and a suite's run with its progress bar.

use anyhow::Result;
use serde::{Serialize, de::DeserializeOwned};
use tabula_bench::trials::{Spread, TrialSpec};

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

impl TrialArgs {
    pub fn spread(&self) -> Spread {
        Spread {
            workers: self.workers,
            connect: self.connect.clone(),
            listen: self.listen.clone(),
            domain: self.domain,
        }
    }
}

/// A suite benchmark as asked: which suite, how many trials from which seed, the
/// parameters file, where failures and the report go, JSON or a table, and where the
/// trials run.
pub struct SuiteRun<'a> {
    pub suite: &'a str,
    pub count: u64,
    pub seed: u64,
    pub params: Option<&'a std::path::Path>,
    pub save_failures: Option<&'a std::path::Path>,
    pub json: bool,
    pub report: Option<&'a std::path::Path>,
    pub spread: &'a TrialArgs,
}

impl SuiteRun<'_> {
    /// Runs the suite's trials of benchmark `bench` (`local(seed)` here, or on the
    /// workers) with a progress bar; the rows in seed order.
    pub fn run<R>(&self, bench: &str, local: impl Fn(u64) -> Result<R> + Sync) -> Result<Vec<R>>
    where
        R: Serialize + DeserializeOwned + Send,
    {
        let params = tabula_bench::trials::params_text(self.params)?;
        let progress = crate::progress::steps(self.count, self.suite);
        let spec = |s| TrialSpec {
            bench: bench.into(),
            suite: self.suite.into(),
            params: params.clone(),
            seed: s,
        };
        let rows = tabula_bench::trials::run(
            &self.spread.spread(),
            self.seed..self.seed.saturating_add(self.count),
            (spec, local),
            &|| progress.inc(1),
        );
        progress.finish_and_clear();
        rows
    }
}
