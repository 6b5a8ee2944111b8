//! What several scenario tests share: the WAM's joints for a tool pose.

use tabula_geom::{Pose, Quat, Vec3};
use tabula_robot::Chain;
use tabula_robot::ik::{IkMode, IkSolver, NumericIk, NumericIkParams};

/// Joint values putting the WAM's tool at `xyz` (its base frame) pointing down
/// (fingers closing along x), from `seed`.
pub fn tool_down(chain: &Chain, xyz: Vec3, seed: &[f64]) -> Vec<f64> {
    let solver = NumericIk::new(
        chain.clone(),
        NumericIkParams {
            timeout_s: None,
            ..Default::default()
        },
    );
    let target = Pose::from_parts(xyz, Quat::from_rotation_x(std::f64::consts::PI));
    solver
        .solve(&target, IkMode::Full, seed)
        .expect("reachable")[0]
        .joints
        .clone()
}
