//! rmw_zenoh's wire conventions as pure functions, apart from the network (so they are
//! tested against the reference's own examples): data key expressions, liveliness
//! tokens with their QoS string, the per-message attachment, and the CDR envelope.
//!
//! Conventions from `ros2/rmw_zenoh` (docs/design.md and `liveliness_utils.cpp`):
//! * data: `<domain>/<topic without its outer slashes>/<dds type name>/<RIHS01 hash>`;
//! * liveliness: `@ros2_lv/<domain>/<zid>/<node id>/<entity id>/<kind>/<enclave>/<ns>/<node>`
//!   then, for endpoints, `/<topic>/<dds type>/<hash>/<qos>`, every `/` inside a name
//!   turned into `%` and an empty namespace or enclave written `%`;
//! * attachment (rmw_zenoh ≥ 0.3, Jazzy and later): int64 sequence number, int64 source
//!   timestamp (ns), then the 16-byte GID with its length as an unsigned LEB128 (33 bytes);
//! * payload: CDR with the 4-byte encapsulation header (`00 01 00 00`: plain CDR, little
//!   endian).

use serde::{Serialize, de::DeserializeOwned};

/// The administration space every rmw_zenoh liveliness token lives under.
pub const ADMIN_SPACE: &str = "@ros2_lv";

/// Why bytes from the wire were refused.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum WireError {
    #[error("not an rmw attachment: {0} bytes")]
    Attachment(usize),
    #[error("not CDR: {0}")]
    Cdr(String),
    #[error("bad name `{0}`: {1}")]
    Name(String, &'static str),
}

/// `sensor_msgs/msg/PointCloud2` → `sensor_msgs::msg::dds_::PointCloud2_` (the DDS type
/// name rmw_zenoh puts in keys).
pub fn dds_type_name(ros_type: &str) -> Result<String, WireError> {
    let mut parts = ros_type.split('/');
    match (parts.next(), parts.next(), parts.next(), parts.next()) {
        (Some(pkg), Some(kind), Some(name), None)
            if !pkg.is_empty() && !kind.is_empty() && !name.is_empty() =>
        {
            Ok(format!("{pkg}::{kind}::dds_::{name}_"))
        }
        _ => Err(WireError::Name(
            ros_type.into(),
            "a type is package/msg|srv/Name",
        )),
    }
}

/// `sensor_msgs::msg::dds_::PointCloud2_` → `sensor_msgs/msg/PointCloud2` (`None` for
/// names that are not a ROS type's DDS name).
pub fn ros_type_name(dds: &str) -> Option<String> {
    let mut parts = dds.split("::");
    match (
        parts.next(),
        parts.next(),
        parts.next(),
        parts.next(),
        parts.next(),
    ) {
        (Some(pkg), Some(kind), Some("dds_"), Some(name), None) => {
            Some(format!("{pkg}/{kind}/{}", name.strip_suffix('_')?))
        }
        _ => None,
    }
}

/// `/a/b` → `a%b`: how names sit in liveliness tokens (one key chunk each).
pub fn mangle(name: &str) -> String {
    name.replace('/', "%")
}

/// A topic's name checked as ROS 2 requires (absolute here: tabula names every topic from
/// the root), without the slashes at its ends.
fn bare_topic(topic: &str) -> Result<&str, WireError> {
    let t = topic.trim_matches('/');
    if t.is_empty()
        || !t
            .chars()
            .all(|c| c.is_ascii_alphanumeric() || c == '_' || c == '/')
        || t.contains("//")
    {
        return Err(WireError::Name(
            topic.into(),
            "a topic is letters, digits, `_` and `/`",
        ));
    }
    Ok(t)
}

/// The key a topic's (or a service's) samples travel on.
pub fn topic_key(
    domain: u32,
    topic: &str,
    ros_type: &str,
    type_hash: &str,
) -> Result<String, WireError> {
    Ok(format!(
        "{domain}/{}/{}/{type_hash}",
        bare_topic(topic)?,
        dds_type_name(ros_type)?
    ))
}

/// What kind of graph entity a liveliness token announces.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum EntityKind {
    Node,
    Publisher,
    Subscription,
    ServiceServer,
    ServiceClient,
}

