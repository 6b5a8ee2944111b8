//! What the network costs: a camera frame from `publish` (CDR encoding included) to a
//! subscriber holding tabula's decoded cloud, over zenoh on TCP loopback between two
//! sessions — a router and a client, as `tabula serve` and a task talk.

use crate::msgs::{Header, PointCloud2};
use crate::node::{Mode, Node, NodeConfig, RosError};
use crate::wire::Qos;
use std::sync::mpsc::{Receiver, channel};
use std::time::{Duration, Instant};
use tabula_geom::PointCloud;

/// A router listening on `endpoint` and a client connected to it.
fn pair(endpoint: &str) -> Result<(std::sync::Arc<Node>, std::sync::Arc<Node>), RosError> {
    let mut router = NodeConfig::new("tabula_bench_pub", Mode::Router);
    router.listen = vec![endpoint.into()];
    let publisher_node = Node::open(router)?;
    let mut client = NodeConfig::new("tabula_bench_sub", Mode::Client);
    client.connect = vec![endpoint.into()];
    Ok((publisher_node, Node::open(client)?))
}

/// The floor under [`cloud_latency`]: `bytes` bytes put and received as they are, no
/// message built, encoded or decoded (seconds per frame).
pub fn raw_latency(bytes: usize, frames: usize, endpoint: &str) -> Result<Vec<f64>, RosError> {
    use zenoh::Wait;
    let (a, b) = pair(endpoint)?;
    let key = "bench/raw";
    let (tx, rx) = channel::<Instant>();
    let _sub = b
        .session()
        .declare_subscriber(key)
        .callback(move |sample| {
            if sample.payload().len() == bytes {
                let _ = tx.send(Instant::now());
            }
        })
        .wait()
        .map_err(|e| RosError::Zenoh(e.to_string()))?;
    let publisher = a
        .session()
        .declare_publisher(key)
        .wait()
        .map_err(|e| RosError::Zenoh(e.to_string()))?;
    let payload = vec![7u8; bytes];
    let put = || {
        publisher
            .put(payload.clone())
            .wait()
            .map_err(|e| RosError::Zenoh(e.to_string()))
    };
    round_trips(put, &rx, frames, key)
}

/// Latency of each of `frames` publications of `cloud` (seconds), one frame in flight
/// at a time, the router listening on `endpoint`.
pub fn cloud_latency(
    cloud: &PointCloud,
    frames: usize,
    endpoint: &str,
) -> Result<Vec<f64>, RosError> {
    let (publisher_node, subscriber_node) = pair(endpoint)?;
    let topic = "/bench/points";
    let ros_type = "sensor_msgs/msg/PointCloud2";
    let publisher = publisher_node.publisher::<PointCloud2>(topic, ros_type, Qos::default())?;
    let (tx, rx) = channel::<Instant>();
    let _subscription = subscriber_node.subscribe(
        topic,
        ros_type,
        Qos::default(),
        move |msg: PointCloud2, _| {
            // Decoded to tabula's cloud, as a task would use it.
            if msg.to_cloud().is_ok() {
                let _ = tx.send(Instant::now());
            }
        },
    )?;
    // Built from tabula's cloud each time, as a driver publishing frames does.
    let publish = || publisher.publish(&PointCloud2::from_cloud(cloud, None, Header::default()));
    round_trips(publish, &rx, frames, topic)
}

/// Sends until the first sample arrives (before the subscription is matched, samples go
/// nowhere), then times `frames` sends one at a time: from `send` to the arrival the
/// receiver reports on `arrivals`.
fn round_trips(
    send: impl Fn() -> Result<(), RosError>,
    arrivals: &Receiver<Instant>,
    frames: usize,
    what: &str,
) -> Result<Vec<f64>, RosError> {
    let deadline = Instant::now() + Duration::from_secs(10);
    loop {
        send()?;
        if arrivals.recv_timeout(Duration::from_millis(200)).is_ok() {
            break;
        }
        if Instant::now() > deadline {
            return Err(RosError::Timeout(what.into(), 10.0));
        }
    }
    while arrivals.try_recv().is_ok() {}
    let mut latencies = Vec::with_capacity(frames);
    for _ in 0..frames {
        let sent = Instant::now();
        send()?;
        let arrived = arrivals
            .recv_timeout(Duration::from_secs(10))
            .map_err(|_| RosError::Timeout(what.into(), 10.0))?;
        latencies.push(arrived.duration_since(sent).as_secs_f64());
    }
    Ok(latencies)
}
