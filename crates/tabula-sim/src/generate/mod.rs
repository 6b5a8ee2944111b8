//! Seeded tabletop scenes (SPEC §3): a table in a room with boxes and cylinders on it,
//! some touching, some stacked, seen by a head-height Kinect-like camera that also sees
//! the floor and a wall. The perception benchmark and its test suite are made of these.

mod blocks;
pub mod clear;
mod grips;
pub mod place;
pub mod shelf;
pub mod table_pick;
pub mod tabletop;
pub mod tidy;
pub use clear::*;
pub use place::*;
pub use shelf::*;
pub use table_pick::table_pick_place_task;
pub use tabletop::*;
pub use tidy::{TidyTask, tidy_task};
