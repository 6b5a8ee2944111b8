//! Robots described in xacro (macros, properties, includes, arguments, math), as most
//! ROS robots are: expanded into URDF text by the `xacro-rs` crate (MIT, no ROS needed;
//! `$(find pkg)` resolves through `RUST_XACRO_PACKAGE_MAP`), then read as any URDF.

use crate::error::RobotError;
use std::path::Path;
use std::time::Duration;
use tabula_geom::input::{Format, read_text};

/// Longest an expansion may take: macros that call each other can multiply without
/// bound inside the crate's depth limit (50), and a description that has not expanded
/// in this long is not one anybody meant.
const TIME_LIMIT: Duration = Duration::from_secs(20);

/// Whether `path` names a xacro file (`.xacro`, `.urdf.xacro`).
pub fn is_xacro(path: &Path) -> bool {
    path.extension()
        .is_some_and(|e| e.eq_ignore_ascii_case("xacro"))
}

/// The URDF text of the xacro file at `path`, with `args` (`name`, `value`) given as
/// `name:=value` would be on xacro's command line; includes resolve beside the file.
pub fn expand(path: &Path, args: &[(String, String)]) -> Result<String, RobotError> {
    let parse_err = |message: String| RobotError::Parse {
        path: Some(path.to_path_buf()),
        message,
    };
    // The input policy for the top file: a regular file within the robot size limit,
    // nested no deeper than a URDF may be.
    let text = read_text(path, Format::Robot)?;
    let depth = crate::model::xml_depth(&text, 256);
    if depth > 256 {
        return Err(RobotError::TooDeep(depth));
    }
    let (tx, rx) = std::sync::mpsc::channel();
    let owned = path.to_path_buf();
    let args = args.to_vec();
    // Its own thread: a generous stack for the crate's recursion, and a time limit
    // the caller keeps even when an expansion runs away (the thread is then left to
    // finish on its own; the CLI exits right after the error).
    std::thread::Builder::new()
        .name("xacro".into())
        .stack_size(64 << 20)
        .spawn(move || {
            let out = tabula_geom::guard::catch_quietly(|| {
                let mut builder = xacro_rs::XacroProcessor::builder();
                for (k, v) in &args {
                    builder = builder.with_arg(k.clone(), v.clone());
                }
                builder.build().run(&owned).map_err(|e| e.to_string())
            });
            let _ = tx.send(out);
        })
        .map_err(|e| parse_err(format!("cannot start the xacro expansion: {e}")))?;
    let urdf = match rx.recv_timeout(TIME_LIMIT) {
        Ok(Ok(Ok(urdf))) => urdf,
        Ok(Ok(Err(e))) => return Err(parse_err(format!("xacro: {e}"))),
        Ok(Err(_)) => return Err(parse_err("xacro: the expansion failed".into())),
        Err(_) => {
            return Err(parse_err(format!(
                "xacro: no expansion within {} s (macros that multiply without end?)",
                TIME_LIMIT.as_secs()
            )));
        }
    };
    if urdf.len() as u64 > Format::Robot.max_bytes() {
        return Err(parse_err(format!(
            "xacro: the expansion is {} MiB, over the robot limit",
            urdf.len() >> 20
        )));
    }
    Ok(urdf)
}
