//! `tabula bench perception`: every perception stage timed on generated Kinect-like
//! frames (the protocol), plus quality against the simulator's labels.

use anyhow::Result;
use clap::Subcommand;
use tabula_bench::perception::{PerceptionBench, Timer, frame_rows};
use tabula_perception::TabletopParams;

#[derive(Subcommand)]
pub enum BenchCommand {
    /// Perception stages on generated 640×480 frames: CPU ms on one thread and wall ms
    /// on two, the nine-object frame first, then a suite of seeded scenes.
    Perception {
        /// Scenes in the quality suite (seeds 1..=N, 3–12 objects each).
        #[arg(long, default_value_t = 20, value_parser = crate::args::count_u64)]
        scenes: u64,
        /// Repetitions per stage (medians are reported).
        #[arg(long, default_value_t = 11, value_parser = crate::args::count)]
        reps: usize,
        #[arg(long)]
        json: bool,
    },
    /// The perception pipeline on PCD/PLY frames (real sensor frames, say), framed as
    /// `perceive` frames them: CPU ms on one thread and wall ms on two, on the
    /// organized frame and on the same points without their grid. The PCL anchor on
    /// the same files: `scripts/pcl_tabletop.sh REPS FILE…`.
    Frames {
        #[arg(long = "cloud", required = true)]
        clouds: Vec<std::path::PathBuf>,
        #[arg(long, default_value_t = 11, value_parser = crate::args::count)]
        reps: usize,
        /// `both`, `organized` or `unorganized`.
        #[arg(long, default_value = "both")]
        layout: String,
        /// Segment organized frames on every N-th pixel of every N-th row
        /// (`TabletopParams::frame_stride`).
        #[arg(long, default_value_t = 1, value_parser = clap::value_parser!(u8).range(1..=8))]
        stride: u8,
        #[arg(long)]
        json: bool,
    },
    /// Seed 001's integral test on generated Golem-III shelf scenes: success by physics,
    /// decision CPU time (perceive → grasp choice → every motion plan).
    PickPlace {
        /// Generated variants (seeds 1..=N) besides scenes/golem_shelves.toml.
        #[arg(long, default_value_t = 20, value_parser = crate::args::count_u64)]
        variants: u64,
        /// Run the table family with this robot (a .urdf or .xacro file, its gripper from
        /// `--srdf` or a TOML beside it) instead of Golem-III's shelves: an object standing
        /// alone on the clearing cell's table taken to a free spot of it.
        #[arg(long)]
        robot: Option<String>,
        #[arg(long)]
        json: bool,
    },
    /// Tidying on its generated family (a PR2, a table with 2–6 objects, one or two
    /// other tables): objects moved (physics), knocked over, decision CPU.
    Tidy {
        /// Tasks (seeds `seed`, `seed + 1`, …).
        #[arg(long, default_value_t = 20, value_parser = crate::args::count_u64)]
        tasks: u64,
        #[arg(long, default_value_t = 1, value_parser = crate::args::seed)]
        seed: u64,
        /// Write each generated task's scene into this folder (`tidy-SEED.toml`).
        #[arg(long)]
        save_scenes: Option<std::path::PathBuf>,
        #[arg(long)]
        json: bool,
    },
    /// Seed 002's table clearing on a generated suite: completion, objects per action,
    /// grasp success, push loops and collisions judged by physics; decision CPU per frame.
    Clear {
        /// `seed` (scenes/clutter.toml), `random` (3–12 objects, touching and stacked),
        /// `packed` (grids: every grasp blocked at first) or `pile` (20–30 dropped).
        #[arg(long, default_value = "random")]
        suite: String,
        #[arg(long, default_value_t = 50, value_parser = crate::args::count_u64)]
        scenes: u64,
        /// First scene seed (scenes use seed, seed + 1, …).
        #[arg(long, default_value_t = 1, value_parser = crate::args::seed)]
        seed: u64,
        /// Clear with this robot (a .urdf or .xacro file, its gripper from `--srdf` or a
        /// TOML beside it) instead of seed 002's WAM: it stands where its arm reaches the
        /// whole table and the bin.
        #[arg(long)]
        robot: Option<String>,
        /// Parameters (TOML, `ClearParams`).
        #[arg(long)]
        params: Option<std::path::PathBuf>,
        /// Print the parameters `--params` takes, with their defaults (SPEC's values), as
        /// TOML to start a file from, and exit.
        #[arg(long, exclusive = true)]
        print_params: bool,
        /// Write the scene of every run that does not clear its table, or touches an object
        /// it is not acting on, into this folder.
        #[arg(long)]
        save_failures: Option<std::path::PathBuf>,
        #[arg(long)]
        json: bool,
        #[command(flatten)]
        spread: crate::trials::TrialArgs,
    },
    /// Seed 000's placing on a generated suite: success by physics with 95 % intervals,
    /// failures by cause, decision CPU time.
    Place {
        /// `simple` (cubes, boxes, cylinders), `complex` (mugs, drills, bottles, …),
        /// `rooms` (simple objects in walled rooms with ramps, cones and sign drums the
        /// surface search must not take), or `simple-grips` / `complex-grips` (the same
        /// objects held anywhere a parallel gripper can hold them: turned at random, by
        /// a handle, a rim, an end).
        #[arg(long, default_value = "simple")]
        suite: String,
        #[arg(long, default_value_t = 20, value_parser = crate::args::count_u64)]
        trials: u64,
        /// First task seed (tasks use seed, seed + 1, …).
        #[arg(long, default_value_t = 1, value_parser = crate::args::seed)]
        seed: u64,
        /// Parameters (TOML, `PlaceParams`).
        #[arg(long)]
        params: Option<std::path::PathBuf>,
        /// Print the parameters `--params` takes, with their defaults (SPEC's values), as
        /// TOML to start a file from, and exit.
        #[arg(long, exclusive = true)]
        print_params: bool,
        /// Write the scene of every failed task (and of every decision over a second)
        /// into this folder.
        #[arg(long)]
        save_failures: Option<std::path::PathBuf>,
        #[arg(long)]
        json: bool,
        #[command(flatten)]
        spread: crate::trials::TrialArgs,
    },
    /// ROS 2 over zenoh: a 640×480 camera frame from publish (message built, CDR
    /// encoded) to decoded into a tabula cloud by a subscriber, on TCP loopback.
    #[cfg(feature = "ros")]
    Ros {
        #[arg(long, default_value_t = 100, value_parser = crate::args::count)]
        frames: usize,
        #[arg(long)]
        json: bool,
    },
    /// Stable poses of the test objects (written as OBJ files for the side-by-side with
    /// trimesh: `scripts/trimesh_stable_poses.py DIR`): median CPU ms, most likely pose.
    StablePoses {
        /// Folder the meshes are written to.
        #[arg(long, default_value = "target/stable-pose-meshes")]
        dir: std::path::PathBuf,
        #[arg(long, default_value_t = 21, value_parser = crate::args::count)]
        reps: usize,
        #[arg(long)]
        json: bool,
    },
}

