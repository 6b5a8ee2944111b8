//! Tasks run against a robot served elsewhere (`--connect`): the task here, the robot
//! (and, for a simulated one, its judge) there, over zenoh with rmw_zenoh's conventions.

use crate::tasks::TaskRunArgs;
use anyhow::{Result, anyhow, bail};
use std::time::Duration;
use tabula_ros::driver::ZenohDriver;
use tabula_ros::judge::JudgeSession;
use tabula_ros::node::{Mode, NodeConfig};
use tabula_ros::protocol::JudgedTask;

/// How long to wait for a served robot to answer before giving up.
const CONNECT_WAIT: Duration = Duration::from_secs(10);

/// Connects to the robot `--connect` names, and checks it is the scene's robot.
pub fn connect(run: &TaskRunArgs, robot: &str) -> Result<ZenohDriver> {
    if run.dry_run {
        bail!("--dry-run runs the scene here; it cannot be combined with --connect");
    }
    let mut config = NodeConfig::new("tabula_task", Mode::Client);
    config.connect = run.connect.clone();
    config.domain = run.domain;
    let driver = ZenohDriver::connect(config, CONNECT_WAIT)
        .map_err(|e| anyhow!("cannot reach the robot at {}: {e}", run.connect.join(", ")))?;
    let served = &driver.description().robot;
    if served != robot {
        bail!("the robot served there is `{served}`, the scene's is `{robot}`");
    }
    Ok(driver)
}

/// Starts a judged run of `task` there.
pub fn begin(driver: &ZenohDriver, task: JudgedTask) -> Result<JudgeSession> {
    JudgeSession::begin(driver, task)
        .map_err(|e| anyhow!("the served robot cannot run this task: {e}"))
}

/// Ends the judged run and reads its verdict.
pub fn verdict<V: serde::de::DeserializeOwned>(
    session: JudgeSession,
    planned: Option<tabula_geom::Pose>,
) -> Result<V> {
    let v = session
        .finish(planned)
        .map_err(|e| anyhow!("no verdict from the served robot: {e}"))?;
    serde_json::from_value(v).map_err(|e| anyhow!("malformed verdict: {e}"))
}

/// The served world now, as a scene file.
pub fn scene(driver: &ZenohDriver) -> Result<String> {
    driver
        .scene()
        .map_err(|e| anyhow!("cannot read the served world: {e}"))
}
