//! A zenoh session as a ROS 2 node with `rmw_zenoh`'s conventions: every publisher,
//! subscription and service declares its liveliness token, so `ros2 node list` and
//! `ros2 topic list` under `rmw_zenoh` show them, samples carry the rmw attachment, and
//! payloads are CDR. One session per node, opened once (zenoh's own advice).

use crate::types::type_hash;
use crate::wire::{
    Attachment, EntityKind, Qos, WireError, endpoint_token, from_cdr, node_token, to_cdr, topic_key,
};
use serde::{Serialize, de::DeserializeOwned};
use std::marker::PhantomData;
use std::sync::Arc;
use std::sync::atomic::{AtomicI64, AtomicU32, Ordering};
use std::time::{Duration, SystemTime, UNIX_EPOCH};
use zenoh::Wait;
use zenoh::liveliness::LivelinessToken;

/// Why talking over zenoh failed.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum RosError {
    #[error("zenoh: {0}")]
    Zenoh(String),
    #[error(transparent)]
    Wire(#[from] WireError),
    #[error(transparent)]
    Type(#[from] crate::types::TypeError),
    #[error("no answer from `{0}` within {1:.1} s (is `tabula serve` running and reachable?)")]
    Timeout(String, f64),
    #[error("`{0}` answered with an error: {1}")]
    Remote(String, String),
}

/// zenoh's error, without the source location its messages end with.
fn zerr(e: impl std::fmt::Display) -> RosError {
    let text = e.to_string();
    let text = text.split(" at /").next().unwrap_or(&text).trim();
    RosError::Zenoh(text.to_string())
}

/// How a node joins the network (zenoh's modes): a router accepts ROS 2 nodes that
/// connect to it (as `rmw_zenohd` does); a peer or a client connects.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Mode {
    Router,
    Peer,
    Client,
}

/// Where and how a node opens its session.
#[derive(Debug, Clone)]
pub struct NodeConfig {
    pub name: String,
    pub namespace: String,
    /// ROS_DOMAIN_ID.
    pub domain: u32,
    pub mode: Mode,
    /// Endpoints to listen on (`tcp/127.0.0.1:7447`).
    pub listen: Vec<String>,
    /// Endpoints to connect to.
    pub connect: Vec<String>,
    /// A zenoh configuration file (JSON5), read first; the fields above then apply.
    pub config_file: Option<std::path::PathBuf>,
    /// Keep trying to reach `connect` in the background (a worker waiting for its
    /// router) rather than failing at once (a task that needs its robot now).
    pub keep_trying: bool,
}

impl NodeConfig {
    pub fn new(name: &str, mode: Mode) -> Self {
        Self {
            name: name.into(),
            namespace: String::new(),
            domain: 0,
            mode,
            listen: Vec::new(),
            connect: Vec::new(),
            config_file: None,
            keep_trying: false,
        }
    }

    fn zenoh_config(&self) -> Result<zenoh::Config, RosError> {
        for e in self.listen.iter().chain(&self.connect) {
            if e.parse::<zenoh::config::EndPoint>().is_err() {
                return Err(RosError::Zenoh(format!(
                    "`{}` is not a zenoh endpoint (protocol/address, like tcp/127.0.0.1:7447)",
                    tabula_geom::input::clip(e, 80)
                )));
            }
        }
        let mut c = match &self.config_file {
            // Through the input policy's reader: zenoh's own would read `/dev/zero`
            // until the memory runs out.
            Some(path) => {
                let text = tabula_geom::input::read_text(path, tabula_geom::input::Format::Params)
                    .map_err(|e| RosError::Zenoh(e.to_string()))?;
                zenoh::Config::from_json5(&text)
                    .map_err(|e| RosError::Zenoh(format!("{}: {e}", path.display())))?
            }
            None => zenoh::Config::default(),
        };
        let mode = match self.mode {
            Mode::Router => "\"router\"",
            Mode::Peer => "\"peer\"",
            Mode::Client => "\"client\"",
        };
        let list = |v: &[String]| serde_json::to_string(v).unwrap_or_else(|_| "[]".into());
        c.insert_json5("mode", mode).map_err(zerr)?;
        if self.config_file.is_none() || !self.listen.is_empty() {
            c.insert_json5("listen/endpoints", &list(&self.listen))
                .map_err(zerr)?;
        }
        if self.config_file.is_none() || !self.connect.is_empty() {
            c.insert_json5("connect/endpoints", &list(&self.connect))
                .map_err(zerr)?;
        }
        if self.keep_trying {
            c.insert_json5("connect/timeout_ms", "-1").map_err(zerr)?;
            c.insert_json5("connect/exit_on_failure", "false")
                .map_err(zerr)?;
        }
        if self.config_file.is_none() {
            // Explicit endpoints only, as rmw_zenoh's default session config: no
            // multicast scouting that finds (or is blocked by) whatever is on the LAN.
            c.insert_json5("scouting/multicast/enabled", "false")
                .map_err(zerr)?;
        }
        Ok(c)
    }
}