impl EntityKind {
    pub fn code(self) -> &'static str {
        match self {
            EntityKind::Node => "NN",
            EntityKind::Publisher => "MP",
            EntityKind::Subscription => "MS",
            EntityKind::ServiceServer => "SS",
            EntityKind::ServiceClient => "SC",
        }
    }
}

/// The QoS of an endpoint as rmw_zenoh writes it in tokens:
/// `reliability:durability:history,depth:deadline:lifespan:liveliness` with every value
/// at the RMW default left empty (reliable, volatile, keep-last 42, infinite durations,
/// automatic liveliness).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Qos {
    pub best_effort: bool,
    pub transient_local: bool,
    /// Keep-last depth (`None`: keep all).
    pub depth: Option<u32>,
}

impl Default for Qos {
    /// ROS 2's default profile for topics: reliable, volatile, keep last 10.
    fn default() -> Self {
        Self {
            best_effort: false,
            transient_local: false,
            depth: Some(10),
        }
    }
}

impl Qos {
    /// Sensor data (`rmw_qos_profile_sensor_data`): best effort, keep last 5.
    pub fn sensor_data() -> Self {
        Self {
            best_effort: true,
            transient_local: false,
            depth: Some(5),
        }
    }

    /// Services (`rmw_qos_profile_services_default`): reliable, volatile, keep last 10.
    pub fn services() -> Self {
        Self::default()
    }

    pub fn encode(&self) -> String {
        let reliability = if self.best_effort { "2" } else { "" };
        let durability = if self.transient_local { "1" } else { "" };
        let history = match self.depth {
            Some(42) => ",".to_string(),
            Some(d) => format!(",{d}"),
            None => "2,".to_string(),
        };
        format!("{reliability}:{durability}:{history}:,:,:,,")
    }
}

/// `<enclave>/<namespace>/<node>` of a token: the enclave and an empty namespace are `%`.
fn node_path(namespace: &str, node: &str) -> String {
    let ns = if namespace.trim_matches('/').is_empty() {
        "%".to_string()
    } else {
        mangle(namespace)
    };
    format!("%/{ns}/{}", mangle(node))
}

/// A node's liveliness token.
pub fn node_token(domain: u32, zid: &str, node_id: u32, namespace: &str, node: &str) -> String {
    format!(
        "{ADMIN_SPACE}/{domain}/{zid}/{node_id}/{node_id}/NN/{}",
        node_path(namespace, node)
    )
}

/// An endpoint's (publisher, subscription, service) liveliness token: the node's
/// domain, session id and id, the entity's id and kind.
pub fn endpoint_token(
    (domain, zid, node_id): (u32, &str, u32),
    (entity_id, kind): (u32, EntityKind),
    (namespace, node): (&str, &str),
    (topic, ros_type, type_hash): (&str, &str, &str),
    qos: Qos,
) -> Result<String, WireError> {
    Ok(format!(
        "{ADMIN_SPACE}/{domain}/{zid}/{node_id}/{entity_id}/{}/{}/{}/{}/{type_hash}/{}",
        kind.code(),
        node_path(namespace, node),
        mangle(&format!("/{}", bare_topic(topic)?)),
        dds_type_name(ros_type)?,
        qos.encode()
    ))
}

/// What a liveliness token says of its entity.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct TokenInfo {
    pub domain: u32,
    pub zid: String,
    pub kind: EntityKind,
    pub namespace: String,
    pub node: String,
    /// Endpoints only: the topic or service (with its leading `/`) and its DDS type.
    pub topic: Option<String>,
    pub dds_type: Option<String>,
}

