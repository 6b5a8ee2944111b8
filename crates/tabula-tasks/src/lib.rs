//! tabula's task layer: the jobs users came for, written against the driver traits of
//! `tabula_robot::driver` only — the simulator, a zenoh bridge or a real robot are the
//! same to them.
//!
//! * [`pick_place`]: pick an object at given coordinates and place it at others (seed
//!   001's integral test, SPEC §2.5), either arm.
//! * [`clear`]: clear a cluttered table into a bin by grasps and pushes, replanning
//!   after every action (seed 002, SPEC §3).
//! * [`place`]: place a held object it has no model of stably on a surface it finds
//!   (seed 000, SPEC §1).
//! * [`tidy`]: take every object from one table and stand each on another surface —
//!   a task from the shared skills alone.
//! * [`observe`]: what the robot sees — its own body filtered out, the object and the
//!   surface near a position, the occupancy that becomes the collision world.
//! * [`scene`]: the tabletop scene model one frame gives (table, objects, hulls).
//! * [`skills`]: what the tasks share — the hand, grasp planners, motions, one error.
//! * [`stable`]: stable poses of a mesh or a scanned cloud (SPEC §1.2).
//! * [`task`]: the [`Task`](task::Task) trait every task implements, and what a
//!   watcher of a run is told.
//! * [`torso`]: the torso raised before manipulating (seed 000 §1.6).

pub mod clear;
pub mod observe;
pub mod pick_place;
pub mod place;
pub mod scene;
pub mod skills;
pub mod stable;
pub mod task;
pub mod tidy;
pub mod torso;
