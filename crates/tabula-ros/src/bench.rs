//! What the network costs: a camera frame from `publish` (CDR encoding included) to a
//! subscriber holding tabula's decoded cloud, over zenoh on TCP loopback between two
//! sessions — a router and a client, as `tabula serve` and a task talk.

use crate::msgs::{Header, PointCloud2};
use crate::node::{Mode, Node, NodeConfig, RosError};
use crate::wire::Qos;
use std::sync::mpsc::channel;
use std::time::{Duration, Instant};
use tabula_geom::PointCloud;

/// Latency of each of `frames` publications of `cloud` (seconds), one frame in flight
/// at a time, the router listening on `endpoint`.
pub fn cloud_latency(
    cloud: &PointCloud,
    frames: usize,
    endpoint: &str,
) -> Result<Vec<f64>, RosError> {
    let mut router = NodeConfig::new("tabula_bench_pub", Mode::Router);
    router.listen = vec![endpoint.into()];
    let publisher_node = Node::open(router)?;
    let mut client = NodeConfig::new("tabula_bench_sub", Mode::Client);
    client.connect = vec![endpoint.into()];
    let subscriber_node = Node::open(client)?;
    let topic = "/bench/points";
    let ros_type = "sensor_msgs/msg/PointCloud2";
    let publisher = publisher_node.publisher::<PointCloud2>(topic, ros_type, Qos::default())?;
    let (tx, rx) = channel::<(i64, Instant)>();
    let _subscription = subscriber_node.subscribe(
        topic,
        ros_type,
        Qos::default(),
        move |msg: PointCloud2, attachment| {
            // Decoded to tabula's cloud, as a task would use it.
            if msg.to_cloud().is_ok() {
                let seq = attachment.map_or(-1, |a| a.sequence_number);
                let _ = tx.send((seq, Instant::now()));
            }
        },
    )?;
    let msg = || PointCloud2::from_cloud(cloud, None, Header::default());
    // Until the subscription is matched, samples go nowhere: publish until one arrives.
    let deadline = Instant::now() + Duration::from_secs(10);
    loop {
        publisher.publish(&msg())?;
        if rx.recv_timeout(Duration::from_millis(200)).is_ok() {
            break;
        }
        if Instant::now() > deadline {
            return Err(RosError::Timeout(topic.into(), 10.0));
        }
    }
    while rx.try_recv().is_ok() {}
    let mut latencies = Vec::with_capacity(frames);
    for _ in 0..frames {
        let sent = Instant::now();
        publisher.publish(&msg())?;
        let (_, arrived) = rx
            .recv_timeout(Duration::from_secs(10))
            .map_err(|_| RosError::Timeout(topic.into(), 10.0))?;
        latencies.push(arrived.duration_since(sent).as_secs_f64());
    }
    Ok(latencies)
}
