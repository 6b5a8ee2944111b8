//! The perception benchmarks: every stage timed on the generated reference frame (CPU
//! on one thread, wall on two; the anchors PCL and Open3D give on the same frame),
//! quality against the simulator's labels on a suite of seeded scenes, and the whole
//! pipeline on sensor files.

pub mod suite;

pub use suite::PerceptionBench;

use crate::stats::median;
use anyhow::Result;
use serde::Serialize;
use std::time::Instant;
use tabula_geom::polygon::{inside_convex, polygon_area};
use tabula_geom::{CloudFile, PointCloud, Vec2, Vec3};
use tabula_perception::eval::{Score, Truth, score, table_top_truth};
use tabula_perception::filters::{
    NormalParams, OutlierParams, local_planes_at, statistical_outliers, voxel_grid,
};
use tabula_perception::plane::{RansacParams, ransac_plane};
use tabula_perception::segment::euclidean_clusters;
use tabula_perception::surfaces::plane_basis;
use tabula_perception::{TabletopParams, extract, to_world};
use tabula_robot::ik::bench::thread_cpu_seconds;
use tabula_sim::generate::{TABLE_TOP, TabletopLayout, tabletop_frame};

/// One stage's times on the reference frame, with the anchor measured beside it.
#[derive(Serialize)]
pub struct StageTime {
    pub stage: String,
    pub cpu_ms_1_thread: f64,
    pub wall_ms_2_threads: f64,
    pub anchor: &'static str,
}

/// Times work: median CPU ms on one thread and median wall ms on two, over `reps` runs.
pub struct Timer {
    one: rayon::ThreadPool,
    two: rayon::ThreadPool,
    reps: usize,
}

impl Timer {
    pub fn new(reps: usize) -> Result<Self> {
        Ok(Self {
            one: rayon::ThreadPoolBuilder::new().num_threads(1).build()?,
            two: rayon::ThreadPoolBuilder::new().num_threads(2).build()?,
            reps,
        })
    }

    /// Median CPU ms on one thread and median wall ms on two.
    pub fn time(&self, f: &(dyn Fn() + Sync)) -> (f64, f64) {
        let cpu = (0..self.reps)
            .map(|_| {
                self.one.install(|| {
                    let c0 = thread_cpu_seconds();
                    f();
                    (thread_cpu_seconds() - c0) * 1e3
                })
            })
            .collect::<Vec<f64>>();
        let wall = (0..self.reps)
            .map(|_| {
                self.two.install(|| {
                    let t = Instant::now();
                    f();
                    t.elapsed().as_secs_f64() * 1e3
                })
            })
            .collect::<Vec<f64>>();
        (
            median(&cpu).unwrap_or(f64::NAN),
            median(&wall).unwrap_or(f64::NAN),
        )
    }
}

impl Timer {
    /// The same pools with fewer repetitions.
    pub fn with_reps(self, reps: usize) -> Self {
        Self { reps, ..self }
    }
}

/// A generated frame in the world frame with the simulator's labels.
pub struct Frame {
    cloud: PointCloud,
    viewpoint: Vec3,
    labels: Vec<u32>,
    table_label: u32,
    object_labels: Vec<u32>,
}

pub fn frame(seed: u64, layout: &TabletopLayout) -> Result<Frame> {
    let g = tabletop_frame(seed, layout)?;
    Ok(Frame {
        cloud: to_world(&g.frame.world_from_camera, &g.frame.cloud),
        viewpoint: g.frame.world_from_camera.translation,
        labels: g.frame.labels,
        table_label: g.table_label,
        object_labels: g.object_labels.iter().map(|o| o.1).collect(),
    })
}

pub fn quality(f: &Frame, params: &TabletopParams) -> Result<Score> {
    let t = extract(&f.cloud, f.viewpoint, params)?;
    let finite: Vec<bool> = f.cloud.points.iter().map(|p| p.is_finite()).collect();
    let top = table_top_truth(&f.cloud.points, TABLE_TOP);
    Ok(score(
        &t,
        &Truth {
            finite: &finite,
            labels: &f.labels,
            table_label: f.table_label,
            table_top: &top,
            object_labels: &f.object_labels,
        },
        0.8,
        200,
    ))
}