/// One ROS 2 node over a zenoh session.
pub struct Node {
    session: zenoh::Session,
    pub config: NodeConfig,
    zid: String,
    next_entity: AtomicU32,
    _token: LivelinessToken,
}

/// The node id rmw_zenoh gives the first node of a context.
const NODE_ID: u32 = 0;

fn now_ns() -> i64 {
    SystemTime::now()
        .duration_since(UNIX_EPOCH)
        .map_or(0, |d| d.as_nanos() as i64)
}

impl Node {
    pub fn open(config: NodeConfig) -> Result<Arc<Node>, RosError> {
        let session = zenoh::open(config.zenoh_config()?).wait().map_err(zerr)?;
        let zid = session.zid().to_string();
        let token = session
            .liveliness()
            .declare_token(node_token(
                config.domain,
                &zid,
                NODE_ID,
                &config.namespace,
                &config.name,
            ))
            .wait()
            .map_err(zerr)?;
        Ok(Arc::new(Node {
            session,
            config,
            zid,
            next_entity: AtomicU32::new(NODE_ID + 1),
            _token: token,
        }))
    }

    /// How many peers and routers the session is connected to now.
    pub fn reached(&self) -> usize {
        let info = self.session.info();
        info.peers_zid().wait().count() + info.routers_zid().wait().count()
    }

    pub fn session(&self) -> &zenoh::Session {
        &self.session
    }

    /// The session's zenoh id as tokens write it.
    pub fn zid(&self) -> &str {
        &self.zid
    }

    /// An endpoint's id, key, token and GID.
    fn endpoint(
        &self,
        kind: EntityKind,
        topic: &str,
        ros_type: &str,
        qos: Qos,
    ) -> Result<(String, LivelinessToken, [u8; 16]), RosError> {
        let id = self.next_entity.fetch_add(1, Ordering::Relaxed);
        let hash = type_hash(ros_type)?;
        let dds_type = ros_type.to_string();
        let key = topic_key(self.config.domain, topic, &dds_type, &hash)?;
        let token = endpoint_token(
            (self.config.domain, &self.zid, NODE_ID),
            (id, kind),
            (&self.config.namespace, &self.config.name),
            (topic, &dds_type, &hash),
            qos,
        )?;
        let token = self
            .session
            .liveliness()
            .declare_token(token)
            .wait()
            .map_err(zerr)?;
        // rmw_zenoh's GID: a digest of the entity's identity (16 bytes).
        let digest = <sha2::Sha256 as sha2::Digest>::digest(format!("{}/{id}", self.zid));
        let mut gid = [0u8; 16];
        gid.copy_from_slice(&digest[..16]);
        Ok((key, token, gid))
    }

    /// The ROS 2 graph of this node's domain as the liveliness tokens tell it (what
    /// `ros2 node list` and `ros2 topic list` show).
    pub fn graph(&self, timeout: Duration) -> Result<Vec<crate::wire::TokenInfo>, RosError> {
        graph(&self.session, self.config.domain, timeout)
    }

    /// A publisher of `ros_type` messages on `topic`.
    pub fn publisher<T: Serialize>(
        &self,
        topic: &str,
        ros_type: &str,
        qos: Qos,
    ) -> Result<Publisher<T>, RosError> {
        let (key, token, gid) = self.endpoint(EntityKind::Publisher, topic, ros_type, qos)?;
        let mut builder = self.session.declare_publisher(key.clone());
        if qos.best_effort {
            builder = builder.congestion_control(zenoh::qos::CongestionControl::Drop);
        } else {
            builder = builder.congestion_control(zenoh::qos::CongestionControl::Block);
        }
        let publisher = builder.wait().map_err(zerr)?;
        Ok(Publisher {
            publisher,
            key,
            gid,
            sequence: AtomicI64::new(0),
            _token: token,
            _type: PhantomData,
        })
    }

