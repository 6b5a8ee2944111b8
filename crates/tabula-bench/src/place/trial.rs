//! The placing suites' trials: a generated task placed in the simulator and judged,
//! with the ground truth of what the scan and the surface search should have found.

use super::place_in;
use super::truth::{held, resting_faces};
use crate::spec::TrialSpec;
use anyhow::Result;
use serde::Serialize;
use tabula_sim::SimWorld;
use tabula_tasks::place::{PlaceParams, PlaceRequest};

#[derive(Serialize, serde::Deserialize)]
pub struct BenchRow {
    pub seed: u64,
    pub object: String,
    pub layout: tabula_sim::generate::PlaceLayout,
    pub clutter: usize,
    pub arm: String,
    pub success: bool,
    pub cause: Option<String>,
    pub orientation_error_deg: f64,
    pub moved_after_release_mm: f64,
    pub decision_ms: f64,
    pub wall_s: f64,
    /// The surface the task chose is the generated table's top (centroid over it,
    /// height within 2 cm): the sweep found it.
    #[serde(default)]
    pub table_found: bool,
    /// Ground truth for meshes: whether the true object, held as the task holds it,
    /// has a resting pose the hand leaves free (see [`resting_faces`]).
    #[serde(default)]
    pub grip_allows_rest: Option<bool>,
    /// Ground truth for meshes: the angle (°) from the chosen pose's support normal to
    /// the nearest stable pose of the true object, both in the tool frame — how well the
    /// scan found the face it set the object down on.
    #[serde(default)]
    pub normal_error_deg: Option<f64>,
    /// Where the object came to rest and on what, for a check by another physics
    /// engine (`scripts/mujoco_rest.py`).
    #[serde(default)]
    pub rest: Option<RestRecord>,
}

/// The held object's end state and the table it was to rest on (world frame).
#[derive(Serialize, serde::Deserialize)]
pub struct RestRecord {
    /// The object's shape as its scene gives it (a mesh path relative to the meshes'
    /// folder: `--save-failures DIR` keeps them in `DIR/meshes`).
    pub shape: tabula_sim::scene::ShapeSpec,
    /// x y z qx qy qz qw after the release and settling.
    pub final_pose: [f64; 7],
    pub table_center: [f64; 2],
    pub table_size: [f64; 3],
    pub table_yaw: f64,
}

/// The suite's generated task `seed`.
pub fn task_of(
    seed: u64,
    suite: Suite,
    mesh_dir: &std::path::Path,
) -> std::io::Result<tabula_sim::generate::PlaceTask> {
    use tabula_sim::generate::{place_task, room_task};
    match suite {
        Suite::Rooms => room_task(seed, mesh_dir),
        Suite::Simple => place_task(seed, true, mesh_dir),
        Suite::Complex => place_task(seed, false, mesh_dir),
        Suite::SimpleGrips => holdable_task(seed, true, mesh_dir),
        Suite::ComplexGrips => holdable_task(seed, false, mesh_dir),
    }
}

/// How many grips of one task are drawn before its last is taken as it is.
const GRIP_DRAWS: u64 = 64;

/// Task `seed` held at a grip a parallel gripper can really hold (issue 32's rule, see
/// [`GripRule::Anywhere`]) that also leaves the true object a stable pose with the hand
/// clear of the table (judged with the default parameters, so the suite does not
/// change with `--params`): grips are drawn until one does.
///
/// [`GripRule::Anywhere`]: tabula_sim::generate::GripRule::Anywhere
fn holdable_task(
    seed: u64,
    simple: bool,
    mesh_dir: &std::path::Path,
) -> std::io::Result<tabula_sim::generate::PlaceTask> {
    use tabula_sim::generate::{GripRule, place_task_gripped};
    let rule = PlaceParams::default();
    let mut draw = 0;
    loop {
        let task = place_task_gripped(seed, simple, (GripRule::Anywhere, draw), mesh_dir)?;
        let free = tabula_sim::Scene::parse(&task.scene, "generated")
            .ok()
            .and_then(|scene| resting_faces(&scene, &rule))
            .is_some_and(|faces| faces.iter().any(|(_, clear)| *clear));
        draw += 1;
        if free || draw == GRIP_DRAWS {
            return Ok(task);
        }
    }
}

/// Whether a found surface is the task's table top.
fn is_table(
    task: &tabula_sim::generate::PlaceTask,
    surface: &tabula_tasks::place::SurfaceReport,
) -> bool {
    let [cx, cy] = task.table_center;
    let (dx, dy) = (surface.centroid[0] - cx, surface.centroid[1] - cy);
    let (s, c) = task.table_yaw.sin_cos();
    let (u, v) = (c * dx + s * dy, -s * dx + c * dy);
    u.abs() <= task.table_size[0] / 2.0
        && v.abs() <= task.table_size[1] / 2.0
        && (surface.height - task.table_size[2]).abs() <= 0.02
}