/// The prism of the reference frame (points over the table, inside its outline), for
/// the stages that run on it.
fn reference_prism(cloud: &PointCloud, eye: Vec3, params: &TabletopParams) -> Result<Vec<bool>> {
    let t = extract(cloud, eye, params)?;
    let (u, v) = plane_basis(t.plane.normal);
    let to2 = |q: Vec3| Vec2::new(q.dot(u), q.dot(v));
    let mut hull: Vec<Vec2> = t.table.hull.iter().map(|&q| to2(q)).collect();
    if polygon_area(&hull) < 0.0 {
        hull.reverse();
    }
    Ok(cloud
        .points
        .iter()
        .map(|&q| q.is_finite() && t.plane.distance(q) > 0.01 && inside_convex(&hull, to2(q)))
        .collect())
}

/// Every stage timed on the reference frame `nine` (the nine objects): rows in
/// the order the stages run; the frame's valid points.
pub fn stage_times(
    nine: &Frame,
    params: &TabletopParams,
    timer: &Timer,
) -> Result<(Vec<StageTime>, usize)> {
    let params = params.clone();
    let cloud = &nine.cloud;
    let eye = nine.viewpoint;
    let finite_points: Vec<Vec3> = cloud
        .points
        .iter()
        .copied()
        .filter(|p| p.is_finite())
        .collect();
    let unorganized = PointCloud::unorganized(finite_points.clone());
    let all: Vec<usize> = (0..cloud.points.len())
        .filter(|&i| cloud.points[i].is_finite())
        .collect();
    let prism = reference_prism(cloud, eye, &params)?;
    let prism_idx: Vec<usize> = (0..prism.len()).filter(|&i| prism[i]).collect();
    let anchor_sor = OutlierParams {
        mean_k: 20,
        std_mul: 2.0,
    };
    let fixed = RansacParams {
        confidence: 1.0,
        ..RansacParams::default()
    };
    let adaptive = RansacParams::default();
    type Stage<'a> = (&'a str, &'static str, Box<dyn Fn() + Sync + 'a>);
    let stages: Vec<Stage> = vec![
        (
            "statistical outlier removal k=20 2σ (image grid)",
            "PCL/Open3D 681–801 ms",
            Box::new(|| {
                let _ = statistical_outliers(cloud, Some(eye), &anchor_sor);
            }),
        ),
        (
            "statistical outlier removal k=20 2σ (kd-tree, unorganized)",
            "PCL/Open3D 681–801 ms",
            Box::new(|| {
                let _ = statistical_outliers(&unorganized, Some(eye), &anchor_sor);
            }),
        ),
        (
            "statistical outlier removal k=10 1σ (seed's, image grid)",
            "—",
            Box::new(|| {
                let _ = statistical_outliers(cloud, Some(eye), &params.outliers);
            }),
        ),
        (
            "RANSAC plane 1 cm, 1000 iterations, raw frame",
            "PCL 262 ms, Open3D 771 ms",
            Box::new(|| {
                let _ = ransac_plane(&cloud.points, &all, &fixed);
            }),
        ),
        (
            "RANSAC plane 1 cm, adaptive (p = 0.999), raw frame",
            "PCL 262 ms, Open3D 771 ms",
            Box::new(|| {
                let _ = ransac_plane(&cloud.points, &all, &adaptive);
            }),
        ),
        (
            "voxel grid 2 cm",
            "12–14 ms",
            Box::new(|| {
                let _ = voxel_grid(&finite_points, 0.02);
            }),
        ),
        (
            "normals of the prism (7×7 PCA)",
            "—",
            Box::new(|| {
                let _ = local_planes_at(cloud, eye, &prism, &prism_idx, &NormalParams::default());
            }),
        ),
        (
            "Euclidean clustering 1 cm of the prism (image grid)",
            "PCL/Open3D 162–169 ms",
            Box::new(|| {
                let _ = euclidean_clusters(cloud, Some(&prism), 0.01, 200);
            }),
        ),
        (
            "whole tabletop pipeline, same points unorganized (kd-tree paths)",
            "PCL 1,199 ms, Open3D 1,332 ms",
            Box::new(|| {
                let _ = extract(&unorganized, eye, &params);
            }),
        ),
        (
            "whole tabletop pipeline (outliers → planes → hull → prism → segmentation → objects)",
            "PCL 1,199 ms, Open3D 1,332 ms",
            Box::new(|| {
                let _ = extract(cloud, eye, &params);
            }),
        ),
    ];
    let rows = stages
        .iter()
        .map(|(stage, anchor, f)| {
            let (cpu, wall) = timer.time(f.as_ref());
            StageTime {
                stage: stage.to_string(),
                cpu_ms_1_thread: cpu,
                wall_ms_2_threads: wall,
                anchor,
            }
        })
        .collect();
    Ok((rows, finite_points.len()))
}