    /// Calls `on_message` with every `ros_type` message on `topic` (and its
    /// attachment); malformed samples are counted in the log and skipped.
    pub fn subscribe<T: DeserializeOwned + 'static>(
        &self,
        topic: &str,
        ros_type: &str,
        qos: Qos,
        on_message: impl Fn(T, Option<Attachment>) + Send + Sync + 'static,
    ) -> Result<Subscription, RosError> {
        let (key, token, _) = self.endpoint(EntityKind::Subscription, topic, ros_type, qos)?;
        let topic_name = topic.to_string();
        let subscriber = self
            .session
            .declare_subscriber(key)
            .callback(move |sample| {
                let bytes = sample.payload().to_bytes();
                let attachment = sample
                    .attachment()
                    .and_then(|a| Attachment::decode(&a.to_bytes()).ok());
                match from_cdr::<T>(&bytes) {
                    Ok(msg) => on_message(msg, attachment),
                    Err(e) => tracing::warn!("{topic_name}: dropped a sample: {e}"),
                }
            })
            .wait()
            .map_err(zerr)?;
        Ok(Subscription {
            _subscriber: subscriber,
            _token: token,
        })
    }

    /// Serves `srv_type` on `name`: `handler` answers every request.
    pub fn service<Req, Resp>(
        &self,
        name: &str,
        srv_type: &str,
        handler: impl Fn(Req) -> Resp + Send + Sync + 'static,
    ) -> Result<Service, RosError>
    where
        Req: DeserializeOwned + Clone + 'static,
        Resp: Serialize + 'static,
    {
        self.service_queue(name, srv_type, move |r: Request<Req>| {
            let answer = handler(r.request.clone());
            r.reply(&answer);
        })
    }

    /// Serves `srv_type` on `name`, handing every decoded request to `on_request`,
    /// which may answer it later from another thread ([`Request::reply`]); requests
    /// that do not decode are answered with an error here.
    pub fn service_queue<Req: DeserializeOwned + 'static>(
        &self,
        name: &str,
        srv_type: &str,
        on_request: impl Fn(Request<Req>) + Send + Sync + 'static,
    ) -> Result<Service, RosError> {
        let (key, token, gid) =
            self.endpoint(EntityKind::ServiceServer, name, srv_type, Qos::services())?;
        let queryable = self
            .session
            .declare_queryable(key)
            .complete(true)
            .callback(move |query| {
                let sequence = query
                    .attachment()
                    .and_then(|a| Attachment::decode(&a.to_bytes()).ok())
                    .map_or(0, |a| a.sequence_number);
                let decoded = query
                    .payload()
                    .ok_or_else(|| WireError::Cdr("an empty request".into()))
                    .and_then(|b| from_cdr::<Req>(&b.to_bytes()));
                match decoded {
                    Ok(request) => on_request(Request {
                        request,
                        query,
                        sequence,
                        gid,
                    }),
                    Err(e) => {
                        if let Err(e) = query.reply_err(e.to_string()).wait() {
                            tracing::warn!("reply not sent: {e}");
                        }
                    }
                }
            })
            .wait()
            .map_err(zerr)?;
        Ok(Service {
            _queryable: queryable,
            _token: token,
        })
    }

    /// A client of `srv_type` on `name`.
    pub fn client<Req: Serialize, Resp: DeserializeOwned>(
        &self,
        name: &str,
        srv_type: &str,
    ) -> Result<Client<Req, Resp>, RosError> {
        let (key, token, gid) =
            self.endpoint(EntityKind::ServiceClient, name, srv_type, Qos::services())?;
        Ok(Client {
            session: self.session.clone(),
            name: name.into(),
            key,
            gid,
            sequence: AtomicI64::new(0),
            _token: token,
            _types: PhantomData,
        })
    }
}

/// A declared publisher; dropping it undeclares it and its token.
pub struct Publisher<T> {
    publisher: zenoh::pubsub::Publisher<'static>,
    key: String,
    gid: [u8; 16],
    sequence: AtomicI64,
    _token: LivelinessToken,
    _type: PhantomData<fn(&T)>,
}

impl<T: Serialize> Publisher<T> {
    pub fn key(&self) -> &str {
        &self.key
    }

