//! The ROS 2 messages tabula sends and reads (field for field as their `.msg` files, in
//! CDR through serde), and their conversions to tabula's own types. Everything read
//! from the wire is checked: a malformed cloud or trajectory is an error, not a panic.

use serde::{Deserialize, Serialize};
use tabula_geom::{PointCloud, Pose, Quat, Vec3};

/// `builtin_interfaces/msg/Time` (also the shape of `Duration`).
#[derive(Debug, Clone, Copy, Default, PartialEq, Serialize, Deserialize)]
pub struct Time {
    pub sec: i32,
    pub nanosec: u32,
}

impl Time {
    /// From seconds (negative and non-finite values clamp to zero).
    pub fn from_secs(t: f64) -> Self {
        let t = if t.is_finite() { t.max(0.0) } else { 0.0 };
        let sec = t.floor().min(i32::MAX as f64);
        Self {
            sec: sec as i32,
            nanosec: (((t - sec) * 1e9).round() as u32).min(999_999_999),
        }
    }

    pub fn secs(&self) -> f64 {
        self.sec as f64 + self.nanosec as f64 * 1e-9
    }
}

/// `std_msgs/msg/Header`.
#[derive(Debug, Clone, Default, PartialEq, Serialize, Deserialize)]
pub struct Header {
    pub stamp: Time,
    pub frame_id: String,
}

/// `sensor_msgs/msg/PointField`.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct PointField {
    pub name: String,
    pub offset: u32,
    pub datatype: u8,
    pub count: u32,
}

/// PointField datatypes.
pub const FLOAT32: u8 = 7;
pub const FLOAT64: u8 = 8;
pub const UINT32: u8 = 6;

/// `sensor_msgs/msg/PointCloud2`.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct PointCloud2 {
    pub header: Header,
    pub height: u32,
    pub width: u32,
    pub fields: Vec<PointField>,
    pub is_bigendian: bool,
    pub point_step: u32,
    pub row_step: u32,
    #[serde(with = "serde_bytes")]
    pub data: Vec<u8>,
    pub is_dense: bool,
}

/// Why a message could not be turned into tabula's types.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum MsgError {
    #[error("point cloud: {0}")]
    Cloud(String),
    #[error("trajectory: {0}")]
    Trajectory(String),
}

impl PointCloud2 {
    /// An organized cloud with fields x y z (float32) and rgb (float32 holding packed
    /// 0x00RRGGBB, as PCL and RViz read it); missing points are NaN.
    pub fn from_cloud(cloud: &PointCloud, colors: Option<&[[u8; 3]]>, header: Header) -> Self {
        let field = |name: &str, offset| PointField {
            name: name.into(),
            offset,
            datatype: FLOAT32,
            count: 1,
        };
        let mut data = Vec::with_capacity(cloud.points.len() * 16);
        for (i, p) in cloud.points.iter().enumerate() {
            for v in [p.x, p.y, p.z] {
                data.extend_from_slice(&(v as f32).to_le_bytes());
            }
            let [r, g, b] = colors.and_then(|c| c.get(i)).copied().unwrap_or([255; 3]);
            let rgb = (u32::from(r) << 16) | (u32::from(g) << 8) | u32::from(b);
            data.extend_from_slice(&rgb.to_le_bytes());
        }
        let (width, height) = if cloud.width * cloud.height == cloud.points.len() {
            (cloud.width, cloud.height)
        } else {
            (cloud.points.len(), 1)
        };
        Self {
            header,
            height: height as u32,
            width: width as u32,
            fields: vec![
                field("x", 0),
                field("y", 4),
                field("z", 8),
                field("rgb", 12),
            ],
            is_bigendian: false,
            point_step: 16,
            row_step: 16 * width as u32,
            data,
            is_dense: cloud.points.iter().all(|p| p.is_finite()),
        }
    }

