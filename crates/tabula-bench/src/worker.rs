//! Trials on `tabula worker` processes over zenoh: the worker's loop that answers
//! them one at a time, and the bench's side that spreads trials over the workers found.
//!
//! Each worker is a ROS 2 node (`tabula_worker`) with its own service
//! `/tabula/workers/<id>/trial` (`tabula_msgs/srv/Call`: a [`TrialSpec`] in, the
//! trial's row out, as JSON); the bench finds them in the graph and keeps each busy.

use crate::spec::{Spread, TrialSpec};
use anyhow::{Result, anyhow, bail};
use serde::de::DeserializeOwned;
use std::collections::{BTreeMap, VecDeque};
use std::sync::Mutex;
use std::time::{Duration, Instant};
use tabula_ros::msgs::{CallRequest, CallResponse};
use tabula_ros::node::{Mode, Node, NodeConfig, Request};
use tabula_ros::protocol::CALL_TYPE;
use tabula_ros::wire::EntityKind;

const WORKERS: &str = "/tabula/workers/";

/// Serves trials on the network `connect` reaches (ROS domain `domain`) until Ctrl+C
/// or for `duration` seconds; an error when nothing answers there within `wait` s.
pub fn serve(connect: &[String], domain: u32, wait: f64, duration: Option<f64>) -> Result<()> {
    let mut config = NodeConfig::new("tabula_worker", Mode::Peer);
    config.connect = connect.to_vec();
    config.domain = domain;
    let node =
        Node::open(config).map_err(|e| anyhow!("cannot join {}: {e}", connect.join(", ")))?;
    // A peer session opens whether or not anything answers at the endpoints: a worker
    // that reached nothing says so instead of waiting forever as if it were ready.
    let reached = Instant::now();
    loop {
        if node.reached() > 0 {
            break;
        }
        if reached.elapsed().as_secs_f64() > wait || tabula_robot::driver::stop_requested() {
            bail!(
                "cannot join {}: nothing answered there within {wait} s (is the bench's --listen or a router running?)",
                connect.join(", ")
            );
        }
        std::thread::sleep(Duration::from_millis(50));
    }
    // The session id names the worker: unique on the network.
    let id: String = node
        .zid()
        .chars()
        .filter(char::is_ascii_alphanumeric)
        .collect();
    let (tx, rx) = std::sync::mpsc::channel::<Request<CallRequest>>();
    let _service = node
        .service_queue(&format!("{WORKERS}w{id}/trial"), CALL_TYPE, move |r| {
            let _ = tx.send(r);
        })
        .map_err(|e| anyhow!("{e}"))?;
    eprintln!("worker w{id} ready on {}", connect.join(", "));
    let start = Instant::now();
    let until = duration.map(Duration::from_secs_f64);
    while !(tabula_robot::driver::stop_requested() || until.is_some_and(|d| start.elapsed() >= d)) {
        let Ok(r) = rx.recv_timeout(Duration::from_millis(100)) else {
            continue;
        };
        let answer = serde_json::from_str::<TrialSpec>(&r.request.request)
            .map_err(|e| anyhow!("not a trial: {e}"))
            .and_then(|spec| crate::registry::trial(&spec));
        r.reply(&match answer {
            Ok(row) => CallResponse {
                ok: true,
                response: row.to_string(),
            },
            Err(e) => CallResponse {
                ok: false,
                response: format!("{e:#}"),
            },
        });
    }
    let _ = std::fs::remove_dir_all(crate::place::worker_mesh_dir());
    Ok(())
}

/// How long one trial may take on a worker.
const TRIAL_TIMEOUT: Duration = Duration::from_secs(1800);

/// Runs the trials of `seeds` on `n` workers found in the graph, each kept busy with
/// one trial at a time; the rows in seed order.
pub fn spread<R: DeserializeOwned + Send>(
    args: &Spread,
    n: usize,
    seeds: std::ops::Range<u64>,
    spec: impl Fn(u64) -> TrialSpec + Sync,
    tick: &(dyn Fn() + Sync),
) -> Result<Vec<R>> {
    if args.connect.is_empty() && args.listen.is_empty() {
        bail!("--workers needs --connect (a router the workers joined) or --listen");
    }
    let mode = if args.listen.is_empty() {
        Mode::Client
    } else {
        Mode::Router
    };
    let mut config = NodeConfig::new("tabula_bench", mode);
    config.connect = args.connect.clone();
    config.listen = args.listen.clone();
    config.domain = args.domain;
    let node = Node::open(config).map_err(|e| anyhow!("cannot join the workers' network: {e}"))?;
    let deadline = Instant::now() + Duration::from_secs(60);
    let workers: Vec<String> = loop {
        let mut found: Vec<String> = node
            .graph(Duration::from_millis(500))
            .map_err(|e| anyhow!("{e}"))?
            .into_iter()
            .filter(|t| t.kind == EntityKind::ServiceServer)
            .filter_map(|t| t.topic)
            .filter(|t| t.starts_with(WORKERS) && t.ends_with("/trial"))
            .collect();
        found.sort();
        found.dedup();
        if found.len() >= n {
            found.truncate(n);
            break found;
        }
        if Instant::now() > deadline {
            bail!("{} of {n} workers found within 60 s", found.len());
        }
        std::thread::sleep(Duration::from_millis(200));
    };
    tracing::info!("trials on {}", workers.join(", "));
    let queue = Mutex::new(seeds.collect::<VecDeque<u64>>());
    let rows: Mutex<BTreeMap<u64, Result<R>>> = Mutex::default();
    std::thread::scope(|scope| {
        for name in &workers {
            let (node, queue, rows, spec) = (&node, &queue, &rows, &spec);
            scope.spawn(move || {
                let client = match node.client::<CallRequest, CallResponse>(name, CALL_TYPE) {
                    Ok(c) => c,
                    Err(e) => {
                        tracing::warn!("{name}: {e}");
                        return;
                    }
                };
                loop {
                    let Some(seed) = queue.lock().ok().and_then(|mut q| q.pop_front()) else {
                        return;
                    };
                    let row = serde_json::to_string(&spec(seed))
                        .map_err(anyhow::Error::from)
                        .and_then(|request| {
                            client
                                .call(&CallRequest { request }, TRIAL_TIMEOUT)
                                .map_err(|e| anyhow!("{e}"))
                        })
                        .and_then(|r| {
                            if r.ok {
                                serde_json::from_str::<R>(&r.response)
                                    .map_err(|e| anyhow!("malformed row from {name}: {e}"))
                            } else {
                                Err(anyhow!("trial {seed} on {name}: {}", r.response))
                            }
                        });
                    if let Ok(mut rows) = rows.lock() {
                        rows.insert(seed, row);
                    }
                    tick();
                }
            });
        }
    });
    let rows = rows
        .into_inner()
        .map_err(|_| anyhow!("a worker thread panicked"))?;
    rows.into_values().collect()
}
