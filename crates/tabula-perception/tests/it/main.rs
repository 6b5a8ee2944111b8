//! tabula-perception's scenario tests in one binary: each file was its own test binary, each
//! compiled and linked against the whole workspace on its own.

mod partial;
mod pieces;
mod placement;
mod real_frames;
mod robustness;
mod surfaces;
mod tabletop;
