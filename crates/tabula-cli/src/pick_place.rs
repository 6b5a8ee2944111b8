//! `tabula pick-place`: seed 001's pick and place by coordinates in the simulator,
//! judged by its physics (or against a robot served at `--connect`).

use crate::tasks::{TaskRunArgs, check_arm, load_params, scene_robot};
use anyhow::{Result, bail};
use clap::Args;
use tabula_bench::report::pick_place::section;
use tabula_bench::report::recorded;
use tabula_geom::Vec3;
use tabula_tasks::pick_place::{PickPlaceParams, PickPlaceRequest};

pub use tabula_bench::pick_place::PickPlaceRun as PickPlaceJson;

#[derive(Args)]
pub struct PickPlaceArgs {
    #[command(flatten)]
    pub run: TaskRunArgs,
    /// Which arm: a name from the robot's description (`left`, `right`) or `auto`.
    #[arg(long, default_value = "auto")]
    pub arm: String,
    /// Approximate world position of the object (m).
    #[arg(long, num_args = 3, allow_negative_numbers = true, value_names = ["X", "Y", "Z"], required = true, value_parser = crate::args::finite)]
    pub pick: Vec<f64>,
    /// Where the object goes (m): its footprint centre; the surface is found under Z.
    #[arg(long, num_args = 3, allow_negative_numbers = true, value_names = ["X", "Y", "Z"], required = true, value_parser = crate::args::finite)]
    pub place: Vec<f64>,
}

fn vec3(v: &[f64], what: &str) -> Result<Vec3> {
    match v {
        [x, y, z] if v.iter().all(|c| c.is_finite()) => Ok(Vec3::new(*x, *y, *z)),
        _ => bail!("--{what} takes three finite numbers"),
    }
}

/// Runs one pick and place in the simulator, judges it, and saves what was asked.
pub fn run_pick_place(a: &PickPlaceArgs) -> Result<PickPlaceJson> {
    let pick = vec3(&a.pick, "pick")?;
    let place = vec3(&a.place, "place")?;
    let params: PickPlaceParams = load_params(a.run.params.as_deref())?;
    let request = PickPlaceRequest {
        arm: (a.arm != "auto").then(|| a.arm.clone()),
        pick,
        place,
    };
    if !a.run.connect.is_empty() {
        #[cfg(feature = "ros")]
        {
            let (out, scene) = pick_place_remote(a, &request, &params)?;
            a.run.save(&scene, &out, |report, out| {
                report.title = "tabula pick-place".into();
                let section = section(report, out, None)?;
                report.sections.push(section);
                Ok(())
            })?;
            return Ok(out);
        }
        #[cfg(not(feature = "ros"))]
        bail!("this tabula was built without ROS 2 support (feature `ros`)");
    }
    let world = a.run.world()?;
    let robot = scene_robot(&world, a.run.robot.as_deref())?;
    check_arm(&world, &robot, &a.arm)?;
    let (out, world, recorded) = recorded(a.run.recording(), |start| {
        tabula_bench::pick_place::pick_place_in(
            world,
            a.run.robot.as_deref(),
            (&request, &params),
            a.run.seed,
            start,
        )
    })?;
    a.run.save(&world, &out, |report, out| {
        report.title = "tabula pick-place".into();
        let section = section(report, out, recorded.as_ref())?;
        report.sections.push(section);
        Ok(())
    })?;
    Ok(out)
}

/// One pick and place by the robot served at `--connect`, judged there.
#[cfg(feature = "ros")]
fn pick_place_remote(
    a: &PickPlaceArgs,
    request: &PickPlaceRequest,
    params: &PickPlaceParams,
) -> Result<(PickPlaceJson, String)> {
    use crate::tasks::{load_world, scene_robot_named};
    use tabula_tasks::pick_place::pick_place;
    let world = load_world(a.run.scene()?)?.1;
    let (robot_name, robot) = scene_robot_named(&world, a.run.robot.as_deref())?;
    check_arm(&world, &robot_name, &a.arm)?;
    let mut driver = crate::remote::connect(&a.run, &robot_name)?;
    let session = crate::remote::begin(
        &driver,
        tabula_ros::protocol::JudgedTask::new(
            "pick-place",
            a.run.seed,
            tabula_ros::protocol::ground::PickPlace {
                pick: request.pick.to_array(),
                place: request.place.to_array(),
            },
        ),
    )?;
    let outcome = pick_place(&mut driver, &robot, request, params);
    let verdict = crate::remote::verdict(session, None)?;
    let scene = crate::remote::scene(&driver)?;
    Ok((PickPlaceJson::of(outcome, verdict, false), scene))
}

pub fn run(a: PickPlaceArgs) -> Result<()> {
    if a.run.print_params {
        return crate::tasks::print_params::<PickPlaceParams>();
    }
    let out = run_pick_place(&a)?;
    if a.run.json {
        println!("{}", serde_json::to_string_pretty(&out)?);
    } else {
        let r = &out.report;
        println!(
            "pick-place{}: {} (arm {}, {} grasp)",
            if out.dry_run { " (dry run)" } else { "" },
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
    match crate::exit::of_task(out.success) {
        crate::exit::OK => Ok(()),
        status => std::process::exit(status),
    }
}
