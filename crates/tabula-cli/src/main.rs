//! `tabula`: the command-line face of the tabula manipulation stack.

mod args;
mod arm;
mod bench;
mod clear;
mod demo;
#[cfg(feature = "ros")]
mod graph;
mod ik;
mod motion;
mod perceive;
mod pick_place;
mod place;
mod plan;
mod progress;
#[cfg(feature = "ros")]
mod remote;
mod robot;
#[cfg(feature = "ros")]
mod serve;
#[cfg(feature = "ros")]
mod services;
mod sim;
mod stable;
mod tasks;
mod teleop;
mod tidy;
mod trials;
#[cfg(feature = "ros")]
mod worker;

use clap::{Parser, Subcommand};

/// Exit statuses (INPUT_POLICY.md): scripts tell a failed task from a bad input from a
/// bug without reading the output.
pub mod exit {
    /// The command did what it was asked.
    pub const OK: i32 = 0;
    /// The input (a file, a flag, a parameter) cannot be used; one line says why.
    pub const ERROR: i32 = 1;
    /// The input was fine but there is no answer: unsolvable, no plan, the task failed.
    pub const NO_SOLUTION: i32 = 2;
    /// The command line itself is malformed (BSD's EX_USAGE).
    pub const USAGE: i32 = 64;
    /// A bug: a panic reached the top (BSD's EX_SOFTWARE).
    pub const INTERNAL: i32 = 70;
    /// The operator stopped the run (Ctrl+C), as shells report SIGINT: 128 + 2.
    pub const STOPPED: i32 = 130;

    /// The status a task run ends with: stopped, done, or no solution (and the time
    /// limit's error when it ran out).
    pub fn of_task(success: bool) -> i32 {
        if time_is_up() {
            time_up_error()
        } else if tabula_robot::driver::stop_requested() {
            STOPPED
        } else if success {
            OK
        } else {
            NO_SOLUTION
        }
    }

    /// Set once `--time-limit` has run out.
    static TIME_UP: std::sync::OnceLock<f64> = std::sync::OnceLock::new();

    pub fn time_is_up() -> bool {
        TIME_UP.get().is_some()
    }

    /// The error `--time-limit` ends a run with.
    pub fn time_up_error() -> ! {
        // The watchdog and the main thread may both get here: one line only.
        static SAID: std::sync::atomic::AtomicBool = std::sync::atomic::AtomicBool::new(false);
        if !SAID.swap(true, std::sync::atomic::Ordering::SeqCst) {
            let limit = TIME_UP.get().copied().unwrap_or(f64::NAN);
            eprintln!("error: the time limit of {limit} s (--time-limit) ran out");
        }
        std::process::exit(ERROR);
    }

    /// `--time-limit`: a watchdog that, at the limit, asks every driver to stop (the
    /// robot holds where it is), gives the command two seconds to wind down, and ends
    /// the process with the limit named — whatever the command was doing (a parser, a
    /// search, a physics step).
    pub fn end_after(limit: f64) {
        std::thread::spawn(move || {
            std::thread::sleep(std::time::Duration::from_secs_f64(limit));
            let _ = TIME_UP.set(limit);
            tabula_robot::driver::request_stop();
            std::thread::sleep(std::time::Duration::from_secs(2));
            time_up_error();
        });
    }

    /// Ctrl+C while robots move: the first asks every driver to stop (the robot holds
    /// where it is, the run ends, `--save-scene` is written, the status is 130); a
    /// second quits at once.
    pub fn stop_on_ctrl_c() {
        let _ = ctrlc::set_handler(|| {
            if tabula_robot::driver::stop_requested() {
                std::process::exit(STOPPED);
            }
            tabula_robot::driver::request_stop();
            eprintln!("stopping: the robot holds where it is (Ctrl+C again quits at once)");
        });
    }
}

/// tabula — perceive, model, place and clear with one Rust workspace.
#[derive(Parser)]
#[command(name = "tabula", version, about, propagate_version = true)]
struct Cli {
    /// Log what the tasks do on stderr: -v phases and decisions, -vv details, -vvv all.
    #[arg(short, long, action = clap::ArgAction::Count, global = true)]
    verbose: u8,
    #[command(flatten)]
    robot_files: args::RobotFileArgs,
    /// End any command after this many seconds of wall time: a robot that moves is
    /// stopped first (it holds where it is), then the run ends with an error naming the
    /// limit (exit 1).
    #[arg(long, global = true, allow_negative_numbers = true, value_name = "SECONDS", value_parser = args::seconds)]
    time_limit: Option<f64>,
    #[command(subcommand)]
    command: Command,
}