/// One scene of the quality suite (fields in the order JSON has always listed them).
#[derive(Serialize)]
pub struct SuiteRow {
    pub cpu_ms: f64,
    pub objects: usize,
    pub recovered: usize,
    pub seed: u64,
    pub stacked_pairs: usize,
    pub table_precision: f64,
    pub table_recall: f64,
    pub touching_pairs: usize,
    pub wall_ms: f64,
}

/// Scene `seed` of the suite: quality against its labels and the pipeline's times.
pub fn suite_row(seed: u64, params: &TabletopParams, timer: &Timer) -> Result<SuiteRow> {
    let layout = TabletopLayout::random(seed);
    let f = frame(seed, &layout)?;
    let s = quality(&f, params)?;
    let (cpu, wall) = timer.time(&|| {
        let _ = extract(&f.cloud, f.viewpoint, params);
    });
    Ok(SuiteRow {
        cpu_ms: cpu,
        objects: s.objects,
        recovered: s.recovered,
        seed,
        stacked_pairs: layout.stacked_pairs,
        table_precision: s.table_precision,
        table_recall: s.table_recall,
        touching_pairs: layout.touching_pairs,
        wall_ms: wall,
    })
}

/// The pipeline on one sensor file, organized or not (fields in JSON's order).
#[derive(Serialize)]
pub struct FrameRow {
    pub cpu_ms: f64,
    pub file: String,
    pub layout: &'static str,
    pub objects: usize,
    pub partial_objects: usize,
    pub points: usize,
    pub stages_ms: tabula_perception::tabletop::StageTimes,
    pub wall_ms: f64,
}

/// Framing (the support search when the file gives no pose) and the whole pipeline,
/// timed together on `file` as its grid has it and without the grid (`layout`: `both`,
/// `organized` or `unorganized`).
pub fn frame_rows(
    (name, file): (&str, &CloudFile),
    layout: &str,
    params: &TabletopParams,
    timer: &Timer,
) -> Result<Vec<FrameRow>> {
    use tabula_perception::support::{SupportParams, frame_cloud};
    use tabula_perception::tabletop::extract_framed;
    let grid_free = PointCloud::unorganized(
        file.cloud
            .points
            .iter()
            .copied()
            .filter(|q| q.is_finite())
            .collect(),
    );
    let mut rows = Vec::new();
    for (kind, cloud) in [("organized", &file.cloud), ("unorganized", &grid_free)] {
        if layout != "both" && layout != kind {
            continue;
        }
        let run = || -> Result<tabula_perception::tabletop::Tabletop> {
            let framing = frame_cloud(
                cloud,
                &file.viewpoint,
                None,
                None,
                &SupportParams::default(),
            )?;
            let world = to_world(&framing.world_from_cloud, cloud);
            Ok(extract_framed(&world, &framing, params)?)
        };
        let t = run()?;
        let (cpu, wall) = timer.time(&|| {
            let _ = run();
        });
        rows.push(FrameRow {
            cpu_ms: cpu,
            file: name.to_string(),
            layout: kind,
            objects: t.objects.len(),
            partial_objects: t.partial.len(),
            points: cloud.finite_count(),
            stages_ms: t.times,
            wall_ms: wall,
        });
    }
    Ok(rows)
}
