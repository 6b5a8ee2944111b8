//! ROS 2 interface definitions and their RIHS01 type hashes (REP-2016), computed here from
//! the definitions rather than copied: a type hash is the SHA-256 of the type's
//! description — its fields and, sorted by name, every type it refers to — written as
//! Python's `json.dumps` writes it, default values left out.
//!
//! Definitions are the `.msg`/`.srv` texts with fully qualified nested types, without
//! comments or constants (neither enters the hash). A service `pkg/srv/S` is hashed as
//! rosidl does: the type `pkg/srv/S` with fields `request_message`, `response_message`
//! and `event_message` (`pkg/srv/S_Event`: `service_msgs/ServiceEventInfo info`,
//! bounded sequences of one request and one response).

use sha2::{Digest, Sha256};
use std::collections::BTreeMap;

/// Every interface tabula speaks: its ROS 2 name and its definition.
pub const DEFINITIONS: &[(&str, &str)] = &[
    ("builtin_interfaces/msg/Time", "int32 sec\nuint32 nanosec"),
    (
        "builtin_interfaces/msg/Duration",
        "int32 sec\nuint32 nanosec",
    ),
    (
        "std_msgs/msg/Header",
        "builtin_interfaces/msg/Time stamp\nstring frame_id",
    ),
    ("std_msgs/msg/String", "string data"),
    (
        "sensor_msgs/msg/PointField",
        "string name\nuint32 offset\nuint8 datatype\nuint32 count",
    ),
    (
        "sensor_msgs/msg/PointCloud2",
        "std_msgs/msg/Header header\nuint32 height\nuint32 width\n\
         sensor_msgs/msg/PointField[] fields\nbool is_bigendian\nuint32 point_step\n\
         uint32 row_step\nuint8[] data\nbool is_dense",
    ),
    (
        "sensor_msgs/msg/JointState",
        "std_msgs/msg/Header header\nstring[] name\nfloat64[] position\n\
         float64[] velocity\nfloat64[] effort",
    ),
    (
        "geometry_msgs/msg/Vector3",
        "float64 x\nfloat64 y\nfloat64 z",
    ),
    ("geometry_msgs/msg/Point", "float64 x\nfloat64 y\nfloat64 z"),
    (
        "geometry_msgs/msg/Quaternion",
        "float64 x\nfloat64 y\nfloat64 z\nfloat64 w",
    ),
    (
        "geometry_msgs/msg/Pose",
        "geometry_msgs/msg/Point position\ngeometry_msgs/msg/Quaternion orientation",
    ),
    (
        "geometry_msgs/msg/PoseStamped",
        "std_msgs/msg/Header header\ngeometry_msgs/msg/Pose pose",
    ),
    (
        "geometry_msgs/msg/PointStamped",
        "std_msgs/msg/Header header\ngeometry_msgs/msg/Point point",
    ),
    (
        "geometry_msgs/msg/Pose2D",
        "float64 x\nfloat64 y\nfloat64 theta",
    ),
    (
        "geometry_msgs/msg/Transform",
        "geometry_msgs/msg/Vector3 translation\ngeometry_msgs/msg/Quaternion rotation",
    ),
    (
        "geometry_msgs/msg/TransformStamped",
        "std_msgs/msg/Header header\nstring child_frame_id\n\
         geometry_msgs/msg/Transform transform",
    ),
    (
        "tf2_msgs/msg/TFMessage",
        "geometry_msgs/msg/TransformStamped[] transforms",
    ),
    (
        "trajectory_msgs/msg/JointTrajectoryPoint",
        "float64[] positions\nfloat64[] velocities\nfloat64[] accelerations\n\
         float64[] effort\nbuiltin_interfaces/msg/Duration time_from_start",
    ),
    (
        "trajectory_msgs/msg/JointTrajectory",
        "std_msgs/msg/Header header\nstring[] joint_names\n\
         trajectory_msgs/msg/JointTrajectoryPoint[] points",
    ),
    (
        "control_msgs/msg/GripperCommand",
        "float64 position\nfloat64 max_effort",
    ),
    (
        "service_msgs/msg/ServiceEventInfo",
        "uint8 event_type\nbuiltin_interfaces/msg/Time stamp\nchar[16] client_gid\n\
         int64 sequence_number",
    ),
    // tabula's own services: a JSON request and a JSON answer, so that a new command
    // needs no new type (documented in the README's ROS 2 section).
    (
        "tabula_msgs/srv/Call",
        "string request\n---\nbool ok\nstring response",
    ),
    (
        "tabula_msgs/srv/Perceive",
        "sensor_msgs/msg/PointCloud2 cloud\nbool has_pose\n\
         geometry_msgs/msg/Transform world_from_cloud\n---\nbool ok\nstring response",
    ),
    (
        "tabula_msgs/srv/Capture",
        "string camera\n---\nbool ok\nstring error\nsensor_msgs/msg/PointCloud2 cloud\n\
         geometry_msgs/msg/Transform world_from_camera",
    ),
];

