//! `tabula pick-place`: the task layer run in the simulator, judged by its physics.

use anyhow::{Context, Result, bail};
use clap::Args;
use serde::Serialize;
use std::cell::RefCell;
use std::path::{Path, PathBuf};
use std::rc::Rc;
use tabula_geom::{Pose, Vec3};
use tabula_sim::world::EntityKind;
use tabula_sim::{PhysicsParams, Scene, SimDriver, SimWorld};
use tabula_tasks::pick_place::{PickPlaceParams, PickPlaceRequest, pick_place};

#[derive(Args)]
pub struct PickPlaceArgs {
    #[arg(long)]
    pub scene: PathBuf,
    /// Which arm: a name from the robot's description (`left`, `right`) or `auto`.
    #[arg(long, default_value = "auto")]
    pub arm: String,
    /// Approximate world position of the object (m).
    #[arg(long, num_args = 3, allow_negative_numbers = true, value_names = ["X", "Y", "Z"], required = true)]
    pub pick: Vec<f64>,
    /// Where the object goes (m): its footprint centre; the surface is found under Z.
    #[arg(long, num_args = 3, allow_negative_numbers = true, value_names = ["X", "Y", "Z"], required = true)]
    pub place: Vec<f64>,
    /// The robot to drive when the scene has several.
    #[arg(long)]
    pub robot: Option<String>,
    /// Parameters (TOML, `PickPlaceParams`).
    #[arg(long)]
    pub params: Option<PathBuf>,
    /// Camera noise seed.
    #[arg(long, default_value_t = 1)]
    pub seed: u64,
    #[arg(long)]
    pub json: bool,
    /// Write the final world as a scene file.
    #[arg(long)]
    pub save_scene: Option<PathBuf>,
    /// Write a report (run.json and index.html) into this folder.
    #[arg(long)]
    pub report: Option<PathBuf>,
}

/// The physics verdict on a placement (ground truth, never used for decisions).
#[derive(Debug, Clone, Serialize)]
pub struct Verdict {
    pub success: bool,
    /// The object the task was asked to move (the one nearest the pick position).
    pub object: String,
    /// Horizontal distance of the object's footprint centre from the target (m).
    pub target_error: f64,
    /// Angle between the object's up axis before and after (rad).
    pub tilt: f64,
    pub resting: bool,
    /// Robot–furniture contacts seen during the motions (link, furniture).
    pub furniture_contacts: Vec<(String, String)>,
    /// Other objects moved by more than 1 cm.
    pub disturbed: Vec<String>,
    pub final_pose: [f64; 6],
}

pub fn load_world(scene_path: &Path) -> Result<(Scene, SimWorld)> {
    let scene = Scene::load(scene_path)?;
    let world = SimWorld::from_scene(&scene, PhysicsParams::default())
        .with_context(|| format!("{}", scene_path.display()))?;
    Ok((scene, world))
}

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

fn vec3(v: &[f64], what: &str) -> Result<Vec3> {
    match v {
        [x, y, z] if v.iter().all(|c| c.is_finite()) => Ok(Vec3::new(*x, *y, *z)),
        _ => bail!("--{what} takes three finite numbers"),
    }
}

/// Everything `pick-place` prints with `--json`.
#[derive(Serialize)]
pub struct PickPlaceJson {
    pub success: bool,
    pub error: Option<String>,
    pub error_message: Option<String>,
    #[serde(flatten)]
    pub report: tabula_tasks::pick_place::PickPlaceReport,
    pub verdict: Verdict,
    pub final_pose: [f64; 6],
}

