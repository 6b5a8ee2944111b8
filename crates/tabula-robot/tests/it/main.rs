//! tabula-robot's scenario tests in one binary: each file was its own test binary, each
//! compiled and linked against the whole workspace on its own.

mod analytic_spherical_wrist;
mod analytic_ur;
mod common;
mod descriptions;
mod golem3_kinematics;
mod numeric_ik;
mod srdf_and_defaults;
mod srdf_gripper;
mod urdf_loading;
mod xacro;
