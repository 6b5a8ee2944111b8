//! tabula's built-in simulator (SPEC §5): scenes from TOML, rigid-body physics with
//! rapier3d-f64, a ray-cast depth camera with Kinect-like noise, and the seed's scene
//! commands. It plays Gazebo's part: it produces the frames perception is tested on and
//! tells by physics whether an object really rests where a plan said.

pub mod builtin;
pub mod camera;
pub mod driver;
pub mod frame_file;
pub mod generate;
pub mod judge;
pub mod objects;
pub mod replay;
pub mod scene;
pub mod world;

pub use camera::{Camera, DepthFrame};
pub use driver::SimDriver;
pub use scene::{Scene, SceneError};
pub use world::{PhysicsParams, SettleReport, SimError, SimWorld};
