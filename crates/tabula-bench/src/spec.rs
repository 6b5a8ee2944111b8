//! What a trial is, and where trials may run.

use serde::{Deserialize, Serialize};

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