#[derive(Subcommand)]
enum Command {
    /// The main job: the four jobs end to end in the simulator (placing, clearing, pick
    /// and place, tidying), then the capabilities they stand on; writes a report.
    Demo {
        /// Where the report goes (index.html with pictures, plots and 3D replays).
        #[arg(long, default_value = "tabula-demo")]
        report: std::path::PathBuf,
    },
    /// A manipulation service: move an arm to joint values, a pose or a named pose, open
    /// or close a gripper — in the simulator or, with --dry-run, through a fake driver.
    Arm(arm::ArmArgs),
    /// Benchmarks that print the tables in BENCHMARKS.md.
    Bench {
        /// Write a report into this folder: index.html with the numbers, success per
        /// class and timing distributions as plots, and run.json.
        #[arg(long, global = true)]
        report: Option<std::path::PathBuf>,
        #[command(subcommand)]
        command: bench::BenchCommand,
    },
    /// Clear a cluttered table into the bin by grasps and pushes, replanning after every
    /// action (seed 002), in the simulator, judged by its physics.
    Clear(clear::ClearArgs),
    /// Take every object from one table and stand each on another surface the robot
    /// finds (clearing's perception and grasps, placing's stable poses and approach),
    /// in the simulator, judged by its physics.
    Tidy(tidy::TidyArgs),
    /// The ROS 2 graph of a zenoh network (nodes, topics, services with their types),
    /// from rmw_zenoh's liveliness tokens: `ros2 node list` without ROS.
    #[cfg(feature = "ros")]
    Graph(graph::GraphArgs),
    /// Inverse and forward kinematics: solve, benchmark, inspect robots.
    Ik {
        #[command(subcommand)]
        command: ik::IkCommand,
    },
    /// Motion planning: collision world, RRT-Connect, benchmarks (MoveIt/OMPL's role).
    Motion {
        #[command(subcommand)]
        command: motion::MotionCommand,
    },
    /// Pick an object at given coordinates and place it at others (seed 001's integral
    /// test), in the simulator, judged by its physics.
    PickPlace(pick_place::PickPlaceArgs),
    /// Place the object the robot holds stably on a free spot of a surface it finds
    /// (seed 000): scan it, find how it rests, search surfaces, approach, put it down;
    /// in the simulator, judged by its physics.
    Place(place::PlaceArgs),
    /// Perception: surfaces, the table, its objects and free space in a PCD/PLY frame.
    Perceive(perceive::PerceiveArgs),
    /// Task planning in PDDL: plan, validate, benchmark (Fast Downward's role).
    Plan(plan::PlanArgs),
    /// Robot files: the description a URDF and its SRDF give (`robot describe`).
    Robot {
        #[command(subcommand)]
        command: robot::RobotCommand,
    },
    /// Serve the simulator as a ROS 2 robot over zenoh (rmw_zenoh's conventions): point
    /// clouds, joint states and TF out, trajectories and gripper commands in, and the
    /// driver services `place`/`clear`/`pick-place --connect` drive it through.
    #[cfg(feature = "ros")]
    Serve(serve::ServeArgs),
    /// The built-in simulator: settle scenes, capture depth frames, render snapshots.
    Sim {
        #[command(subcommand)]
        command: sim::SimCommand,
    },
    /// Tele-operate the gripper from the keyboard in a terminal UI: steps in the base or
    /// the tool frame, checked and executed in the simulator (seed 000's Module 0).
    Teleop(teleop::TeleopArgs),
    /// Serve benchmark trials to `tabula bench place|clear --workers N` over zenoh.
    #[cfg(feature = "ros")]
    Worker(worker::WorkerArgs),
    /// How an object rests on a table (seed 000): stable poses of a mesh or a scanned
    /// cloud with their stability margins and landing probabilities.
    StablePoses(stable::StablePosesArgs),
    /// The built-in scenes: `--scene NAME` loads one from any folder; `tabula scenes
    /// NAME` prints its TOML to start your own from.
    Scenes {
        /// A scene to print (default: list them all).
        name: Option<String>,
    },
}