/// One task of the placing suite (`simple` or complex objects), placed in the
/// simulator and judged by physics; complex objects' meshes go to `mesh_dir`.
pub fn trial(
    s: u64,
    suite: Suite,
    params: &PlaceParams,
    mesh_dir: &std::path::Path,
) -> Result<BenchRow> {
    let task = task_of(s, suite, mesh_dir)?;
    let scene = tabula_sim::Scene::parse(&task.scene, "generated")
        .map_err(|e| anyhow::anyhow!("task {s}: {e}"))?;
    let world = SimWorld::from_scene(&scene, Default::default())
        .map_err(|e| anyhow::anyhow!("task {s}: {e}"))?;
    let faces = resting_faces(&scene, params);
    let held_shape = held(&scene).map(|(_, _, o)| o.shape.clone());
    let grip_allows_rest = faces.as_ref().map(|f| f.iter().any(|(_, clear)| *clear));
    let t0 = std::time::Instant::now();
    let request = PlaceRequest {
        arm: Some(task.arm.clone()),
        not_on: Vec::new(),
        near: None,
    };
    let (out, _) = place_in(world, None, (&request, params), s, |_| {})?;
    let cause = if out.success {
        None
    } else if let Some(e) = &out.error {
        Some(e.kind.clone())
    } else {
        let v = &out.verdict;
        Some(
            if v.surface.is_none() {
                "fell off"
            } else if !v.inside_edges {
                "over the edge"
            } else if v.orientation_error_deg > 5.0 {
                "toppled or turned"
            } else if v.moved_after_release_m >= 0.01 {
                "slid after release"
            } else if !v.disturbed.is_empty() {
                "disturbed others"
            } else if !v.furniture_contacts.is_empty() {
                "hit furniture"
            } else {
                "not released"
            }
            .to_string(),
        )
    };
    let table_found = out
        .report
        .surface
        .as_ref()
        .is_some_and(|f| is_table(&task, f));
    Ok(BenchRow {
        seed: s,
        table_found,
        grip_allows_rest,
        normal_error_deg: faces
            .zip(out.report.stable_pose.as_ref())
            .and_then(|(f, chosen)| {
                f.iter()
                    .map(|(n, _)| n.angle_between(chosen.normal()).to_degrees())
                    .min_by(f64::total_cmp)
            }),
        object: task.object,
        layout: task.layout,
        clutter: task.clutter,
        arm: task.arm,
        success: out.success,
        cause,
        orientation_error_deg: out.orientation_error_deg,
        moved_after_release_mm: out.verdict.moved_after_release_m * 1e3,
        decision_ms: out.decision_ms,
        wall_s: t0.elapsed().as_secs_f64(),
        rest: held_shape.map(|shape| RestRecord {
            shape,
            final_pose: out.verdict.final_pose,
            table_center: task.table_center,
            table_size: task.table_size,
            table_yaw: task.table_yaw,
        }),
    })
}

/// The placing suites.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Suite {
    Simple,
    Complex,
    /// Simple objects in rooms with walls and things that are not surfaces.
    Rooms,
    /// Simple and complex objects held anywhere a parallel gripper can hold them.
    SimpleGrips,
    ComplexGrips,
}

pub fn suite_of(suite: &str) -> Result<Suite> {
    match suite {
        "simple" => Ok(Suite::Simple),
        "complex" => Ok(Suite::Complex),
        "rooms" => Ok(Suite::Rooms),
        "simple-grips" => Ok(Suite::SimpleGrips),
        "complex-grips" => Ok(Suite::ComplexGrips),
        other => anyhow::bail!(
            "--suite is `simple`, `complex`, `rooms`, `simple-grips` or `complex-grips`, not `{other}`"
        ),
    }
}

/// A placing trial as a worker runs it (meshes in the worker's own temporary folder).
pub fn trial_of(spec: &TrialSpec) -> Result<BenchRow> {
    let params: PlaceParams = match &spec.params {
        Some(text) => tabula_geom::input::parse_params(text, "the bench's parameters")?,
        None => PlaceParams::default(),
    };
    trial(
        spec.seed,
        suite_of(&spec.suite)?,
        &params,
        &worker_mesh_dir(),
    )
}

/// Where a worker process writes the complex objects' meshes.
pub fn worker_mesh_dir() -> std::path::PathBuf {
    std::env::temp_dir().join(format!("tabula-worker-meshes-{}", std::process::id()))
}
