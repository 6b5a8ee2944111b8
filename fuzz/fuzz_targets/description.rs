//! Any text as a robot description (the TOML beside a URDF) for the PR2: numbers,
//! names, widths, axes and named poses come back checked or as an error, never a
//! panic; an accepted description's arms have chains, named poses and grippers whose
//! width map is finite. Run: `cargo +nightly fuzz run description`.
#![no_main]

use libfuzzer_sys::fuzz_target;

#[path = "common/pr2.rs"]
mod common;
use common::pr2;
use tabula_robot::description::RobotDescription;

fuzz_target!(|data: &[u8]| {
    let text = String::from_utf8_lossy(data);
    let pr2 = pr2();
    let Ok(d) = RobotDescription::from_toml(&text, pr2) else {
        return;
    };
    for arm in &d.arms {
        let chain = arm.chain(pr2).expect("an accepted arm has a chain");
        let zeros = vec![0.0; chain.joint_names.len()];
        for pose in arm.named.keys().map(String::as_str).chain(["tucked"]) {
            if let Ok(q) = arm.named_configuration(pose, &chain.joint_names, &zeros) {
                assert!(q.iter().all(|v| v.is_finite()));
            }
        }
        if let Some(g) = d.gripper_of(arm) {
            assert!(g.approach().is_finite() && g.closing().is_finite());
            assert!(g.width_at(pr2, 0.0).is_finite());
        }
    }
});
