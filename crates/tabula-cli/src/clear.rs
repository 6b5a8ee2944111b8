//! `tabula clear`: seed 002's table clearing run in the simulator, judged by its physics.

use crate::tasks::{load_world, scene_robot};
use anyhow::{Context, Result, anyhow};
use clap::Args;
use serde::Serialize;
use std::path::PathBuf;
use tabula_geom::Vec3;
use tabula_geom::parry::bounding_volume::BoundingVolume;
use tabula_robot::robots::NamedRobot;
use tabula_sim::verdict::{ClearJudge, ClearVerdict};
use tabula_sim::{SimDriver, SimWorld};
use tabula_tasks::clear::{ClearEvent, ClearParams, ClearReport, ClearRequest, clear};

#[derive(Args)]
pub struct ClearArgs {
    #[arg(long)]
    pub scene: PathBuf,
    /// The robot to drive when the scene has several.
    #[arg(long)]
    pub robot: Option<String>,
    /// Parameters (TOML, `ClearParams`).
    #[arg(long)]
    pub params: Option<PathBuf>,
    /// Stop after this many actions (default: 3 per object seen first, plus 5).
    #[arg(long)]
    pub max_actions: Option<usize>,
    /// Camera noise seed.
    #[arg(long, default_value_t = 1)]
    pub seed: u64,
    #[arg(long)]
    pub json: bool,
    /// Write the final world as a scene file.
    #[arg(long)]
    pub save_scene: Option<PathBuf>,
    /// Write a report (run.json) into this folder.
    #[arg(long)]
    pub report: Option<PathBuf>,
}

/// Everything `clear` prints with `--json`: the task's own metrics, the judged ones.
#[derive(Serialize)]
pub struct ClearJson {
    /// Every object that stood on the table ended in the bin.
    pub success: bool,
    pub error: Option<String>,
    pub error_message: Option<String>,
    #[serde(flatten)]
    pub report: ClearReport,
    /// Arm–object contacts with objects the arm was not acting on (judged).
    pub collisions: usize,
    pub verdict: ClearVerdict,
}

pub fn load_params(path: Option<&std::path::Path>) -> Result<ClearParams> {
    Ok(match path {
        Some(p) => {
            let text = std::fs::read_to_string(p)
                .with_context(|| format!("cannot read {}", p.display()))?;
            toml::from_str(&text).with_context(|| format!("{}", p.display()))?
        }
        None => ClearParams::default(),
    })
}

/// The bin's opening (top centre of its bounds), where objects are let go.
fn drop_point(world: &SimWorld, bin: &str) -> Result<Vec3> {
    let b = world
        .furniture_shapes()
        .into_iter()
        .filter(|(n, _, _)| n == bin)
        .map(|(_, s, p)| s.compute_aabb(&p))
        .reduce(|a, b| a.merged(&b))
        .ok_or_else(|| anyhow!("the scene has no furniture named `{bin}` to clear into"))?;
    let c = b.center();
    Ok(Vec3::new(c.x, c.y, b.maxs.z))
}

