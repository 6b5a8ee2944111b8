//! tabula-sim's scenario tests in one binary: each file was its own test binary, each
//! compiled and linked against the whole workspace on its own.

mod camera;
mod common;
mod driver;
mod grasp;
mod mesh;
mod mobile;
mod physics;
mod piles;
mod replay;
mod scene;
