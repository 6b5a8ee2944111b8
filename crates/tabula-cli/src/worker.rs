//! `tabula worker`: serves benchmark trials to `tabula bench … --workers N` over zenoh,
//! one at a time, on this machine (see `tabula_bench::worker`).

use anyhow::Result;

#[derive(clap::Args)]
pub struct WorkerArgs {
    /// The zenoh router (or the bench's `--listen`) to join.
    #[arg(long, value_name = "ENDPOINT", required = true)]
    pub connect: Vec<String>,
    /// ROS_DOMAIN_ID.
    #[arg(long, default_value_t = 0, value_parser = clap::value_parser!(u32).range(0..=232))]
    pub domain: u32,
    /// How long to wait for the bench (or a router) to answer at `--connect` before
    /// giving up with an error (s).
    #[arg(long, default_value_t = 10.0, value_parser = crate::args::seconds)]
    pub wait: f64,
    /// Stop after this many seconds (default: at Ctrl+C).
    #[arg(long, value_parser = crate::args::seconds)]
    pub duration: Option<f64>,
}

pub fn run(a: WorkerArgs) -> Result<()> {
    tabula_bench::worker::serve(&a.connect, a.domain, a.wait, a.duration)
}