/// Reads an rmw_zenoh liveliness token (the graph as `ros2 node list` builds it);
/// `None` for anything else.
pub fn parse_token(key: &str) -> Option<TokenInfo> {
    let parts: Vec<&str> = key.split('/').collect();
    if parts.len() < 9 || parts[0] != ADMIN_SPACE {
        return None;
    }
    let kind = match parts[5] {
        "NN" => EntityKind::Node,
        "MP" => EntityKind::Publisher,
        "MS" => EntityKind::Subscription,
        "SS" => EntityKind::ServiceServer,
        "SC" => EntityKind::ServiceClient,
        _ => return None,
    };
    let unmangle = |s: &str| {
        if s == "%" {
            String::new()
        } else {
            s.replace('%', "/")
        }
    };
    let endpoint = kind != EntityKind::Node;
    if endpoint && parts.len() < 13 {
        return None;
    }
    Some(TokenInfo {
        domain: parts[1].parse().ok()?,
        zid: parts[2].into(),
        kind,
        namespace: unmangle(parts[7]),
        node: unmangle(parts[8]),
        topic: endpoint.then(|| unmangle(parts[9])),
        dds_type: endpoint.then(|| parts[10].to_string()),
    })
}

/// What rmw_zenoh attaches to every sample and query.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Attachment {
    pub sequence_number: i64,
    /// Wall clock when sent (ns since the Unix epoch).
    pub source_timestamp: i64,
    pub source_gid: [u8; 16],
}

impl Attachment {
    pub const LEN: usize = 33;

    pub fn encode(&self) -> Vec<u8> {
        let mut out = Vec::with_capacity(Self::LEN);
        out.extend_from_slice(&self.sequence_number.to_le_bytes());
        out.extend_from_slice(&self.source_timestamp.to_le_bytes());
        out.push(16);
        out.extend_from_slice(&self.source_gid);
        out
    }

    pub fn decode(bytes: &[u8]) -> Result<Self, WireError> {
        if bytes.len() != Self::LEN || bytes[16] != 16 {
            return Err(WireError::Attachment(bytes.len()));
        }
        let i64_at = |k: usize| {
            let mut b = [0u8; 8];
            b.copy_from_slice(&bytes[k..k + 8]);
            i64::from_le_bytes(b)
        };
        let mut gid = [0u8; 16];
        gid.copy_from_slice(&bytes[17..]);
        Ok(Self {
            sequence_number: i64_at(0),
            source_timestamp: i64_at(8),
            source_gid: gid,
        })
    }
}

/// The encapsulation header of plain little-endian CDR (RTPS `CDR_LE`).
pub const CDR_LE: [u8; 4] = [0x00, 0x01, 0x00, 0x00];

/// A message as rmw_zenoh sends it: the encapsulation header, then CDR.
pub fn to_cdr<T: Serialize>(msg: &T) -> Result<Vec<u8>, WireError> {
    let mut out = CDR_LE.to_vec();
    cdr_encoding::to_writer::<T, byteorder::LittleEndian, _>(&mut out, msg)
        .map_err(|e| WireError::Cdr(e.to_string()))?;
    Ok(out)
}

