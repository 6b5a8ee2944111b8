//! tabula-motion's scenario tests in one binary: each file was its own test binary, each
//! compiled and linked against the whole workspace on its own.

mod mbm_panda;
mod mesh_geometry;
mod moveit_yaml;
mod planning;
