//! tabula's ROS 2 side checked by an independent implementation of rmw_zenoh's
//! conventions (ZettaScale's hiroz: its liveliness-token parser and key formatter, its
//! RIHS01 hasher) and another CDR implementation (the `cdr` crate), over a real zenoh
//! session on loopback: what a ROS 2 node under rmw_zenoh would see of `tabula serve`.

use hiroz_protocol::entity::{EndpointKind, Entity};
use hiroz_protocol::format::KeyExprFormatter;
use hiroz_protocol::format::rmw_zenoh::RmwZenohFormatter;
use serde::Deserialize;
use std::net::TcpListener;
use std::sync::Arc;
use std::sync::atomic::{AtomicBool, Ordering};
use std::time::{Duration, Instant};
use tabula_ros::node::{Mode, NodeConfig};
use tabula_ros::serve::{Rates, Server};
use tabula_ros::types::{DEFINITIONS, description, type_hash};
use tabula_ros::wire::Attachment;
use zenoh::Wait;

fn free_port() -> u16 {
    TcpListener::bind("127.0.0.1:0")
        .and_then(|l| l.local_addr())
        .map(|a| a.port())
        .expect("a free loopback port")
}

/// `sensor_msgs/msg/PointCloud2` as the test's own reader declares it.
#[derive(Deserialize)]
struct Time {
    _sec: i32,
    _nanosec: u32,
}
#[derive(Deserialize)]
struct Header {
    _stamp: Time,
    frame_id: String,
}
#[derive(Deserialize)]
struct PointField {
    name: String,
    offset: u32,
    datatype: u8,
    count: u32,
}
#[derive(Deserialize)]
struct PointCloud2 {
    header: Header,
    height: u32,
    width: u32,
    fields: Vec<PointField>,
    is_bigendian: bool,
    point_step: u32,
    row_step: u32,
    #[serde(with = "serde_bytes")]
    data: Vec<u8>,
    _is_dense: bool,
}

/// Every hash tabula declares, computed again by hiroz-schema from the same
/// descriptions (its JSON writer and SHA-256, not ours).
#[test]
fn type_hashes_agree_with_hiroz() {
    use hiroz_schema::{FieldDescription, FieldTypeDescription, TypeDescription};
    let convert = |name: &str, fields: &[tabula_ros::types::Field]| TypeDescription {
        type_name: name.into(),
        fields: fields
            .iter()
            .map(|f| FieldDescription {
                name: f.name.clone(),
                field_type: FieldTypeDescription {
                    type_id: f.ty.type_id as u8,
                    capacity: f.ty.capacity,
                    string_capacity: f.ty.string_capacity,
                    nested_type_name: f.ty.nested_type_name.clone(),
                },
                default_value: String::new(),
            })
            .collect(),
    };
    for (name, _) in DEFINITIONS {
        let d = description(name).unwrap();
        let msg = hiroz_schema::TypeDescriptionMsg {
            type_description: convert(&d.type_name, &d.fields),
            referenced_type_descriptions: d.referenced.iter().map(|(n, f)| convert(n, f)).collect(),
        };
        assert_eq!(
            hiroz_schema::calculate_hash(&msg).to_rihs_string(),
            type_hash(name).unwrap(),
            "{name}"
        );
    }
}

