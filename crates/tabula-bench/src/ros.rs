//! `bench ros`: a camera frame published as a PointCloud2 and received over zenoh, and
//! the same bytes put and received raw, on TCP loopback.

use anyhow::Result;
use serde::Serialize;

/// Latencies of `frames` frames (fields in the order JSON has always listed them).
#[derive(Serialize)]
pub struct Latency {
    pub frames: usize,
    pub width: usize,
    pub height: usize,
    pub bytes: usize,
    pub median_ms: f64,
    pub p95_ms: f64,
    pub max_ms: f64,
    pub raw_median_ms: f64,
    pub raw_p95_ms: f64,
    pub mb_per_s_at_median: f64,
}

/// The `q` quantile of sorted `v` by nearest rank; NaN when empty.
fn at(v: &[f64], q: f64) -> f64 {
    match v.len() {
        0 => f64::NAN,
        n => v[((n - 1) as f64 * q).round() as usize],
    }
}

impl Latency {
    /// The frame of scenes/pr2_holding.toml's head camera, published and received
    /// `frames` times, then its bytes raw.
    pub fn measure(frames: usize) -> Result<Self> {
        let scene = tabula_sim::Scene::parse(tabula_sim::builtin::PR2_HOLDING, "pr2_holding.toml")?;
        let world = tabula_sim::SimWorld::from_scene(&scene, Default::default())?;
        let camera = world.camera("head")?;
        let frame = tabula_sim::camera::capture(&world, &camera, 1);
        let endpoint = || -> Result<String> {
            let port = std::net::TcpListener::bind("127.0.0.1:0")?
                .local_addr()?
                .port();
            Ok(format!("tcp/127.0.0.1:{port}"))
        };
        let in_ms = |v: Vec<f64>| -> Vec<f64> {
            let mut ms: Vec<f64> = v.into_iter().map(|s| s * 1e3).collect();
            ms.sort_by(f64::total_cmp);
            ms
        };
        let ms = in_ms(
            tabula_ros::bench::cloud_latency(&frame.cloud, frames, &endpoint()?)
                .map_err(|e| anyhow::anyhow!("{e}"))?,
        );
        let bytes = frame.cloud.points.len() * 16;
        let raw = in_ms(
            tabula_ros::bench::raw_latency(bytes, frames, &endpoint()?)
                .map_err(|e| anyhow::anyhow!("{e}"))?,
        );
        Ok(Self {
            frames: ms.len(),
            width: frame.cloud.width,
            height: frame.cloud.height,
            bytes,
            median_ms: at(&ms, 0.5),
            p95_ms: at(&ms, 0.95),
            max_ms: at(&ms, 1.0),
            raw_median_ms: at(&raw, 0.5),
            raw_p95_ms: at(&raw, 0.95),
            mb_per_s_at_median: bytes as f64 / 1e6 / (at(&ms, 0.5) / 1e3),
        })
    }

    /// What `bench ros` prints.
    pub fn lines(&self) -> Vec<String> {
        vec![
            format!(
                "{}×{} PointCloud2 ({:.1} MB) publish → decoded, TCP loopback, {} frames: median {:.2} ms, p95 {:.2} ms, max {:.2} ms",
                self.width,
                self.height,
                self.bytes as f64 / 1e6,
                self.frames,
                self.median_ms,
                self.p95_ms,
                self.max_ms
            ),
            format!(
                "the same bytes put and received raw (zenoh alone): median {:.2} ms, p95 {:.2} ms",
                self.raw_median_ms, self.raw_p95_ms
            ),
        ]
    }
}
