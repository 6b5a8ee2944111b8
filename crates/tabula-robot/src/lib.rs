//! Robot models, kinematic chains, forward kinematics and inverse kinematics.
//!
//! * [`RobotModel`] loads any URDF; [`Chain`] is the serial chain between two links.
//! * [`ik::NumericIk`] solves any chain (damped least squares with restarts);
//!   [`ik::Golem3Ik`] is the closed-form solver of seed 001 (SPEC §2.2), all branches.
//! * [`robots`] gives the built-in robots of `robots/` by name, each with its
//!   [`description::RobotDescription`] (arm groups, grippers, head, base).
//! * [`driver`] is the boundary the task layer talks to a robot through.

pub mod chain;
pub mod description;
pub mod driver;
mod error;
pub mod fake;
pub mod ik;
pub mod model;
pub mod packages;
pub mod robots;
pub mod srdf;
pub mod xacro;

pub use chain::Chain;
pub use description::RobotDescription;
pub use error::RobotError;
pub use model::RobotModel;
