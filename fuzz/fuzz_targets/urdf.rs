//! Any bytes as a URDF: the loader returns a model or an error, never panics, and a
//! loaded model's chains and FK answer too. Run: `cargo +nightly fuzz run urdf`.
#![no_main]

use libfuzzer_sys::fuzz_target;
use tabula_robot::description::RobotDescription;
use tabula_robot::{Chain, RobotModel};

const WAM: &str = tabula_robot::robots::WAM_URDF;

fuzz_target!(|data: &[u8]| {
    let text = String::from_utf8_lossy(data);
    // The same bytes as the TOML description (groups, grippers) of a known robot.
    if let Ok(wam) = RobotModel::from_urdf_str(WAM, None) {
        let _ = RobotDescription::from_toml(&text, &wam);
    }
    if let Ok(model) = RobotModel::from_urdf_str(&text, None) {
        let _ = model.forward_kinematics(&model.mid_configuration());
        if let (Some(a), Some(b)) = (model.links.first(), model.links.last())
            && let Ok(chain) = Chain::new(&model, &a.name, &b.name)
        {
            let _ = chain.fk(&chain.mid_configuration());
        }
    }
});
