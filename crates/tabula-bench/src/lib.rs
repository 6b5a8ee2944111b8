//! Judged runs and benchmarks. Every task run in the simulator and judged by physics
//! ([`judged`]: one run for any [`Judged`] task), the suites' trials and the rows they
//! give (one module per task), where trials run ([`trials`]: on this machine's cores or
//! on `tabula worker`s), and the statistics the rows are summed up with ([`stats`]).
//! The CLI parses arguments and prints; everything measured is here.

pub mod clear;
pub mod demo;
pub mod ik;
pub mod judged;
pub mod motion_plan;
pub mod mount;
pub mod perception;
pub mod pick_place;
pub mod place;
pub mod plan;
pub mod registry;
pub mod report;
#[cfg(feature = "ros")]
pub mod ros;
pub mod spec;
pub mod stable;
pub mod stats;
pub mod tidy;
pub mod trials;
#[cfg(feature = "ros")]
pub mod worker;

pub use judged::{Judged, Verdict, run_in, run_judged};

use anyhow::{Result, bail};
use tabula_robot::robots::NamedRobot;
use tabula_sim::SimWorld;

/// The scene's robot (`wanted`, or its first) by name.
pub fn scene_robot(world: &SimWorld, wanted: Option<&str>) -> Result<String> {
    match wanted {
        Some(r) => {
            world.robot(r)?;
            Ok(r.to_string())
        }
        None => match world.robots.first() {
            Some(r) => Ok(r.name.clone()),
            None => bail!("the scene has no robot"),
        },
    }
}

/// The scene's robot (`wanted`, or its first) by name, with its model and description.
pub fn scene_robot_named(world: &SimWorld, wanted: Option<&str>) -> Result<(String, NamedRobot)> {
    let name = scene_robot(world, wanted)?;
    let r = world.robot(&name)?;
    let mut robot = NamedRobot::new(r.model.clone(), r.description.clone(), &name);
    robot.srdf = r.srdf.clone();
    Ok((name, robot))
}
