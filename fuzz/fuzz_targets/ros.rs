//! What arrives from a zenoh network: any bytes as an rmw attachment, a CDR point cloud
//! (then decoded into a cloud), a CDR trajectory (then checked), a liveliness token or
//! a driver command give a value or an error, never a panic.
#![no_main]

use libfuzzer_sys::fuzz_target;
use tabula_ros::msgs::{JointTrajectory, PointCloud2};
use tabula_ros::protocol::Command;
use tabula_ros::wire::{Attachment, from_cdr, parse_token};

fuzz_target!(|data: &[u8]| {
    let _ = Attachment::decode(data);
    if let Ok(cloud) = from_cdr::<PointCloud2>(data) {
        let _ = cloud.to_cloud();
    }
    if let Ok(t) = from_cdr::<JointTrajectory>(data) {
        let _ = t.to_trajectory();
    }
    if let Ok(text) = std::str::from_utf8(data) {
        let _ = parse_token(text);
        let _ = serde_json::from_str::<Command>(text);
    }
});