/// A field's type as `type_description_interfaces/FieldType` numbers it.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct FieldType {
    pub type_id: u32,
    pub capacity: u64,
    pub string_capacity: u64,
    pub nested_type_name: String,
}

/// One field of a type description.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Field {
    pub name: String,
    pub ty: FieldType,
}

/// A type's description as REP-2016 hashes it: the type, then every type it refers
/// to, sorted by name.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct TypeDescription {
    pub type_name: String,
    pub fields: Vec<Field>,
    pub referenced: Vec<(String, Vec<Field>)>,
}

/// Why a definition could not be read or hashed.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum TypeError {
    #[error("unknown interface `{0}`")]
    Unknown(String),
    #[error("in `{0}`: cannot read `{1}`")]
    Syntax(String, String),
}

fn primitive_id(name: &str) -> Option<u32> {
    Some(match name {
        "int8" => 2,
        "uint8" | "char" => 3,
        "int16" => 4,
        "uint16" => 5,
        "int32" => 6,
        "uint32" => 7,
        "int64" => 8,
        "uint64" => 9,
        "float32" => 10,
        "float64" => 11,
        "bool" => 15,
        "byte" => 16,
        "string" => 17,
        "wstring" => 18,
        _ => return None,
    })
}

fn parse_field(owner: &str, line: &str) -> Result<Field, TypeError> {
    let bad = || TypeError::Syntax(owner.into(), line.into());
    let mut it = line.split_whitespace();
    let (ty, name) = match (it.next(), it.next()) {
        (Some(t), Some(n)) => (t, n),
        _ => return Err(bad()),
    };
    let (base, array) = match ty.split_once('[') {
        Some((b, rest)) => (b, Some(rest.strip_suffix(']').ok_or_else(bad)?)),
        None => (ty, None),
    };
    let (mut type_id, nested) = match primitive_id(base) {
        Some(id) => (id, String::new()),
        None if base.split('/').count() == 3 => (1, base.to_string()),
        None => return Err(bad()),
    };
    let mut capacity = 0;
    match array {
        None => {}
        Some("") => type_id += 144,
        Some(bound) => {
            if let Some(max) = bound.strip_prefix("<=") {
                type_id += 96;
                capacity = max.parse().map_err(|_| bad())?;
            } else {
                type_id += 48;
                capacity = bound.parse().map_err(|_| bad())?;
            }
        }
    }
    Ok(Field {
        name: name.into(),
        ty: FieldType {
            type_id,
            capacity,
            string_capacity: 0,
            nested_type_name: nested,
        },
    })
}

fn fields_of(owner: &str, text: &str) -> Result<Vec<Field>, TypeError> {
    text.lines()
        .map(str::trim)
        .filter(|l| !l.is_empty())
        .map(|l| parse_field(owner, l))
        .collect()
}

