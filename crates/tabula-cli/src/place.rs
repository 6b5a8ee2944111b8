//! `tabula place` and `tabula bench place`: placing an unknown held object stably
//! (seed 000) in the simulator, judged by its physics.

use crate::tasks::{TaskRunArgs, load_params, scene_robot};
use anyhow::Result;
use tabula_bench::place::{BenchRow, PlaceRun as PlaceJson, suite_of, task_of, trial};
use tabula_bench::report::place::section;
use tabula_bench::report::{Recorded, Report, recorded};
use tabula_sim::SimWorld;
use tabula_tasks::place::{PlaceParams, PlaceRequest};

#[derive(clap::Args)]
pub struct PlaceArgs {
    #[command(flatten)]
    pub run: TaskRunArgs,
    /// The arm holding the object (`auto`: the one whose gripper is closed).
    #[arg(long, default_value = "auto")]
    pub arm: String,
}

/// One placement by the robot served at `--connect`, judged there.
#[cfg(feature = "ros")]
fn place_remote(
    a: &PlaceArgs,
    world: &SimWorld,
    request: &PlaceRequest,
    params: &PlaceParams,
) -> Result<(PlaceJson, String)> {
    use crate::tasks::scene_robot_named;
    use tabula_bench::judged::planned_rest;
    use tabula_tasks::place::place;
    let (robot_name, robot) = scene_robot_named(world, a.run.robot.as_deref())?;
    let mut driver = crate::remote::connect(&a.run, &robot_name)?;
    let session = crate::remote::begin(
        &driver,
        tabula_ros::protocol::JudgedTask::new("place", a.run.seed, ()),
    )?;
    let outcome = place(&mut driver, &robot, request, params);
    let verdict = crate::remote::verdict(session, planned_rest(&outcome, params))?;
    let scene = crate::remote::scene(&driver)?;
    Ok((PlaceJson::of(outcome, verdict, false), scene))
}

pub fn run(a: PlaceArgs) -> Result<()> {
    if a.run.print_params {
        return crate::tasks::print_params::<PlaceParams>();
    }
    let params: PlaceParams = load_params(a.run.params.as_deref())?;
    let world = a.run.world()?;
    let robot = scene_robot(&world, a.run.robot.as_deref())?;
    crate::tasks::check_arm(&world, &robot, &a.arm)?;
    let request = PlaceRequest {
        arm: if a.arm == "auto" {
            tabula_bench::place::held_by(&world, &robot)
        } else {
            Some(a.arm.clone())
        },
        not_on: Vec::new(),
        near: None,
    };
    let sections = |report: &mut Report, out: &PlaceJson, recorded: Option<&Recorded>| {
        report.title = "tabula place".into();
        let section = section(report, out, &params, recorded)?;
        report.sections.push(section);
        Ok(())
    };
    if !a.run.connect.is_empty() {
        #[cfg(feature = "ros")]
        {
            let (out, scene) = place_remote(&a, &world, &request, &params)?;
            return a
                .run
                .finish(&scene, &out, out.success, print_summary, |r, o| {
                    sections(r, o, None)
                });
        }
        #[cfg(not(feature = "ros"))]
        anyhow::bail!("this tabula was built without ROS 2 support (feature `ros`)");
    }
    let (out, world, recorded) = recorded(a.run.recording(), |start| {
        tabula_bench::place::place_in(world, Some(&robot), (&request, &params), a.run.seed, start)
    })?;
    a.run
        .finish(&world, &out, out.success, print_summary, |report, out| {
            sections(report, out, recorded.as_ref())
        })
}