impl BenchCommand {
    /// Benchmarks that drive robots in the simulator (Ctrl+C stops them).
    pub fn moves_robots(&self) -> bool {
        matches!(
            self,
            BenchCommand::PickPlace { .. }
                | BenchCommand::Clear { .. }
                | BenchCommand::Tidy { .. }
                | BenchCommand::Place { .. }
        )
    }
}

pub fn run(c: BenchCommand, report: Option<&std::path::Path>) -> Result<()> {
    match c {
        BenchCommand::Perception { scenes, reps, json } => {
            perception(scenes, reps.max(1), json, report)
        }
        BenchCommand::Frames {
            clouds,
            reps,
            layout,
            stride,
            json,
        } => frames(&clouds, (reps.max(1), stride.into()), &layout, json, report),
        BenchCommand::PickPlace {
            variants,
            robot,
            json,
        } => pick_place(variants, robot.as_deref(), json, report),
        BenchCommand::Tidy {
            tasks,
            seed,
            save_scenes,
            json,
        } => crate::tidy::bench(tasks, seed, save_scenes.as_deref(), json),
        BenchCommand::Clear {
            print_params: true, ..
        } => crate::tasks::print_params::<tabula_tasks::clear::ClearParams>(),
        BenchCommand::Clear {
            suite,
            scenes,
            seed,
            params,
            save_failures,
            json,
            spread,
            robot,
            ..
        } => crate::clear::bench(
            robot.as_deref(),
            &crate::trials::SuiteRun {
                suite: &suite,
                count: scenes,
                seed,
                params: params.as_deref(),
                save_failures: save_failures.as_deref(),
                json,
                report,
                spread: &spread,
            },
        ),
        BenchCommand::Place {
            print_params: true, ..
        } => crate::tasks::print_params::<tabula_tasks::place::PlaceParams>(),
        BenchCommand::Place {
            suite,
            trials,
            seed,
            params,
            save_failures,
            json,
            spread,
            ..
        } => crate::place::bench(&crate::trials::SuiteRun {
            suite: &suite,
            count: trials,
            seed,
            params: params.as_deref(),
            save_failures: save_failures.as_deref(),
            json,
            report,
            spread: &spread,
        }),
        #[cfg(feature = "ros")]
        BenchCommand::Ros { frames, json } => ros_latency(frames, json),
        BenchCommand::StablePoses { dir, reps, json } => {
            crate::stable::bench(&dir, reps, json, report)
        }
    }
}

