//! `tabula motion …`: plan a motion (MoveIt's core job), and the planning benchmarks.

mod mbm;
mod plan;

use tabula_bench::motion_plan::planning_params;

use anyhow::{Result, bail};
use clap::Subcommand;
use tabula_motion::PlannerParams;
use tabula_motion::bench;
use tabula_robot::{Chain, robots};

#[derive(Subcommand)]
pub enum MotionCommand {
    /// Plan a collision-free motion for a robot's group in a scene (tabula TOML or MoveIt
    /// YAML) to joints, a pose, a named state or a MoveIt motion plan request.
    Plan(plan::PlanArgs),
    /// RRT-Connect on generated tabletop reach problems (table, shelf, boxes).
    Bench {
        /// wam or pr2 (generated problems); with --mbm, the problems' robot (URDF or
        /// xacro; its SRDF with --srdf).
        #[arg(long, default_value = "wam")]
        robot: String,
        /// MotionBenchMaker problems: a folder of set folders of sceneNNNN.yaml +
        /// requestNNNN.yaml, or the same as .tar.bz2.
        #[arg(long)]
        mbm: Option<std::path::PathBuf>,
        /// With --mbm: write every solved path (JSON) for outside checking.
        #[arg(long, requires = "mbm")]
        paths: Option<std::path::PathBuf>,
        /// With --mbm: motion parameters (TOML, `MoveGroupParams`; default: 1 mm padding,
        /// edges certified by conservative advancement).
        #[arg(long, requires = "mbm")]
        params: Option<std::path::PathBuf>,
        /// Print the parameters `--params` takes, with their defaults (SPEC's values), as
        /// TOML to start a file from, and exit.
        #[arg(long, exclusive = true)]
        print_params: bool,
        #[arg(long, default_value_t = 200, value_parser = crate::args::count)]
        problems: usize,
        #[arg(long, default_value_t = 1, value_parser = crate::args::seed)]
        seed: u64,
        /// Planning time limit per problem (s).
        #[arg(long, default_value_t = 1.0, value_parser = crate::args::seconds)]
        timeout: f64,
        #[arg(long)]
        json: bool,
        /// Write a report into this folder: the planning-time distribution.
        #[arg(long)]
        report: Option<std::path::PathBuf>,
    },
}

pub fn run(cmd: MotionCommand) -> Result<()> {
    match cmd {
        MotionCommand::Plan(args) => plan::run(args)?,
        MotionCommand::Bench {
            print_params: true, ..
        } => crate::tasks::print_toml(&planning_params(None)?)?,
        MotionCommand::Bench {
            robot,
            mbm: Some(mbm_path),
            paths,
            params,
            seed,
            timeout,
            json,
            ..
        } => mbm::run(mbm::MbmRun {
            problems: &mbm_path,
            robot: &robot,
            params: params.as_deref(),
            seed,
            timeout,
            json,
            paths: paths.as_ref(),
        })?,
        MotionCommand::Bench {
            robot,
            mbm: None,
            problems,
            seed,
            timeout,
            json,
            report: report_dir,
            ..
        } => {
            if robot != "wam" && robot != "pr2" {
                bail!("--robot must be wam or pr2 (the generated scenes are sized for them)");
            }
            if !(timeout.is_finite() && timeout > 0.0) {
                bail!("--timeout must be a positive number of seconds");
            }
            let r = robots::load(&robot)?;
            // The arm planning group (for the PR2 MoveIt's right_arm: 7 joints, torso fixed).
            let chain = Chain::new(&r.model, &r.default_base, &r.default_tip)?;
            let params = PlannerParams {
                timeout_s: timeout,
                ..PlannerParams::default()
            };
            let progress = crate::progress::spinner(&format!("{problems} reach problems"));
            let report = bench::run(&r, &chain, problems, seed, &params)?;
            progress.finish_and_clear();
            let what = (robot.as_str(), seed, timeout);
            if let Some(dir) = &report_dir {
                tabula_bench::report::motion::reach_page(dir, what, &report)?;
            }
            if json {
                println!("{}", serde_json::to_string(&report)?);
            } else {
                for line in tabula_bench::report::motion::reach_lines(what, &report) {
                    println!("{line}");
                }
            }
        }
    }
    Ok(())
}
