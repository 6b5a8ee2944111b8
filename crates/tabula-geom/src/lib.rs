//! Geometry types shared by every tabula crate.
//!
//! One set of math types crosses every crate boundary: the glam-based types that
//! parry3d-f64 and rapier3d-f64 use since 2026 (re-exported here under parry's names),
//! so no crate converts between two vector libraries. nalgebra stays inside solvers.
//!
//! Poses are named after the frames they map between: `world_from_gripper` maps
//! gripper-frame coordinates to world coordinates, so
//! `world_from_base * base_from_gripper == world_from_gripper`.

pub use parry3d_f64 as parry;
pub use parry3d_f64::glamx::{DMat3 as Mat3, DMat4 as Mat4, DPose3 as Pose, DQuat as Quat};
pub use parry3d_f64::glamx::{DVec2 as Vec2, DVec3 as Vec3};

mod angles;
mod cloud;
pub mod collada;
pub mod convex_pieces;
pub mod guard;
pub mod hull_input;
pub mod input;
pub mod mesh;
pub mod pcd;
pub mod ply;
pub mod polygon;
pub mod raster;
pub mod shape_cache;
pub use angles::*;
pub use cloud::{
    CloudFile, PcdEncoding, PcdExtras, PointCloud, bounds, packed_voxel_key, voxel_key,
};
pub use pcd::{PcdError, read_pcd, read_pcd_file};
pub use ply::{PlyEncoding, PlyError, read_ply, read_ply_mesh, write_ply};
