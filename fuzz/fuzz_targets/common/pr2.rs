//! The PR2 parsed once per fuzzing process: the targets that use it fuzz what sits
//! beside a URDF (an SRDF, a description), not the URDF.

use tabula_robot::RobotModel;

pub fn pr2() -> &'static RobotModel {
    static PR2: std::sync::OnceLock<RobotModel> = std::sync::OnceLock::new();
    PR2.get_or_init(|| {
        RobotModel::from_urdf_str(tabula_robot::robots::PR2_URDF, None).expect("the PR2 parses")
    })
}
