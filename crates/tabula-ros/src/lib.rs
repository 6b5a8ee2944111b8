//! tabula speaks ROS 2 over zenoh, with `rmw_zenoh`'s conventions: a ROS 2 node that
//! runs `rmw_zenoh` sees tabula's nodes, topics and services, and tabula's tasks drive a
//! robot in another process or on another machine through the same driver traits the
//! simulator implements.
//!
//! * [`wire`] and [`types`]: the conventions as pure functions (keys, tokens, QoS,
//!   attachments, CDR, RIHS01 type hashes), tested against the reference's examples;
//! * [`msgs`]: the ROS 2 messages tabula sends, with their conversions;
//! * [`node`]: a zenoh session as a ROS 2 node (publishers, subscriptions, services with
//!   their liveliness tokens);
//! * [`protocol`]: tabula's driver and capture services (what a task asks a robot);
//! * [`serve`]: the simulator served as a ROS 2 robot, judging runs from its ground
//!   truth;
//! * [`driver`]: the driver traits over zenoh, for a robot served elsewhere;
//! * [`bench`]: what a camera frame costs on the wire.

pub mod bench;
pub mod driver;
pub mod judge;
pub mod msgs;
pub mod node;
pub mod protocol;
pub mod serve;
pub mod types;
pub mod wire;