    /// The points (x y z by name, float32 or float64, either byte order), the grid kept.
    pub fn to_cloud(&self) -> Result<PointCloud, MsgError> {
        let bad = |m: String| MsgError::Cloud(m);
        let (w, h) = (self.width as usize, self.height as usize);
        let n = w
            .checked_mul(h)
            .ok_or_else(|| bad("size overflows".into()))?;
        let step = self.point_step as usize;
        let row = self.row_step as usize;
        if n > 0 && (row < w.saturating_mul(step) || step == 0) {
            return Err(bad(format!(
                "row_step {row} < width {w} × point_step {step}"
            )));
        }
        let needed = if n == 0 {
            0
        } else {
            row.checked_mul(h - 1)
                .and_then(|v| v.checked_add(w * step))
                .ok_or_else(|| bad("size overflows".into()))?
        };
        if self.data.len() < needed {
            return Err(bad(format!(
                "{} bytes of data for {w}×{h} points of {step} bytes",
                self.data.len()
            )));
        }
        let mut axes = [(0usize, FLOAT32); 3];
        for (k, name) in ["x", "y", "z"].iter().enumerate() {
            let f = self
                .fields
                .iter()
                .find(|f| f.name == *name)
                .ok_or_else(|| bad(format!("no `{name}` field")))?;
            let size = match f.datatype {
                FLOAT32 => 4,
                FLOAT64 => 8,
                d => return Err(bad(format!("`{name}` has datatype {d}, not a float"))),
            };
            if f.offset as usize + size > step {
                return Err(bad(format!("`{name}` lies outside the point")));
            }
            axes[k] = (f.offset as usize, f.datatype);
        }
        // One reader per axis, chosen once: the loop below runs 307,200 times a frame.
        let reader = |datatype: u8| -> fn(&[u8]) -> f64 {
            match (datatype, self.is_bigendian) {
                (FLOAT32, false) => |b| f64::from(f32::from_le_bytes([b[0], b[1], b[2], b[3]])),
                (FLOAT32, true) => |b| f64::from(f32::from_be_bytes([b[0], b[1], b[2], b[3]])),
                (_, false) => {
                    |b| f64::from_le_bytes([b[0], b[1], b[2], b[3], b[4], b[5], b[6], b[7]])
                }
                (_, true) => {
                    |b| f64::from_be_bytes([b[0], b[1], b[2], b[3], b[4], b[5], b[6], b[7]])
                }
            }
        };
        let read = axes.map(|(offset, datatype)| (offset, reader(datatype)));
        let mut points = Vec::with_capacity(n);
        for v in 0..h {
            let line = &self.data[v * row..v * row + w * step];
            points.extend(line.chunks_exact(step).map(|p| {
                let [x, y, z] = read.map(|(o, f)| f(&p[o..]));
                let q = Vec3::new(x, y, z);
                if q.is_finite() {
                    q
                } else {
                    Vec3::splat(f64::NAN)
                }
            }));
        }
        Ok(PointCloud {
            width: w,
            height: h,
            points,
        })
    }
}

/// `sensor_msgs/msg/JointState`.
#[derive(Debug, Clone, Default, PartialEq, Serialize, Deserialize)]
pub struct JointState {
    pub header: Header,
    pub name: Vec<String>,
    pub position: Vec<f64>,
    pub velocity: Vec<f64>,
    pub effort: Vec<f64>,
}

/// `geometry_msgs/msg/Vector3` (and `Point`, which has the same fields).
#[derive(Debug, Clone, Copy, Default, PartialEq, Serialize, Deserialize)]
pub struct Vector3 {
    pub x: f64,
    pub y: f64,
    pub z: f64,
}

/// `geometry_msgs/msg/Quaternion`.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct Quaternion {
    pub x: f64,
    pub y: f64,
    pub z: f64,
    pub w: f64,
}

/// `geometry_msgs/msg/Transform`.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct Transform {
    pub translation: Vector3,
    pub rotation: Quaternion,
}

impl Transform {
    pub fn from_pose(p: &Pose) -> Self {
        let (t, q) = (p.translation, p.rotation);
        Self {
            translation: Vector3 {
                x: t.x,
                y: t.y,
                z: t.z,
            },
            rotation: Quaternion {
                x: q.x,
                y: q.y,
                z: q.z,
                w: q.w,
            },
        }
    }

    /// The pose, its rotation normalised; `None` for non-finite or zero rotations.
    pub fn to_pose(&self) -> Option<Pose> {
        let (t, r) = (self.translation, self.rotation);
        let q = Quat::from_xyzw(r.x, r.y, r.z, r.w);
        let len = q.length();
        let t = Vec3::new(t.x, t.y, t.z);
        if !(len.is_finite() && len > 1e-9 && t.is_finite()) {
            return None;
        }
        Some(Pose::from_parts(t, q / len))
    }
}

/// `geometry_msgs/msg/TransformStamped`.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct TransformStamped {
    pub header: Header,
    pub child_frame_id: String,
    pub transform: Transform,
}

/// `tf2_msgs/msg/TFMessage`.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct TfMessage {
    pub transforms: Vec<TransformStamped>,
}