/// Every type definition, services expanded into their request, response, event and
/// service types.
fn all_types() -> Result<BTreeMap<String, Vec<Field>>, TypeError> {
    let mut types = BTreeMap::new();
    for (name, text) in DEFINITIONS {
        if let Some((req, resp)) = text.split_once("---") {
            let f = |suffix: &str| format!("{name}{suffix}");
            types.insert(f("_Request"), fields_of(name, req)?);
            types.insert(f("_Response"), fields_of(name, resp)?);
            types.insert(
                f("_Event"),
                fields_of(
                    name,
                    &format!(
                        "service_msgs/msg/ServiceEventInfo info\n{0}_Request[<=1] request\n\
                         {0}_Response[<=1] response",
                        name
                    ),
                )?,
            );
            types.insert(
                name.to_string(),
                fields_of(
                    name,
                    &format!(
                        "{0}_Request request_message\n{0}_Response response_message\n\
                         {0}_Event event_message",
                        name
                    ),
                )?,
            );
        } else {
            types.insert(name.to_string(), fields_of(name, text)?);
        }
    }
    Ok(types)
}

fn json_string(s: &str) -> String {
    serde_json::to_string(s).unwrap_or_default()
}

fn describe(name: &str, fields: &[Field]) -> String {
    let fields: Vec<String> = fields
        .iter()
        .map(|f| {
            format!(
                "{{\"name\": {}, \"type\": {{\"type_id\": {}, \"capacity\": {}, \"string_capacity\": {}, \"nested_type_name\": {}}}}}",
                json_string(&f.name),
                f.ty.type_id,
                f.ty.capacity,
                f.ty.string_capacity,
                json_string(&f.ty.nested_type_name)
            )
        })
        .collect();
    format!(
        "{{\"type_name\": {}, \"fields\": [{}]}}",
        json_string(name),
        fields.join(", ")
    )
}

/// The description of a message or service type.
pub fn description(ros_type: &str) -> Result<TypeDescription, TypeError> {
    let types = all_types()?;
    let top = types
        .get(ros_type)
        .ok_or_else(|| TypeError::Unknown(ros_type.into()))?;
    // Every type reachable from the fields, once, sorted by name (BTreeMap order).
    let mut referenced = BTreeMap::new();
    let mut stack: Vec<&str> = vec![ros_type];
    while let Some(t) = stack.pop() {
        let fields = types.get(t).ok_or_else(|| TypeError::Unknown(t.into()))?;
        for f in fields {
            let n = f.ty.nested_type_name.as_str();
            if !n.is_empty() && !referenced.contains_key(n) {
                let nf = types.get(n).ok_or_else(|| TypeError::Unknown(n.into()))?;
                referenced.insert(n.to_string(), nf.clone());
                stack.push(n);
            }
        }
    }
    Ok(TypeDescription {
        type_name: ros_type.into(),
        fields: top.clone(),
        referenced: referenced.into_iter().collect(),
    })
}

