//! Motion planning for tabula (MoveIt, OMPL and FCL's role): a collision world of one
//! robot and its surroundings, RRT-Connect with shortcutting, time parameterisation,
//! goals as poses through IK, and Cartesian approach/retreat paths.

pub mod bench;
pub mod goals;
pub mod group;
pub mod mbm;
pub mod moveit;
pub mod rrt;
pub mod world;

pub use goals::{cartesian_path, pose_goals};
pub use group::{MoveError, MoveGroup, MoveGroupParams, Plan};
pub use rrt::{
    Path, PlanError, PlannerParams, Trajectory, fitted_world, rrt_connect, segment_certified,
    segment_valid, time_parameterize,
};
pub use world::{CollisionWorld, WorldError, WorldParams};