/// Runs one pick and place in the simulator and judges it.
pub fn run_pick_place(a: &PickPlaceArgs) -> Result<PickPlaceJson> {
    let pick = vec3(&a.pick, "pick")?;
    let place = vec3(&a.place, "place")?;
    let params: PickPlaceParams = match &a.params {
        Some(p) => {
            let text = std::fs::read_to_string(p)
                .with_context(|| format!("cannot read {}", p.display()))?;
            toml::from_str(&text).with_context(|| format!("{}", p.display()))?
        }
        None => PickPlaceParams::default(),
    };
    let (_, mut world) = load_world(&a.scene)?;
    world.settle();
    let robot_name = scene_robot(&world, a.robot.as_deref())?;
    let robot = {
        let r = world.robot(&robot_name)?;
        tabula_robot::robots::NamedRobot::new(r.model.clone(), r.description.clone(), &robot_name)
    };
    let before = world.object_poses();
    let target_object = before
        .iter()
        .min_by(|x, y| {
            (x.1.translation - pick)
                .length()
                .total_cmp(&(y.1.translation - pick).length())
        })
        .map(|(n, p)| (n.clone(), *p))
        .context("the scene has no objects")?;
    let mut driver = SimDriver::new(world, &robot_name, a.seed)?;
    let contacts: Rc<RefCell<Vec<(String, String)>>> = Rc::default();
    {
        let contacts = contacts.clone();
        let robot_name = robot_name.clone();
        driver.observe(move |w| {
            if let Ok(found) = w.robot_contacts(&robot_name, &[EntityKind::Furniture], 1e-3) {
                let mut c = contacts.borrow_mut();
                for pair in found {
                    if !c.contains(&pair) {
                        c.push(pair);
                    }
                }
            }
        });
    }
    let request = PickPlaceRequest {
        arm: (a.arm != "auto").then(|| a.arm.clone()),
        pick,
        place,
    };
    let outcome = pick_place(&mut driver, &robot, &request, &params);
    let mut world = driver.world;
    world.settle();
    let (object, start_pose) = target_object;
    let now = world.pose(&object)?;
    let tilt = (now.rotation * Vec3::Z).angle_between(start_pose.rotation * Vec3::Z);
    let target_error = (now.translation.truncate() - place.truncate()).length();
    let resting = world
        .physics
        .bodies
        .iter()
        .all(|(_, b)| !b.is_dynamic() || b.linvel().length() < 0.01);
    let disturbed: Vec<String> = before
        .iter()
        .filter(|(n, _)| *n != object)
        .filter(|(n, p)| {
            world
                .pose(n)
                .is_ok_and(|q| (q.translation - p.translation).length() > 0.01)
        })
        .map(|(n, _)| n.clone())
        .collect();
    let furniture_contacts = contacts.borrow().clone();
    let final_pose = pose6(&now);
    let success = outcome.error.is_none()
        && target_error <= 0.02
        && tilt <= 0.1
        && resting
        && furniture_contacts.is_empty()
        && world.held_objects(&robot_name).is_empty();
    if let Some(out) = &a.save_scene {
        let text = world
            .to_scene()
            .to_toml()
            .map_err(|e| anyhow::anyhow!("cannot write the scene: {e}"))?;
        std::fs::write(out, text).with_context(|| format!("cannot write {}", out.display()))?;
    }
    Ok(PickPlaceJson {
        success,
        error: outcome.error.as_ref().map(|e| e.kind().to_string()),
        error_message: outcome.error.as_ref().map(|e| e.to_string()),
        report: outcome.report,
        verdict: Verdict {
            success,
            object,
            target_error,
            tilt,
            resting,
            furniture_contacts,
            disturbed,
            final_pose,
        },
        final_pose,
    })
}

fn pose6(p: &Pose) -> [f64; 6] {
    let rpy = tabula_geom::rpy_from_quat(p.rotation);
    [
        p.translation.x,
        p.translation.y,
        p.translation.z,
        rpy[0],
        rpy[1],
        rpy[2],
    ]
}

pub fn run(a: PickPlaceArgs) -> Result<()> {
    let out = run_pick_place(&a)?;
    if let Some(dir) = &a.report {
        std::fs::create_dir_all(dir).with_context(|| format!("cannot create {}", dir.display()))?;
        std::fs::write(dir.join("run.json"), serde_json::to_string_pretty(&out)?)?;
    }
    if a.json {
        println!("{}", serde_json::to_string_pretty(&out)?);
    } else {
        let r = &out.report;
        println!(
            "pick-place: {} (arm {}, {} grasp)",
            if out.success { "success" } else { "FAILED" },
            r.arm.as_deref().unwrap_or("-"),
            r.grasp
                .map_or("-".into(), |g| format!("{g:?}").to_lowercase()),
        );
        if let Some(e) = &out.error_message {
            println!("  error: {e}");
            for why in r.rejected.iter().take(12) {
                println!("    rejected: {why}");
            }
        }
        for p in &r.phases {
            println!(
                "  {:<22} {:>9.1} ms  {}{}",
                p.name,
                p.ms,
                if p.ok { "ok" } else { "failed" },
                p.plan_ms
                    .map_or(String::new(), |m| format!("  (planned in {m:.1} ms)"))
            );
        }
        println!("  decision (CPU)        {:>9.1} ms", r.decision_cpu_ms);
        let v = &out.verdict;
        println!(
            "  verdict: `{}` {:.1} cm from the target, tilted {:.1}°, {}; furniture contacts: {}",
            v.object,
            v.target_error * 100.0,
            v.tilt.to_degrees(),
            if v.resting { "resting" } else { "moving" },
            v.furniture_contacts.len()
        );
    }
    if !out.success {
        std::process::exit(2);
    }
    Ok(())
}
