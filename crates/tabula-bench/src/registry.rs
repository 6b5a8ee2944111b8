//! The one registry of benchmarks whose trials run on workers: a trial asked by name.

use crate::spec::TrialSpec;
use anyhow::{Result, bail};

/// One trial of a benchmark, as its row in JSON: what a worker answers. The one
/// registry of benchmarks that run on workers.
pub fn trial(spec: &TrialSpec) -> Result<serde_json::Value> {
    Ok(match spec.bench.as_str() {
        "place" => serde_json::to_value(crate::place::trial_of(spec)?)?,
        "clear" => serde_json::to_value(crate::clear::trial_of(spec)?)?,
        other => bail!("no benchmark `{other}` runs on workers"),
    })
}
