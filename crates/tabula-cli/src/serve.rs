//! `tabula serve`: the simulator as a ROS 2 robot over zenoh (rmw_zenoh's conventions),
//! for tasks in other processes (`--connect`) and for ROS 2 nodes.

use crate::tasks::{load_world, scene_robot};
use anyhow::{Context, Result, anyhow};
use std::path::PathBuf;
use std::time::{Duration, Instant};
use tabula_ros::node::{Mode, NodeConfig};
use tabula_ros::serve::{Rates, Server};

#[derive(clap::Args)]
pub struct ServeArgs {
    /// The scene to serve (its robot, furniture, objects and cameras).
    #[arg(long)]
    pub scene: PathBuf,
    /// The robot to serve when the scene has several.
    #[arg(long)]
    pub robot: Option<String>,
    /// Where to listen, as a zenoh router (ROS 2 nodes under rmw_zenoh and
    /// `tabula … --connect` connect here); repeat for several.
    #[arg(long, value_name = "ENDPOINT", default_value = "tcp/127.0.0.1:7447")]
    pub listen: Vec<String>,
    /// Routers or peers to connect to as well (another site's router, say).
    #[arg(long, value_name = "ENDPOINT")]
    pub connect: Vec<String>,
    /// ROS_DOMAIN_ID.
    #[arg(long, default_value_t = 0, value_parser = clap::value_parser!(u32).range(0..=232))]
    pub domain: u32,
    /// A zenoh configuration file (JSON5) to start from.
    #[arg(long)]
    pub zenoh_config: Option<PathBuf>,
    /// Camera noise seed of commands outside judged runs.
    #[arg(long, default_value_t = 1, value_parser = crate::args::seed)]
    pub seed: u64,
    /// How often /joint_states and /tf are published on their own (Hz, 0: after
    /// commands only).
    #[arg(long, default_value_t = 10.0, value_parser = crate::args::rate)]
    pub state_hz: f64,
    /// How often each camera's /<camera>/points is published on its own (Hz, 0: only
    /// frames a task asks for).
    #[arg(long, default_value_t = 1.0, value_parser = crate::args::rate)]
    pub camera_hz: f64,
    /// Stop after this many seconds (default: at Ctrl+C).
    #[arg(long, value_parser = crate::args::seconds)]
    pub duration: Option<f64>,
    /// Write the served world as a scene file when stopping.
    #[arg(long)]
    pub save_scene: Option<PathBuf>,
}

pub fn run(a: ServeArgs) -> Result<()> {
    let world = load_world(&a.scene)?.1;
    let robot = scene_robot(&world, a.robot.as_deref())?;
    let mut config = NodeConfig::new("tabula_sim", Mode::Router);
    config.listen = a.listen.clone();
    config.connect = a.connect.clone();
    config.domain = a.domain;
    config.config_file = a.zenoh_config.clone();
    let rates = Rates {
        state_hz: a.state_hz,
        camera_hz: a.camera_hz,
    };
    let mut server = Server::new(&world, &robot, a.seed, config, rates)
        .map_err(|e| anyhow!("cannot serve on {}: {e}", a.listen.join(", ")))?;
    let served = world.robot(&robot)?;
    let _services = crate::services::declare(
        &server.node,
        served.model.clone(),
        served.description.clone(),
    )
    .map_err(|e| anyhow!("{e}"))?;
    eprintln!(
        "serving `{robot}` as ROS 2 node /tabula_sim (domain {}) on {}; Ctrl+C stops",
        a.domain,
        a.listen.join(", ")
    );
    let start = Instant::now();
    let until = a.duration.map(Duration::from_secs_f64);
    let stop =
        || tabula_robot::driver::stop_requested() || until.is_some_and(|d| start.elapsed() >= d);
    let world = server.serve(world, &stop).map_err(|e| anyhow!("{e}"))?;
    if let Some(path) = &a.save_scene {
        let text = crate::tasks::SavedScene::scene_toml(&world)?;
        std::fs::write(path, text).with_context(|| format!("cannot write {}", path.display()))?;
    }
    Ok(())
}
