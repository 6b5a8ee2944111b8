//! Robots described in xacro (macros, properties, includes, arguments, math,
//! `xacro.load_yaml`), as most ROS robots are: expanded into URDF text by the `xacro-rs`
//! crate (MIT, no ROS needed), then read as any URDF. `$(find pkg)` resolves through
//! the project's package resolver ([`crate::packages`]); `$(optenv)` as ROS does.

mod find;
mod includes;

use crate::error::RobotError;
use crate::packages::PackagePaths;
use std::path::Path;
use std::time::{Duration, Instant};
use tabula_geom::input::{Format, read_text};

/// Longest an expansion may take: macros that call each other can multiply without
/// bound inside the crate's depth limit (50), and a description that has not expanded
/// in this long is not one anybody meant.
const TIME_LIMIT: Duration = Duration::from_secs(20);
/// Most XML nodes an expansion may visit: the PR2, the largest published description
/// tried, visits a few thousand (50× below this); a macro bomb stops here in about a
/// second instead of running to the time limit.
const MAX_NODES: u64 = 200_000;
/// Most memory an expansion may add to the process (resident): the largest published
/// descriptions (PR2, Fetch) expand in well under 100 MiB.
const MEMORY_LIMIT: u64 = 768 << 20;

/// Whether `path` names a xacro file (`.xacro`, `.urdf.xacro`).
pub fn is_xacro(path: &Path) -> bool {
    path.extension()
        .is_some_and(|e| e.eq_ignore_ascii_case("xacro"))
}

/// The URDF text of the xacro file at `path`, with `args` (`name`, `value`) given as
/// `name:=value` would be on xacro's command line; packages are found by `packages`.
pub fn expand(
    path: &Path,
    args: &[(String, String)],
    packages: &PackagePaths,
) -> Result<String, RobotError> {
    let parse_err = |message: String| RobotError::Parse {
        path: Some(path.to_path_buf()),
        message,
    };
    // The input policy for the top file: a regular file within the robot size limit,
    // nested no deeper than a URDF may be.
    let text = read_text(path, Format::Robot)?;
    let depth = tabula_geom::input::xml_depth(&text, 256);
    if depth > 256 {
        return Err(RobotError::TooDeep(depth));
    }
    includes::check(path, &text, args, packages).map_err(|m| parse_err(format!("xacro: {m}")))?;
    let (tx, rx) = std::sync::mpsc::channel();
    let owned = std::path::absolute(path).unwrap_or_else(|_| path.to_path_buf());
    let args = args.to_vec();
    let packages = packages.clone();
    // Its own thread: a generous stack for the crate's recursion, and a time and memory
    // watch the caller keeps even when an expansion runs away (the thread is then left
    // to finish on its own; the CLI exits right after the error).
    std::thread::Builder::new()
        .name("xacro".into())
        .stack_size(64 << 20)
        .spawn(move || {
            let out = tabula_geom::guard::catch_quietly(move || run(&owned, &args, packages));
            let _ = tx.send(out);
        })
        .map_err(|e| parse_err(format!("cannot start the xacro expansion: {e}")))?;
    let urdf = wait(&rx).map_err(|m| parse_err(format!("xacro: {m}")))?;
    if urdf.len() as u64 > Format::Robot.max_bytes() {
        return Err(parse_err(format!(
            "xacro: the expansion is {} MiB, over the robot limit",
            urdf.len() >> 20
        )));
    }
    Ok(urdf)
}

fn run(path: &Path, args: &[(String, String)], packages: PackagePaths) -> Result<String, String> {
    // The expansion stops itself at the same deadline the caller waits for, and at a
    // substitution larger than a robot file may be (a property that doubles itself).
    xacro_rs::budget::set(
        Some(Instant::now() + TIME_LIMIT),
        Format::Robot.max_bytes() as usize,
        MAX_NODES,
    );
    let mut builder = xacro_rs::XacroProcessor::builder()
        .with_extension(Box::new(find::FindPackage {
            packages,
            current_dir: Default::default(),
        }))
        .with_extension(Box::new(xacro_rs::extensions::OptEnvExtension::new()))
        .with_ros_yaml_units();
    for (k, v) in args {
        builder = builder.with_arg(k.clone(), v.clone());
    }
    // xacro-rs puts the reason on lines below its summary; one line keeps both.
    builder.build().run(path).map_err(|e| {
        e.to_string()
            .lines()
            .map(str::trim)
            .filter(|l| !l.is_empty())
            .collect::<Vec<_>>()
            .join(" ")
    })
}

type Outcome = Result<Result<String, String>, String>;

/// The expansion's result, or why it was given up on.
fn wait(rx: &std::sync::mpsc::Receiver<Outcome>) -> Result<String, String> {
    let start = Instant::now();
    let baseline = resident_bytes();
    loop {
        match rx.recv_timeout(Duration::from_millis(50)) {
            Ok(Ok(result)) => return result,
            Ok(Err(_)) => return Err("the expansion failed".into()),
            Err(std::sync::mpsc::RecvTimeoutError::Disconnected) => {
                return Err("the expansion failed".into());
            }
            Err(std::sync::mpsc::RecvTimeoutError::Timeout) => {}
        }
        if start.elapsed() > TIME_LIMIT {
            return Err(format!(
                "no expansion within {} s (macros that multiply without end?)",
                TIME_LIMIT.as_secs()
            ));
        }
        if resident_bytes().saturating_sub(baseline) > MEMORY_LIMIT {
            return Err(format!(
                "the expansion needed over {} MiB (macros or properties that multiply?)",
                MEMORY_LIMIT >> 20
            ));
        }
    }
}

/// The process's resident memory (Linux `/proc/self/statm`; 0 elsewhere).
fn resident_bytes() -> u64 {
    std::fs::read_to_string("/proc/self/statm")
        .ok()
        .and_then(|s| s.split_whitespace().nth(1)?.parse::<u64>().ok())
        .map_or(0, |pages| pages * 4096)
}