fn main() {
    // `tabula … | head` should end quietly when the pipe closes, as Unix tools do,
    // rather than panic on the next print.
    #[cfg(unix)]
    // SAFETY: resetting a signal disposition to its default before any thread starts.
    unsafe {
        libc::signal(libc::SIGPIPE, libc::SIG_DFL);
    }
    std::panic::set_hook(Box::new(|info| {
        if tabula_geom::guard::is_quiet() {
            return;
        }
        let message = tabula_geom::guard::panic_message(info.payload());
        let place = info
            .location()
            .map(|l| format!(" at {}:{}", l.file(), l.line()))
            .unwrap_or_default();
        eprintln!(
            "internal error: {}{place} — a bug in tabula; please report it with the command",
            tabula_geom::input::clip(&message, 200)
        );
        std::process::exit(exit::INTERNAL);
    }));
    let cli = match Cli::try_parse_from(args::negative_exponents(std::env::args_os())) {
        Ok(cli) => cli,
        Err(e) if !e.use_stderr() => {
            // --help and --version.
            let _ = e.print();
            std::process::exit(exit::OK);
        }
        Err(e) => {
            // One line, as every error: clap's first paragraph names the flag and the
            // value (or lists the missing arguments on the lines below it); its tips
            // (a similar flag for a misspelled one, `--` before a value) join it.
            let text = e.render().to_string();
            let mut lines = text.lines().map(str::trim).skip_while(|l| l.is_empty());
            let first: Vec<&str> = lines.by_ref().take_while(|l| !l.is_empty()).collect();
            let mut line = first.join(" ");
            for tip in lines.filter(|l| l.starts_with("tip:")) {
                line = format!("{line}; {tip}");
            }
            eprintln!("{line} (see --help)");
            std::process::exit(exit::USAGE);
        }
    };
    progress::init_logging(cli.verbose);
    if let Err(e) = cli.robot_files.install() {
        eprintln!("error: {e}");
        std::process::exit(exit::USAGE);
    }
    // Commands that move robots stop them on Ctrl+C; the others keep the default
    // (the process ends at once).
    let moves_robots = match &cli.command {
        Command::Demo { .. }
        | Command::Clear(_)
        | Command::Tidy(_)
        | Command::Place(_)
        | Command::PickPlace(_) => true,
        #[cfg(feature = "ros")]
        Command::Serve(_) | Command::Worker(_) => true,
        Command::Bench { command, .. } => command.moves_robots(),
        _ => false,
    };
    if moves_robots {
        exit::stop_on_ctrl_c();
    }
    if let Some(limit) = cli.time_limit {
        exit::end_after(limit);
    }
    let result = match cli.command {
        Command::Demo { report } => demo::run(&report),
        Command::Arm(args) => arm::run(args),
        Command::Teleop(args) => teleop::run(args),
        Command::Bench { command, report } => bench::run(command, report.as_deref()),
        Command::Clear(args) => clear::run(args),
        Command::Tidy(args) => tidy::run(args),
        Command::Ik { command } => ik::run(command),
        #[cfg(feature = "ros")]
        Command::Graph(args) => graph::run(args),
        Command::Plan(args) => plan::run(args),
        Command::Robot { command } => robot::run(command),
        Command::Motion { command } => motion::run(command),
        Command::Perceive(args) => perceive::run(args),
        Command::Place(args) => place::run(args),
        Command::PickPlace(args) => pick_place::run(args),
        Command::Sim { command } => sim::run(command),
        #[cfg(feature = "ros")]
        Command::Serve(args) => serve::run(args),
        #[cfg(feature = "ros")]
        Command::Worker(args) => worker::run(args),
        Command::StablePoses(args) => stable::run(args),
        Command::Scenes { name } => sim::scenes(name.as_deref()),
    };
    if exit::time_is_up() {
        exit::time_up_error();
    }
    if tabula_robot::driver::stop_requested() {
        eprintln!("stopped by Ctrl+C");
        std::process::exit(exit::STOPPED);
    }
    if let Err(e) = &result
        && let Some(usage) = e.downcast_ref::<args::Usage>()
    {
        eprintln!("error: {usage}");
        std::process::exit(exit::USAGE);
    }
    if let Err(e) = &result
        && let Some(no) = e.downcast_ref::<arm::NoSolution>()
    {
        eprintln!("{no}");
        std::process::exit(exit::NO_SOLUTION);
    }
    if let Err(e) = result {
        eprintln!("error: {}", tabula_geom::input::clip(&one_line(&e), 1000));
        std::process::exit(exit::ERROR);
    }
}

/// The error and its causes joined by ": ", each cause said once: many errors already
/// quote their source in their own message (`{path}: {source}`), which anyhow's `{:#}`
/// would print twice.
fn one_line(e: &anyhow::Error) -> String {
    let mut line = String::new();
    let mut last = String::new();
    for cause in e.chain() {
        let text = cause.to_string();
        if last.contains(&text) {
            continue;
        }
        if !line.is_empty() {
            line.push_str(": ");
        }
        line.push_str(&text);
        last = text;
    }
    line
}