    pub fn publish(&self, msg: &T) -> Result<(), RosError> {
        let bytes = to_cdr(msg)?;
        let attachment = Attachment {
            sequence_number: self.sequence.fetch_add(1, Ordering::Relaxed) + 1,
            source_timestamp: now_ns(),
            source_gid: self.gid,
        };
        self.publisher
            .put(bytes)
            .attachment(attachment.encode())
            .wait()
            .map_err(zerr)
    }
}

/// A service request waiting for its answer.
pub struct Request<Req> {
    pub request: Req,
    query: zenoh::query::Query,
    sequence: i64,
    gid: [u8; 16],
}

impl<Req> Request<Req> {
    /// Answers the request (with the rmw attachment carrying its sequence number).
    pub fn reply<Resp: Serialize>(self, answer: &Resp) {
        let attachment = Attachment {
            sequence_number: self.sequence,
            source_timestamp: now_ns(),
            source_gid: self.gid,
        }
        .encode();
        let sent = match to_cdr(answer) {
            Ok(bytes) => self
                .query
                .reply(self.query.key_expr().clone(), bytes)
                .attachment(attachment)
                .wait(),
            Err(e) => self.query.reply_err(e.to_string()).wait(),
        };
        if let Err(e) = sent {
            tracing::warn!("reply not sent: {e}");
        }
    }
}

/// A declared subscription; dropping it undeclares it.
pub struct Subscription {
    _subscriber: zenoh::pubsub::Subscriber<()>,
    _token: LivelinessToken,
}

/// A declared service; dropping it undeclares it.
pub struct Service {
    _queryable: zenoh::query::Queryable<()>,
    _token: LivelinessToken,
}

/// A service client.
pub struct Client<Req, Resp> {
    session: zenoh::Session,
    name: String,
    key: String,
    gid: [u8; 16],
    sequence: AtomicI64,
    _token: LivelinessToken,
    _types: PhantomData<fn(&Req) -> Resp>,
}

impl<Req: Serialize, Resp: DeserializeOwned> Client<Req, Resp> {
    /// Sends `request` and waits up to `timeout` for the answer.
    pub fn call(&self, request: &Req, timeout: Duration) -> Result<Resp, RosError> {
        let attachment = Attachment {
            sequence_number: self.sequence.fetch_add(1, Ordering::Relaxed) + 1,
            source_timestamp: now_ns(),
            source_gid: self.gid,
        };
        let replies = self
            .session
            .get(self.key.as_str())
            .payload(to_cdr(request)?)
            .attachment(attachment.encode())
            .target(zenoh::query::QueryTarget::AllComplete)
            .consolidation(zenoh::query::ConsolidationMode::None)
            .timeout(timeout)
            .wait()
            .map_err(zerr)?;
        match replies.recv() {
            Ok(reply) => match reply.result() {
                Ok(sample) => Ok(from_cdr(&sample.payload().to_bytes())?),
                Err(e) => Err(RosError::Remote(
                    self.name.clone(),
                    String::from_utf8_lossy(&e.payload().to_bytes()).into_owned(),
                )),
            },
            Err(_) => Err(RosError::Timeout(self.name.clone(), timeout.as_secs_f64())),
        }
    }

    /// Waits until a server of this service is in the graph (or `timeout` passes).
    pub fn wait_for_server(&self, domain: u32, timeout: Duration) -> Result<(), RosError> {
        let deadline = std::time::Instant::now() + timeout;
        let name = format!("/{}", self.name.trim_matches('/'));
        loop {
            let found = graph(&self.session, domain, Duration::from_millis(500))?
                .into_iter()
                .any(|t| {
                    t.kind == EntityKind::ServiceServer && t.topic.as_deref() == Some(name.as_str())
                });
            if found {
                return Ok(());
            }
            if std::time::Instant::now() > deadline {
                return Err(RosError::Timeout(self.name.clone(), timeout.as_secs_f64()));
            }
            std::thread::sleep(Duration::from_millis(100));
        }
    }
}

fn graph(
    session: &zenoh::Session,
    domain: u32,
    timeout: Duration,
) -> Result<Vec<crate::wire::TokenInfo>, RosError> {
    let replies = session
        .liveliness()
        .get(format!("{}/{domain}/**", crate::wire::ADMIN_SPACE))
        .timeout(timeout)
        .wait()
        .map_err(zerr)?;
    let mut tokens = Vec::new();
    while let Ok(reply) = replies.recv() {
        if let Ok(sample) = reply.result()
            && let Some(t) = crate::wire::parse_token(sample.key_expr().as_str())
        {
            tokens.push(t);
        }
    }
    Ok(tokens)
}
