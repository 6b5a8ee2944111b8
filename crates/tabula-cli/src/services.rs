//! tabula's capabilities as ROS 2 services beside the served robot, for other ROS 2
//! code: inverse kinematics of the robot's arms, stable poses of a mesh or a scan,
//! tabletop perception of a point cloud, and PDDL plans.
//!
//! `/tabula/ik`, `/tabula/stable_poses` and `/tabula/plan` are `tabula_msgs/srv/Call`
//! (a JSON request, `ok` and a JSON answer or the error); `/tabula/perceive` is
//! `tabula_msgs/srv/Perceive` (a `sensor_msgs/msg/PointCloud2` in, JSON out) so a
//! node sends its camera's cloud as it has it.

use anyhow::{Result, anyhow, bail};
use serde::Deserialize;
use serde_json::{Value, json};
use std::time::{Duration, Instant};
use tabula_geom::{CloudFile, Vec3};
use tabula_robot::description::RobotDescription;
use tabula_robot::ik::{IkMode, NumericIkParams};
use tabula_robot::model::RobotModel;
use tabula_ros::msgs::{CallRequest, CallResponse};
use tabula_ros::node::{Node, RosError, Service};
use tabula_ros::protocol::{CALL_TYPE, PERCEIVE_TYPE, PerceiveRequest, pose_from_array};

/// Answers JSON requests on `name` with `answer`, errors as `ok: false` and one line.
fn json_service(
    node: &Node,
    name: &str,
    answer: impl Fn(Value) -> Result<Value> + Send + Sync + 'static,
) -> Result<Service, RosError> {
    node.service(name, CALL_TYPE, move |r: CallRequest| {
        response(
            serde_json::from_str(&r.request)
                .map_err(|e| anyhow!("not JSON: {e}"))
                .and_then(&answer),
        )
    })
}