fn print_summary(out: &PlaceJson) {
    let r = &out.report;
    println!(
        "place{}: {} (arm {})",
        if out.dry_run { " (dry run)" } else { "" },
        if out.success { "success" } else { "FAILED" },
        r.arm.as_deref().unwrap_or("-")
    );
    if let Some(m) = &r.model {
        println!("  model: {}", tabula_bench::report::place::model_line(m));
    }
    if let Some(s) = &out.stable_pose {
        println!(
            "  stable pose: normal ({:.2}, {:.2}, {:.2}) in the tool, margin {:.1} mm, topples at {:.1}° (of {} poses)",
            s.support_normal[0],
            s.support_normal[1],
            s.support_normal[2],
            s.margin_m * 1e3,
            s.topple_deg,
            r.poses_found
        );
    }
    if let Some(s) = &r.surface {
        println!(
            "  surface: {:.3} m high at ({:.2}, {:.2}), {:.0} cm² ({} found)",
            s.height,
            s.centroid[0],
            s.centroid[1],
            s.area_m2 * 1e4,
            r.surfaces_found
        );
    }
    if let Some(g) = r.base_goal {
        println!(
            "  base drove to ({:.2}, {:.2}, {:.0}°)",
            g[0],
            g[1],
            g[2].to_degrees()
        );
    }
    if let Some(e) = &out.error {
        println!("  error ({}): {}", e.kind, e.message);
        for why in r.rejected.iter().take(10) {
            println!("    rejected: {why}");
        }
    }
    for p in &out.phases {
        println!(
            "  {:<22} {:>9.1} ms  {:<6}  decision CPU {:>7.1} ms",
            p.name,
            p.ms,
            if p.ok { "ok" } else { "failed" },
            p.plan_ms.unwrap_or(0.0)
        );
    }
    println!("  decision (CPU)         {:>9.1} ms", out.decision_ms);
    let v = &out.verdict;
    println!(
        "  verdict: `{}` on {}, {} its edges, {:.1}° from the planned pose, moved {:.1} mm after release, {} disturbed, {} furniture contacts",
        v.object,
        v.surface.as_deref().unwrap_or("nothing"),
        if v.inside_edges { "inside" } else { "outside" },
        v.orientation_error_deg,
        v.moved_after_release_m * 1e3,
        v.disturbed.len(),
        v.furniture_contacts.len()
    );
}

/// `tabula bench place`: the generated suite, each task placed in the simulator (both
/// cores, one task each, or spread over workers) and judged by physics.
pub fn bench(b: &crate::trials::SuiteRun<'_>) -> Result<()> {
    let (suite, save_failures) = (b.suite, b.save_failures);
    let kind = suite_of(suite)?;
    let params: PlaceParams = load_params(b.params)?;
    // Saved failures keep their meshes beside them.
    let mesh_dir = match save_failures {
        Some(d) => d.join("meshes"),
        None => std::env::temp_dir().join(format!("tabula-place-meshes-{}", std::process::id())),
    };
    if let Some(d) = save_failures {
        std::fs::create_dir_all(d)?;
    }
    let rows = b.run("place", |s| trial(s, kind, &params, &mesh_dir));
    // Failures are kept; so are slow decisions (over a second), to look into.
    if let (Some(d), Ok(rows)) = (save_failures, &rows) {
        for r in rows {
            if r.cause.is_some() || r.decision_ms > 1000.0 {
                let task = task_of(r.seed, kind, &mesh_dir)?;
                std::fs::write(
                    d.join(format!("place-{suite}-{}.toml", r.seed)),
                    &task.scene,
                )?;
            }
        }
    }
    if save_failures.is_none() {
        let _ = std::fs::remove_dir_all(&mesh_dir);
    }
    let rows: Vec<BenchRow> = rows?;
    // Failures by cause, for the report and the summary line.
    let mut causes: std::collections::BTreeMap<&str, usize> = Default::default();
    for r in &rows {
        if let Some(c) = &r.cause {
            *causes.entry(c.as_str()).or_default() += 1;
        }
    }
    if let Some(dir) = b.report {
        let command = format!(
            "tabula bench place --suite {suite} --trials {} --seed {}",
            b.count, b.seed
        );
        tabula_bench::report::place::bench_page(dir, command, &rows, &causes)?;
    }
    if b.json {
        println!("{}", serde_json::to_string_pretty(&rows)?);
        return Ok(());
    }
    for line in tabula_bench::report::place::bench_lines(suite, &rows, &causes) {
        println!("{line}");
    }
    Ok(())
}