#[test]
fn a_ros2_peer_sees_the_served_robot_and_decodes_its_cloud() {
    let scene = tabula_sim::Scene::load(std::path::Path::new(concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/../../scenes/pr2_holding.toml"
    )))
    .unwrap();
    let world = tabula_sim::SimWorld::from_scene(&scene, Default::default()).unwrap();
    let endpoint = format!("tcp/127.0.0.1:{}", free_port());
    let mut config = NodeConfig::new("tabula_sim", Mode::Router);
    config.listen = vec![endpoint.clone()];
    config.domain = 7;
    let rates = Rates {
        state_hz: 20.0,
        camera_hz: 4.0,
    };
    let mut server = Server::new(&world, "pr2", 1, config, rates).unwrap();
    let stop = Arc::new(AtomicBool::new(false));
    let stop2 = stop.clone();
    let serving = std::thread::spawn(move || {
        server
            .serve(world, &move || stop2.load(Ordering::SeqCst))
            .map(|_| ())
    });

    // An independent peer: a plain zenoh client session.
    let mut c = zenoh::Config::default();
    c.insert_json5("mode", "\"client\"").unwrap();
    c.insert_json5("connect/endpoints", &format!("[\"{endpoint}\"]"))
        .unwrap();
    c.insert_json5("scouting/multicast/enabled", "false")
        .unwrap();
    let session = zenoh::open(c).wait().unwrap();

    // The graph as `ros2 node list` / `ros2 topic list` build it: liveliness tokens.
    let deadline = Instant::now() + Duration::from_secs(10);
    let (node, cloud_endpoint) = loop {
        let replies = session
            .liveliness()
            .get("@ros2_lv/7/**")
            .timeout(Duration::from_secs(2))
            .wait()
            .unwrap();
        let mut node = None;
        let mut cloud = None;
        while let Ok(reply) = replies.recv() {
            let Ok(sample) = reply.result() else { continue };
            match RmwZenohFormatter::parse_liveliness(sample.key_expr()).unwrap() {
                Entity::Node(n) => node = Some(n),
                Entity::Endpoint(e) if e.topic == "/head/points" => cloud = Some(e),
                Entity::Endpoint(_) => {}
            }
        }
        if let (Some(n), Some(c)) = (node, cloud) {
            break (n, c);
        }
        assert!(
            Instant::now() < deadline,
            "no tokens for the node and its cloud"
        );
    };
    assert_eq!(node.name, "tabula_sim");
    assert_eq!(node.domain_id, 7);
    assert!(matches!(cloud_endpoint.kind, EndpointKind::Publisher));
    let type_info = cloud_endpoint.type_info.clone().expect("a typed endpoint");
    assert_eq!(type_info.name, "sensor_msgs::msg::dds_::PointCloud2_");
    // The hash ROS 2 (Jazzy) gives sensor_msgs/msg/PointCloud2.
    assert_eq!(
        type_info.hash.to_rihs_string(),
        "RIHS01_9198cabf7da3796ae6fe19c4cb3bdd3525492988c70522628af5daa124bae2b5"
    );

    // Subscribe where hiroz says the samples are, and decode one with the `cdr` crate
    // (its own encapsulation-header reader).
    let key = RmwZenohFormatter::topic_key_expr(&cloud_endpoint).unwrap();
    let subscriber = session.declare_subscriber(key.to_string()).wait().unwrap();
    let sample = subscriber
        .recv_timeout(Duration::from_secs(10))
        .unwrap()
        .expect("a point cloud within 10 s");
    let bytes = sample.payload().to_bytes();
    assert_eq!(&bytes[..4], &[0, 1, 0, 0], "plain little-endian CDR");
    let cloud: PointCloud2 = cdr::deserialize(&bytes).unwrap();
    assert_eq!((cloud.width, cloud.height), (640, 480));
    assert!(!cloud.is_bigendian);
    // In the TF frame of the link the camera is mounted on.
    assert_eq!(cloud.header.frame_id, "head_camera_optical_frame");
    let names: Vec<&str> = cloud.fields.iter().map(|f| f.name.as_str()).collect();
    assert_eq!(names, ["x", "y", "z", "rgb"]);
    assert!(cloud.fields.iter().all(|f| f.datatype == 7 && f.count == 1));
    assert_eq!(cloud.fields[2].offset, 8);
    assert_eq!(cloud.row_step, cloud.width * cloud.point_step);
    assert_eq!(cloud.data.len() as u32, cloud.row_step * cloud.height);
    // Some of the frame sees the table (finite depth ahead of the camera).
    let seen = cloud
        .data
        .chunks_exact(cloud.point_step as usize)
        .filter(|p| f32::from_le_bytes([p[8], p[9], p[10], p[11]]).is_finite())
        .count();
    assert!(seen > 10_000, "{seen} points with depth");
    let attachment = Attachment::decode(&sample.attachment().unwrap().to_bytes()).unwrap();
    assert!(attachment.sequence_number >= 1);

    // /tf as robot_state_publisher gives it: world → the root, then parent → child
    // for every joint; decoded by the `cdr` crate into the test's own declaration.
    #[derive(Deserialize)]
    struct Vector3 {
        _x: f64,
        _y: f64,
        _z: f64,
    }
    #[derive(Deserialize)]
    struct Quaternion {
        x: f64,
        y: f64,
        z: f64,
        w: f64,
    }
    #[derive(Deserialize)]
    struct TransformStamped {
        header: Header,
        child_frame_id: String,
        _translation: Vector3,
        rotation: Quaternion,
    }
    #[derive(Deserialize)]
    struct TfMessage {
        transforms: Vec<TransformStamped>,
    }
    let tf_key = format!(
        "7/tf/tf2_msgs::msg::dds_::TFMessage_/{}",
        type_hash("tf2_msgs/msg/TFMessage").unwrap()
    );
    let tf = session.declare_subscriber(tf_key).wait().unwrap();
    let sample = tf
        .recv_timeout(Duration::from_secs(10))
        .unwrap()
        .expect("a TF message within 10 s");
    let msg: TfMessage = cdr::deserialize(&sample.payload().to_bytes()).unwrap();
    let roots: Vec<&TransformStamped> = msg
        .transforms
        .iter()
        .filter(|t| t.header.frame_id == "world")
        .collect();
    assert_eq!(roots.len(), 1, "one root under `world`");
    let pr2 = tabula_robot::robots::load("pr2").unwrap();
    assert_eq!(msg.transforms.len(), pr2.model.joints.len() + 1);
    assert!(msg.transforms.iter().all(|t| {
        let q = &t.rotation;
        ((q.x * q.x + q.y * q.y + q.z * q.z + q.w * q.w) - 1.0).abs() < 1e-9
    }));
    assert!(
        msg.transforms
            .iter()
            .any(|t| t.child_frame_id == "head_camera_optical_frame")
    );

    stop.store(true, Ordering::SeqCst);
    serving.join().unwrap().unwrap();
}
