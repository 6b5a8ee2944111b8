//! tabula-cli's scenario tests in one binary: each file was its own test binary, each
//! compiled and linked against the whole workspace on its own.

mod cli;
mod labels;
mod motion_cli;
mod perceive;
mod pick_place;