/// A message from CDR bytes with their encapsulation header (either byte order).
pub fn from_cdr<T: DeserializeOwned>(bytes: &[u8]) -> Result<T, WireError> {
    if bytes.len() < 4 || bytes[0] != 0 {
        return Err(WireError::Cdr("no encapsulation header".into()));
    }
    let body = &bytes[4..];
    let decoded = match bytes[1] {
        0x01 => cdr_encoding::from_bytes::<T, byteorder::LittleEndian>(body),
        0x00 => cdr_encoding::from_bytes::<T, byteorder::BigEndian>(body),
        k => {
            return Err(WireError::Cdr(format!(
                "encapsulation kind {k} is not plain CDR"
            )));
        }
    };
    decoded
        .map(|(m, _)| m)
        .map_err(|e| WireError::Cdr(e.to_string()))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn keys_follow_rmw_zenoh() {
        assert_eq!(
            topic_key(
                0,
                "/head/points",
                "sensor_msgs/msg/PointCloud2",
                "RIHS01_ab"
            )
            .unwrap(),
            "0/head/points/sensor_msgs::msg::dds_::PointCloud2_/RIHS01_ab"
        );
        assert!(topic_key(0, "/", "a/msg/B", "h").is_err());
        assert!(topic_key(0, "/a b", "a/msg/B", "h").is_err());
        assert!(dds_type_name("PointCloud2").is_err());
        assert_eq!(
            ros_type_name("sensor_msgs::msg::dds_::PointCloud2_").as_deref(),
            Some("sensor_msgs/msg/PointCloud2")
        );
        assert_eq!(ros_type_name("PointCloud2"), None);
    }

    #[test]
    fn tokens_match_the_reference_example() {
        // The token zenoh-cpp's rmw_zenoh example declares for a point-cloud subscriber.
        let t = endpoint_token(
            (0, "zid", 0),
            (3, EntityKind::Subscription),
            ("", "zenoh_sub"),
            (
                "/point_cloud",
                "sensor_msgs/msg/PointCloud2",
                "RIHS01_9198cabf7da3796ae6fe19c4cb3bdd3525492988c70522628af5daa124bae2b5",
            ),
            Qos {
                best_effort: false,
                transient_local: false,
                depth: Some(5),
            },
        )
        .unwrap();
        assert_eq!(
            t,
            "@ros2_lv/0/zid/0/3/MS/%/%/zenoh_sub/%point_cloud/sensor_msgs::msg::dds_::PointCloud2_/RIHS01_9198cabf7da3796ae6fe19c4cb3bdd3525492988c70522628af5daa124bae2b5/::,5:,:,:,,"
        );
        assert_eq!(
            node_token(0, "zid", 0, "/", "zenoh_sub"),
            "@ros2_lv/0/zid/0/0/NN/%/%/zenoh_sub"
        );
        let tf_static = Qos {
            best_effort: false,
            transient_local: true,
            depth: Some(1),
        };
        assert_eq!(tf_static.encode(), ":1:,1:,:,:,,");
    }

    #[test]
    fn tokens_read_back() {
        let t = endpoint_token(
            (3, "abc", 0),
            (4, EntityKind::ServiceServer),
            ("", "tabula_worker"),
            (
                "/tabula/workers/w1/trial",
                "tabula_msgs/srv/Call",
                "RIHS01_x",
            ),
            Qos::services(),
        )
        .unwrap();
        let info = parse_token(&t).unwrap();
        assert_eq!(info.domain, 3);
        assert_eq!(info.kind, EntityKind::ServiceServer);
        assert_eq!(info.node, "tabula_worker");
        assert_eq!(info.topic.as_deref(), Some("/tabula/workers/w1/trial"));
        assert_eq!(
            info.dds_type.as_deref(),
            Some("tabula_msgs::srv::dds_::Call_")
        );
        let n = parse_token(&node_token(0, "abc", 0, "", "n")).unwrap();
        assert_eq!((n.kind, n.topic), (EntityKind::Node, None));
        assert!(parse_token("0/chatter/x/y").is_none());
        assert!(parse_token("@ros2_lv/0/abc/0/1/MP/%/%/n").is_none());
    }

    #[test]
    fn attachment_reads_what_rmw_zenoh_sends() {
        // Captured from rmw_zenoh 0.10.5 (`ros2 topic pub`), sequence number 9.
        let sample: Vec<u8> = "09 00 00 00 00 00 00 00 df 8a b6 f7 e7 35 d3 18 10 fe 98 e4 a3 b5 4b 6e 59 9c 59 34 f4 cf c2 53 43"
            .split(' ')
            .map(|h| u8::from_str_radix(h, 16).unwrap())
            .collect();
        let a = Attachment::decode(&sample).unwrap();
        assert_eq!(a.sequence_number, 9);
        assert_eq!(a.source_gid[0], 0xfe);
        assert_eq!(a.encode(), sample);
        assert!(Attachment::decode(&sample[..20]).is_err());
    }

    #[test]
    fn cdr_round_trips_with_its_header() {
        #[derive(Serialize, serde::Deserialize, PartialEq, Debug)]
        struct T {
            a: u8,
            b: f64,
            s: String,
        }
        let t = T {
            a: 7,
            b: 1.5,
            s: "x".into(),
        };
        let bytes = to_cdr(&t).unwrap();
        assert_eq!(&bytes[..4], &CDR_LE);
        // u8, pad to 8, f64, u32 length 2, "x\0".
        assert_eq!(bytes.len(), 4 + 8 + 8 + 4 + 2);
        assert_eq!(from_cdr::<T>(&bytes).unwrap(), t);
        assert!(from_cdr::<T>(&bytes[..3]).is_err());
        assert!(from_cdr::<T>(&bytes[..10]).is_err());
    }
}
