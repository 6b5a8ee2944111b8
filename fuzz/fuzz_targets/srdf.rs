//! Any bytes as a MoveIt SRDF for a known robot: groups, states, end effectors and the
//! collision matrix come back checked or as an error, never a panic, and the arms it
//! yields have chains. Run: `cargo +nightly fuzz run srdf`.
#![no_main]

use libfuzzer_sys::fuzz_target;

#[path = "common/pr2.rs"]
mod common;
use common::pr2;
use tabula_robot::srdf::Srdf;

fuzz_target!(|data: &[u8]| {
    let text = String::from_utf8_lossy(data);
    let pr2 = pr2();
    if let Ok(srdf) = Srdf::parse(&text, pr2) {
        for arm in srdf.arms(pr2) {
            let _ = arm.chain(pr2);
        }
        let _ = srdf.allows("base_link", "torso_lift_link");
    }
});