/// The RIHS01 hash of a message or service type (`RIHS01_` and 64 hex digits).
pub fn type_hash(ros_type: &str) -> Result<String, TypeError> {
    let d = description(ros_type)?;
    let referenced: Vec<String> = d.referenced.iter().map(|(n, f)| describe(n, f)).collect();
    let json = format!(
        "{{\"type_description\": {}, \"referenced_type_descriptions\": [{}]}}",
        describe(&d.type_name, &d.fields),
        referenced.join(", ")
    );
    let digest = Sha256::digest(json.as_bytes());
    let hex: String = digest.iter().map(|b| format!("{b:02x}")).collect();
    Ok(format!("RIHS01_{hex}"))
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Hashes ROS 2 gives (rmw_zenoh's own examples, and the `EXPECTED_HASH` tables
    /// rosidl_generator_c writes into every package's `*__description.c`).
    #[test]
    fn hashes_match_ros2() {
        let hex = |bytes: &[u8; 32]| -> String {
            format!(
                "RIHS01_{}",
                bytes.iter().map(|b| format!("{b:02x}")).collect::<String>()
            )
        };
        for (name, expected) in [
            (
                "sensor_msgs/msg/PointCloud2",
                "RIHS01_9198cabf7da3796ae6fe19c4cb3bdd3525492988c70522628af5daa124bae2b5".into(),
            ),
            (
                "tf2_msgs/msg/TFMessage",
                "RIHS01_e369d0f05a23ae52508854b66f6aa0437f3449d652e8cbf22d5abe85d020f087".into(),
            ),
            (
                "std_msgs/msg/String",
                "RIHS01_df668c740482bbd48fb39d76a70dfd4bd59db1288021743503259e948f6b1a18".into(),
            ),
            (
                "sensor_msgs/msg/JointState",
                hex(&[
                    0xa1, 0x3e, 0xe3, 0xa3, 0x30, 0xe3, 0x46, 0xc9, 0xd8, 0x7b, 0x5a, 0xa1, 0x8d,
                    0x24, 0xe1, 0x16, 0x90, 0x75, 0x2b, 0xd3, 0x3a, 0x03, 0x50, 0xf1, 0x1c, 0x58,
                    0x82, 0xbc, 0x91, 0x79, 0x26, 0x0e,
                ]),
            ),
            (
                "trajectory_msgs/msg/JointTrajectory",
                hex(&[
                    0x17, 0x9b, 0x33, 0xeb, 0xa5, 0x9d, 0x67, 0x6f, 0x6d, 0x96, 0x7a, 0xc7, 0x1f,
                    0xe3, 0x5e, 0x7c, 0xa2, 0xf6, 0x4b, 0x2f, 0x39, 0x28, 0xf4, 0xa0, 0x18, 0xce,
                    0xc1, 0x15, 0xe2, 0x13, 0x79, 0x6e,
                ]),
            ),
            (
                "trajectory_msgs/msg/JointTrajectoryPoint",
                hex(&[
                    0xde, 0x89, 0x07, 0x03, 0x6d, 0x8b, 0xd4, 0x5a, 0xac, 0x6f, 0x30, 0xcc, 0x90,
                    0x44, 0xa3, 0xd4, 0xa3, 0x29, 0xc4, 0x2c, 0xbf, 0x71, 0x9a, 0xff, 0x7d, 0x95,
                    0xa5, 0x84, 0xcf, 0xa5, 0x32, 0xd7,
                ]),
            ),
            (
                "std_msgs/msg/Header",
                hex(&[
                    0xf4, 0x9f, 0xb3, 0xae, 0x2c, 0xf0, 0x70, 0xf7, 0x93, 0x64, 0x5f, 0xf7, 0x49,
                    0x68, 0x3a, 0xc6, 0xb0, 0x62, 0x03, 0xe4, 0x1c, 0x89, 0x1e, 0x17, 0x70, 0x1b,
                    0x1c, 0xb5, 0x97, 0xce, 0x6a, 0x01,
                ]),
            ),
            (
                "builtin_interfaces/msg/Duration",
                hex(&[
                    0xe8, 0xd0, 0x09, 0xf6, 0x59, 0x81, 0x6f, 0x75, 0x8b, 0x75, 0x33, 0x4e, 0xe1,
                    0xa9, 0xca, 0x5b, 0x5c, 0x0b, 0x85, 0x98, 0x43, 0x26, 0x1f, 0x14, 0xc7, 0xf9,
                    0x37, 0x34, 0x95, 0x99, 0xd9, 0x3b,
                ]),
            ),
            (
                "geometry_msgs/msg/Transform",
                hex(&[
                    0xbe, 0xb8, 0x3f, 0xbe, 0x69, 0x86, 0x36, 0x35, 0x14, 0x61, 0xf6, 0xf3, 0x5d,
                    0x1a, 0xbb, 0x20, 0x01, 0x0c, 0x43, 0xd5, 0x53, 0x74, 0xd8, 0x1b, 0xd0, 0x41,
                    0xf1, 0xba, 0x25, 0x81, 0xfd, 0xdc,
                ]),
            ),
        ] {
            assert_eq!(type_hash(name).unwrap(), expected, "{name}");
        }
    }

    #[test]
    fn unknown_and_malformed_types_are_refused() {
        assert!(matches!(
            type_hash("nope/msg/Nothing"),
            Err(TypeError::Unknown(_))
        ));
        assert!(parse_field("t", "float64").is_err());
        assert!(parse_field("t", "Point p").is_err());
        assert!(parse_field("t", "float64[x] p").is_err());
        assert_eq!(parse_field("t", "char[16] g").unwrap().ty.type_id, 3 + 48);
        assert_eq!(
            parse_field("t", "a/msg/B[<=1] g").unwrap().ty.type_id,
            1 + 96
        );
    }
}