/// An answer as the response says it: the JSON, or the error in one line.
fn response(out: Result<Value>) -> CallResponse {
    match out {
        Ok(v) => CallResponse {
            ok: true,
            response: v.to_string(),
        },
        Err(e) => CallResponse {
            ok: false,
            response: tabula_geom::input::clip(&format!("{e:#}"), 1000),
        },
    }
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct IkRequest {
    /// An arm group of the served robot.
    arm: String,
    /// The tool's target in the arm's base link frame: x y z qx qy qz qw.
    pose: [f64; 7],
    /// Where to start (chain order; default: mid-range).
    #[serde(default)]
    seed: Option<Vec<f64>>,
    #[serde(default)]
    position_only: bool,
}

fn ik(model: &RobotModel, description: &RobotDescription, request: Value) -> Result<Value> {
    let r: IkRequest = serde_json::from_value(request)?;
    let arm = description.arm(&r.arm)?;
    let solver = arm.ik_solver(model, NumericIkParams::default())?;
    let chain = solver.chain();
    let target = pose_from_array(&r.pose).ok_or_else(|| anyhow!("the pose must be finite"))?;
    let seed = r.seed.unwrap_or_else(|| chain.mid_configuration());
    if seed.len() != chain.dof() || seed.iter().any(|v| !v.is_finite()) {
        bail!("the seed must be {} finite joint values", chain.dof());
    }
    let mode = if r.position_only {
        IkMode::PositionOnly
    } else {
        IkMode::Full
    };
    let solutions = match solver.solve(&target, mode, &seed) {
        Ok(s) => s,
        Err(e) => {
            return Ok(json!({"base": chain.base_link, "tip": chain.tip_link,
                "joint_names": chain.joint_names, "solutions": [], "error": e.to_string()}));
        }
    };
    Ok(json!({
        "base": chain.base_link,
        "tip": chain.tip_link,
        "joint_names": chain.joint_names,
        "solutions": solutions.iter().map(|s| json!({
            "joints": s.joints,
            "position_error_m": s.position_error,
            "rotation_error_rad": s.rotation_error,
        })).collect::<Vec<_>>(),
    }))
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct StableRequest {
    /// A scanned cloud in the object's frame …
    #[serde(default)]
    points: Option<Vec<[f64; 3]>>,
    /// … or a closed mesh.
    #[serde(default)]
    vertices: Option<Vec<[f64; 3]>>,
    #[serde(default)]
    triangles: Option<Vec<[u32; 3]>>,
}

/// Most points or vertices a request may carry (a scan is a few thousand).
const MAX_POINTS: usize = 1_000_000;

fn stable_poses(request: Value) -> Result<Value> {
    let r: StableRequest = serde_json::from_value(request)?;
    let params = tabula_tasks::stable::StableParams::default();
    let points = |v: &[[f64; 3]]| -> Result<Vec<Vec3>> {
        if v.len() > MAX_POINTS {
            bail!("at most {MAX_POINTS} points");
        }
        let p: Vec<Vec3> = v.iter().map(|a| Vec3::from_array(*a)).collect();
        if p.iter().any(|p| !p.is_finite()) {
            bail!("points must be finite");
        }
        Ok(p)
    };
    let t0 = tabula_robot::ik::bench::thread_cpu_seconds();
    let poses = match (&r.points, &r.vertices, &r.triangles) {
        (Some(p), None, None) => tabula_tasks::stable::of_cloud(&points(p)?, &params)?,
        (None, Some(v), Some(t)) => {
            let v = points(v)?;
            if t.iter().flatten().any(|&i| i as usize >= v.len()) {
                bail!("a triangle names a vertex that does not exist");
            }
            tabula_tasks::stable::of_mesh(&v, t, &params)?
        }
        _ => bail!("give `points`, or `vertices` and `triangles`"),
    };
    let mut v = serde_json::to_value(&poses)?;
    v["cpu_ms"] = json!((tabula_robot::ik::bench::thread_cpu_seconds() - t0) * 1e3);
    Ok(v)
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct PlanRequest {
    domain: String,
    problem: String,
    /// Greedy (GBFS, h^FF) instead of optimal (A*, LM-cut).
    #[serde(default)]
    fast: bool,
    /// Time limit (s), grounding included.
    #[serde(default = "default_plan_timeout")]
    timeout_s: f64,
}

fn default_plan_timeout() -> f64 {
    10.0
}

fn plan(request: Value) -> Result<Value> {
    use tabula_pddl::{GroundOptions, NoPlan, Planner, SearchMode, parse_domain, parse_problem};
    let r: PlanRequest = serde_json::from_value(request)?;
    if !(r.timeout_s > 0.0 && r.timeout_s <= 600.0) {
        bail!("timeout_s must be in (0, 600]");
    }
    let d = parse_domain(&r.domain)?;
    let p = parse_problem(&r.problem, &d)?;
    let deadline = Instant::now() + Duration::from_secs_f64(r.timeout_s);
    let planner = Planner::new(
        d,
        p,
        GroundOptions {
            deadline: Some(deadline),
            ..GroundOptions::default()
        },
    )?;
    let mode = if r.fast {
        SearchMode::Fast
    } else {
        SearchMode::Optimal
    };
    Ok(
        match planner.plan(
            mode,
            Some(deadline.saturating_duration_since(Instant::now())),
        ) {
            Ok(plan) => json!({"status": "solved", "optimal": plan.optimal, "cost": plan.cost,
            "plan": plan.steps.iter().map(ToString::to_string).collect::<Vec<_>>()}),
            Err(NoPlan::Unsolvable) => json!({"status": "unsolvable"}),
            Err(NoPlan::Timeout) => json!({"status": "timeout"}),
            Err(e) => return Err(e.into()),
        },
    )
}

fn perceive(r: PerceiveRequest) -> Result<Value> {
    let cloud = r.cloud.to_cloud()?;
    let pose = if r.has_pose {
        Some(
            r.world_from_cloud
                .to_pose()
                .ok_or_else(|| anyhow!("world_from_cloud must be finite"))?,
        )
    } else {
        None
    };
    let file = CloudFile::plain(cloud);
    let params = tabula_perception::TabletopParams::default();
    let perceived = tabula_perception::frame::perceive(&file, pose, None, &[], &params)?;
    Ok(perceived.to_json(None, None))
}

/// Declares the services on `node` for the served robot; keep them as long as it
/// serves.
pub fn declare(
    node: &Node,
    model: RobotModel,
    description: RobotDescription,
) -> Result<Vec<Service>, RosError> {
    let perceive_service =
        node.service("/tabula/perceive", PERCEIVE_TYPE, |r: PerceiveRequest| {
            response(perceive(r))
        })?;
    Ok(vec![
        json_service(node, "/tabula/ik", move |v| ik(&model, &description, v))?,
        json_service(node, "/tabula/stable_poses", stable_poses)?,
        json_service(node, "/tabula/plan", plan)?,
        perceive_service,
    ])
}