/// Clears the table of `world` with its robot, judged by physics; returns the world
/// afterwards.
pub fn clear_in(
    mut world: SimWorld,
    robot: Option<&str>,
    params: &ClearParams,
    max_actions: Option<usize>,
    seed: u64,
) -> Result<(ClearJson, SimWorld)> {
    let robot_name = scene_robot(&world, robot)?;
    let robot = {
        let r = world.robot(&robot_name)?;
        NamedRobot::new(r.model.clone(), r.description.clone(), &robot_name)
    };
    world.settle();
    let request = ClearRequest {
        arm: None,
        drop_point: drop_point(&world, "bin")?,
        obstacles: world.furniture_shapes(),
        max_actions,
    };
    let start = world.object_poses();
    let mut driver = SimDriver::new(world, &robot_name, seed)?;
    let mut judge = ClearJudge::default();
    driver.observe(judge.observer(&robot_name));
    let outcome = clear(
        &mut driver,
        &robot,
        &request,
        params,
        &mut |d: &mut SimDriver, e| match e {
            ClearEvent::Before(a) => judge.before(&d.world, Vec3::from_array(a.position)),
            ClearEvent::After(_) => judge.after(&d.world),
        },
    );
    let mut world = driver.world;
    world.settle();
    let verdict = judge.verdict(&start, &world, "table", "bin");
    let (report, error) = match outcome {
        Ok(r) => (r, None),
        Err(e) => (ClearReport::default(), Some(e)),
    };
    Ok((
        ClearJson {
            success: error.is_none() && verdict.objects > 0 && verdict.in_bin == verdict.objects,
            error: error.as_ref().map(|e| e.kind().to_string()),
            error_message: error.as_ref().map(|e| e.to_string()),
            report,
            collisions: verdict.collisions.len(),
            verdict,
        },
        world,
    ))
}

pub fn run(a: ClearArgs) -> Result<()> {
    let params = load_params(a.params.as_deref())?;
    let (_, world) = load_world(&a.scene)?;
    let (out, world) = clear_in(world, a.robot.as_deref(), &params, a.max_actions, a.seed)?;
    if let Some(path) = &a.save_scene {
        let text = world
            .to_scene()
            .to_toml()
            .map_err(|e| anyhow!("cannot write the scene: {e}"))?;
        std::fs::write(path, text).with_context(|| format!("cannot write {}", path.display()))?;
    }
    if let Some(dir) = &a.report {
        std::fs::create_dir_all(dir).with_context(|| format!("cannot create {}", dir.display()))?;
        std::fs::write(dir.join("run.json"), serde_json::to_string_pretty(&out)?)?;
    }
    if a.json {
        println!("{}", serde_json::to_string_pretty(&out)?);
    } else {
        print_summary(&out);
    }
    if !out.success {
        std::process::exit(2);
    }
    Ok(())
}

fn print_summary(out: &ClearJson) {
    let r = &out.report;
    let v = &out.verdict;
    println!(
        "clear: {} — {} of {} objects in the bin, {} left on the table ({})",
        if out.success { "success" } else { "INCOMPLETE" },
        v.in_bin,
        v.objects,
        v.left_on_table,
        if r.stop.is_empty() { "-" } else { &r.stop }
    );
    if let Some(e) = &out.error_message {
        println!("  error: {e}");
    }
    for a in &r.log {
        println!(
            "  frame {:>2}: {:<10} o{:<3} at ({:.3}, {:.3}){}  {}",
            a.frame,
            a.action,
            a.object,
            a.position[0],
            a.position[1],
            a.push
                .map_or(String::new(), |(_, l)| format!(" by {:.2} m", l)),
            if a.ok {
                "ok".to_string()
            } else {
                format!("failed: {}", a.error.as_deref().unwrap_or("-"))
            }
        );
    }
    println!(
        "  actions {} (grasps {}, failed {}, pushes {}), {:.2} objects per action; no-plan frames {}, IK backtracks {}, push loops {}",
        r.actions,
        r.grasps,
        r.failed_grasps,
        r.pushes,
        v.in_bin as f64 / r.actions.max(1) as f64,
        r.no_plan_frames,
        r.ik_backtracks,
        r.push_loops
    );
    println!(
        "  decision (CPU, frame in → first action): median {:.1} ms, p95 {:.1}, max {:.1} — perception {:.1}, predicates {:.1}, planning {:.1}, IK {:.1} (medians)",
        r.decision_ms.median,
        r.decision_ms.p95,
        r.decision_ms.max,
        r.perception_ms,
        r.predicates_ms,
        r.planning_ms,
        r.ik_ms
    );
    println!(
        "  collisions with other objects: {}; moved by accident: {}",
        out.collisions,
        v.disturbed.len()
    );
}