/// `trajectory_msgs/msg/JointTrajectoryPoint`.
#[derive(Debug, Clone, Default, PartialEq, Serialize, Deserialize)]
pub struct JointTrajectoryPoint {
    pub positions: Vec<f64>,
    pub velocities: Vec<f64>,
    pub accelerations: Vec<f64>,
    pub effort: Vec<f64>,
    pub time_from_start: Time,
}

/// `trajectory_msgs/msg/JointTrajectory`.
#[derive(Debug, Clone, Default, PartialEq, Serialize, Deserialize)]
pub struct JointTrajectory {
    pub header: Header,
    pub joint_names: Vec<String>,
    pub points: Vec<JointTrajectoryPoint>,
}

impl JointTrajectory {
    pub fn from_trajectory(t: &tabula_robot::driver::JointTrajectory, header: Header) -> Self {
        Self {
            header,
            joint_names: t.joint_names.clone(),
            points: t
                .times
                .iter()
                .zip(&t.positions)
                .map(|(time, p)| JointTrajectoryPoint {
                    positions: p.clone(),
                    time_from_start: Time::from_secs(*time),
                    ..Default::default()
                })
                .collect(),
        }
    }

    /// tabula's trajectory, checked (shape, finiteness, time order).
    pub fn to_trajectory(&self) -> Result<tabula_robot::driver::JointTrajectory, MsgError> {
        let t = tabula_robot::driver::JointTrajectory {
            joint_names: self.joint_names.clone(),
            times: self
                .points
                .iter()
                .map(|p| p.time_from_start.secs())
                .collect(),
            positions: self.points.iter().map(|p| p.positions.clone()).collect(),
        };
        t.validate()
            .map_err(|e| MsgError::Trajectory(e.to_string()))?;
        Ok(t)
    }
}

/// `control_msgs/msg/GripperCommand`: a finger gap (m) and the most force to use
/// (N; 0 or less means no limit, as ros2_control's gripper controllers read it).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct GripperCommand {
    pub position: f64,
    pub max_effort: f64,
}

/// `tabula_msgs/srv/Call` request: a JSON command.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct CallRequest {
    pub request: String,
}

/// `tabula_msgs/srv/Call` response: whether it succeeded, and a JSON answer (or the
/// error).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct CallResponse {
    pub ok: bool,
    pub response: String,
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::wire::{from_cdr, to_cdr};

    #[test]
    fn clouds_round_trip_and_bad_ones_are_refused() {
        let cloud = PointCloud {
            width: 2,
            height: 2,
            points: vec![
                Vec3::new(0.5, -1.0, 2.0),
                Vec3::splat(f64::NAN),
                Vec3::new(1.0, 2.0, 3.0),
                Vec3::new(-4.0, 0.25, 1.0),
            ],
        };
        let msg = PointCloud2::from_cloud(&cloud, Some(&[[1, 2, 3]; 4]), Header::default());
        assert!(!msg.is_dense);
        let back: PointCloud2 = from_cdr(&to_cdr(&msg).unwrap()).unwrap();
        assert_eq!(back, msg);
        let c = back.to_cloud().unwrap();
        assert_eq!((c.width, c.height), (2, 2));
        assert_eq!(c.points[0], cloud.points[0]);
        assert!(c.points[1].x.is_nan());
        let mut short = msg.clone();
        short.data.truncate(40);
        assert!(short.to_cloud().is_err());
        let mut huge = msg.clone();
        huge.width = u32::MAX;
        huge.height = u32::MAX;
        assert!(huge.to_cloud().is_err());
        let mut nox = msg.clone();
        nox.fields.remove(0);
        assert!(nox.to_cloud().is_err());
        let mut outside = msg;
        outside.fields[2].offset = 14;
        assert!(outside.to_cloud().is_err());
    }

    #[test]
    fn trajectories_round_trip_and_are_checked() {
        let t = tabula_robot::driver::JointTrajectory {
            joint_names: vec!["a".into(), "b".into()],
            times: vec![0.0, 0.5, 1.25],
            positions: vec![vec![0.0, 1.0], vec![0.5, 1.0], vec![1.0, 0.0]],
        };
        let msg = JointTrajectory::from_trajectory(&t, Header::default());
        let back = msg.to_trajectory().unwrap();
        assert_eq!(back, t);
        let mut bad = msg;
        bad.points[1].positions.pop();
        assert!(bad.to_trajectory().is_err());
    }

    #[test]
    fn time_converts() {
        let t = Time::from_secs(12.25);
        assert_eq!((t.sec, t.nanosec), (12, 250_000_000));
        assert_eq!(Time::from_secs(f64::NAN), Time::default());
    }
}
