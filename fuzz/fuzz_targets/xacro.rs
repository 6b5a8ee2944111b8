//! Any bytes as a xacro file: the expansion gives a URDF or an error within its time
//! and memory bounds, never a panic. Run: `cargo +nightly fuzz run xacro`.
#![no_main]

use libfuzzer_sys::fuzz_target;

fuzz_target!(|data: &[u8]| {
    let dir = std::env::temp_dir().join(format!("tabula-fuzz-xacro-{}", std::process::id()));
    if std::fs::create_dir_all(&dir).is_err() {
        return;
    }
    let path = dir.join("robot.urdf.xacro");
    if std::fs::write(&path, data).is_ok() {
        let _ = tabula_robot::RobotModel::from_urdf_file(&path);
    }
});
