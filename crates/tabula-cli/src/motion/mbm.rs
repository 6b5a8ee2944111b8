//! `tabula motion bench --mbm PATH`: MotionBenchMaker's problem sets planned on tabula,
//! timed as VAMP and OMPL time theirs (CPU of the planning thread, plan + shortcut,
//! world built once per problem), with every path written out for outside checking.

use anyhow::{Context, Result};
use std::path::{Path, PathBuf};
use tabula_geom::Pose;
use tabula_motion::group::MoveGroupParams;
use tabula_motion::mbm::{self, MbmReport};
use tabula_motion::moveit::Limits;
use tabula_motion::world::CollisionWorld;
use tabula_robot::robots;

/// What `--mbm` was asked.
pub struct MbmRun<'a> {
    pub problems: &'a Path,
    pub robot: &'a str,
    pub params: Option<&'a Path>,
    pub seed: u64,
    pub timeout: f64,
    pub json: bool,
    pub paths: Option<&'a PathBuf>,
}

pub fn run(r: MbmRun) -> Result<()> {
    let mut params: MoveGroupParams = super::planning_params(r.params)?;
    params.planner.timeout_s = r.timeout;
    params.planner.seed = r.seed;
    let robot = robots::load(r.robot)?;
    let problems = mbm::load(r.problems, &Limits::default())
        .with_context(|| r.problems.display().to_string())?;
    let world_params = {
        let mut w = params.world.clone();
        if w.srdf.is_none() {
            w.srdf = robot.srdf.clone();
        }
        w
    };
    let progress =
        crate::progress::spinner(&format!("{} MotionBenchMaker problems", problems.len()));
    let results = mbm::run(
        &problems,
        &params.planner,
        |group| {
            let arm = robot.description.arm(group).map_err(|e| e.to_string())?;
            let chain = arm.chain(&robot.model).map_err(|e| e.to_string())?;
            CollisionWorld::new(
                robot.model.clone(),
                chain,
                Pose::IDENTITY,
                None,
                world_params.clone(),
            )
            .map_err(|e| e.to_string())
        },
        |_| {},
    );
    progress.finish_and_clear();
    if let Some(out) = r.paths {
        tabula_bench::report::motion::write_paths(out, &results)?;
    }
    let report = MbmReport::of(&results);
    if r.json {
        println!("{}", serde_json::to_string(&report)?);
    } else {
        for line in tabula_bench::report::motion::mbm_lines(&report, r.timeout) {
            println!("{line}");
        }
    }
    Ok(())
}
