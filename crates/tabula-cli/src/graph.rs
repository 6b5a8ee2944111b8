//! `tabula graph`: the ROS 2 graph a zenoh network carries, read from rmw_zenoh's
//! liveliness tokens — `ros2 node list`, `ros2 topic list -t` and `ros2 service list
//! -t` without a ROS installation, to see what `tabula serve` (or any rmw_zenoh node)
//! offers.

use anyhow::{Result, anyhow};
use std::collections::BTreeMap;
use std::time::Duration;
use tabula_ros::node::{Mode, Node, NodeConfig};
use tabula_ros::wire::{EntityKind, ros_type_name};

#[derive(clap::Args)]
pub struct GraphArgs {
    /// A zenoh router or peer of the network (`tabula serve`, `rmw_zenohd`).
    #[arg(long, value_name = "ENDPOINT", required = true)]
    pub connect: Vec<String>,
    /// ROS_DOMAIN_ID.
    #[arg(long, default_value_t = 0, value_parser = clap::value_parser!(u32).range(0..=232))]
    pub domain: u32,
    #[arg(long)]
    pub json: bool,
}

#[derive(Default, serde::Serialize)]
struct Endpoints {
    types: Vec<String>,
    publishers: usize,
    subscriptions: usize,
    servers: usize,
    clients: usize,
}

pub fn run(a: GraphArgs) -> Result<()> {
    let mut config = NodeConfig::new("tabula_graph", Mode::Client);
    config.connect = a.connect.clone();
    config.domain = a.domain;
    let node =
        Node::open(config).map_err(|e| anyhow!("cannot reach {}: {e}", a.connect.join(", ")))?;
    let own = node.zid().to_string();
    let tokens = node
        .graph(Duration::from_secs(2))
        .map_err(|e| anyhow!("{e}"))?;
    let mut nodes = std::collections::BTreeSet::new();
    let mut topics: BTreeMap<String, Endpoints> = BTreeMap::new();
    let mut services: BTreeMap<String, Endpoints> = BTreeMap::new();
    for t in tokens.into_iter().filter(|t| t.zid != own) {
        let full = format!("{}/{}", t.namespace.trim_end_matches('/'), t.node);
        match t.kind {
            EntityKind::Node => {
                nodes.insert(full);
            }
            kind => {
                let (Some(name), Some(dds)) = (t.topic, t.dds_type) else {
                    continue;
                };
                let book = match kind {
                    EntityKind::Publisher | EntityKind::Subscription => &mut topics,
                    _ => &mut services,
                };
                let e = book.entry(name).or_default();
                let ty = ros_type_name(&dds).unwrap_or(dds);
                if !e.types.contains(&ty) {
                    e.types.push(ty);
                }
                match kind {
                    EntityKind::Publisher => e.publishers += 1,
                    EntityKind::Subscription => e.subscriptions += 1,
                    EntityKind::ServiceServer => e.servers += 1,
                    _ => e.clients += 1,
                }
            }
        }
    }
    if a.json {
        println!(
            "{}",
            serde_json::to_string_pretty(&serde_json::json!({
                "nodes": nodes, "topics": topics, "services": services,
            }))?
        );
        return Ok(());
    }
    println!("nodes:");
    for n in &nodes {
        println!("  {n}");
    }
    println!("topics:");
    for (name, e) in &topics {
        println!(
            "  {name} [{}]  {} publisher(s), {} subscription(s)",
            e.types.join(", "),
            e.publishers,
            e.subscriptions
        );
    }
    println!("services:");
    for (name, e) in &services {
        println!("  {name} [{}]", e.types.join(", "));
    }
    Ok(())
}