/// Runs the generated shelf tasks (both cores, one task each) and prints a table.
fn pick_place(
    variants: u64,
    robot: Option<&str>,
    json: bool,
    report: Option<&std::path::Path>,
) -> Result<()> {
    use rayon::prelude::*;
    use tabula_bench::pick_place::BenchRow as PickPlaceRow;
    let mount = match robot {
        Some(file) => Some(crate::clear::robot_mount(file)?),
        None => None,
    };
    let progress = crate::progress::steps(variants, "tasks");
    let rows: Vec<Result<PickPlaceRow>> = (1..=variants)
        .into_par_iter()
        .map(|seed| {
            let _tick = crate::progress::Tick(&progress);
            match &mount {
                Some(m) => tabula_bench::pick_place::table_trial(seed, m),
                None => tabula_bench::pick_place::trial(seed),
            }
        })
        .collect();
    progress.finish_and_clear();
    let rows: Vec<PickPlaceRow> = rows.into_iter().collect::<Result<_>>()?;
    use tabula_bench::report::pick_place as page;
    if let Some(dir) = report {
        page::bench_page(dir, variants, &rows)?;
    }
    if json {
        println!("{}", page::bench_json(&rows));
        return Ok(());
    }
    for line in page::bench_lines(&rows) {
        println!("{line}");
    }
    Ok(())
}

/// `tabula bench frames`: framing (support search when the file gives no pose) and
/// the whole pipeline, timed together, on each file organized and unorganized.
fn frames(
    clouds: &[std::path::PathBuf],
    (reps, stride): (usize, usize),
    layout: &str,
    json: bool,
    report: Option<&std::path::Path>,
) -> Result<()> {
    if !["both", "organized", "unorganized"].contains(&layout) {
        anyhow::bail!("--layout is both, organized or unorganized, not `{layout}`");
    }
    let timer = Timer::new(reps)?;
    let params = TabletopParams {
        frame_stride: stride,
        ..TabletopParams::default()
    };
    let mut rows = Vec::new();
    let progress = crate::progress::steps(clouds.len() as u64, "frames");
    for path in clouds {
        let _tick = crate::progress::Tick(&progress);
        let file = crate::perceive::read_cloud_file(path)?;
        let name = path.display().to_string();
        rows.extend(frame_rows((&name, &file), layout, &params, &timer)?);
    }
    progress.finish_and_clear();
    let rows = serde_json::to_value(&rows)?;
    let rows = rows.as_array().cloned().unwrap_or_default();
    if let Some(dir) = report {
        let what = (layout, reps, clouds.len());
        tabula_bench::report::perception::frames_page(dir, what, &rows)?;
    }
    if json {
        println!("{}", serde_json::to_string_pretty(&rows)?);
        return Ok(());
    }
    for line in tabula_bench::report::perception::frames_lines(&rows) {
        println!("{line}");
    }
    Ok(())
}

fn perception(
    scenes: u64,
    reps: usize,
    json: bool,
    report: Option<&std::path::Path>,
) -> Result<()> {
    let progress = crate::progress::steps(scenes, "scenes");
    let b = PerceptionBench::run(scenes, reps, &mut || progress.inc(1))?;
    progress.finish_and_clear();
    if let Some(dir) = report {
        tabula_bench::report::perception::bench_page(dir, &b)?;
    }
    if json {
        println!("{}", serde_json::to_string_pretty(&b.to_json()?)?);
    } else {
        for line in b.lines() {
            println!("{line}");
        }
    }
    Ok(())
}

/// `tabula bench ros`: the frame of scenes/pr2_holding.toml's head camera, published
/// and received `frames` times.
#[cfg(feature = "ros")]
fn ros_latency(frames: usize, json: bool) -> Result<()> {
    let latency = tabula_bench::ros::Latency::measure(frames)?;
    if json {
        println!("{}", serde_json::to_string_pretty(&latency)?);
    } else {
        for line in latency.lines() {
            println!("{line}");
        }
    }
    Ok(())
}
