//! The run: look, perceive, propose grasps per arm, plan candidates until one plans
//! whole, execute it phase by phase.

use super::grasps::{Job, grasp_candidates};
use super::held::{HeldElsewhere, held_in_grippers};
use super::look::look_around;
use super::scene::{Scene, add_occupancy, perceive};
use super::sequence::{Sequence, plan_sequence};
use super::{
    GraspKind, Phase, PickPlaceError, PickPlaceParams, PickPlaceReport, PickPlaceRequest,
    motion_error,
};
use crate::skills::Hand;
use crate::skills::phase::{Clock, timed};
use tabula_geom::Pose;
use tabula_motion::group::thread_cpu;
use tabula_motion::{MoveGroup, Plan};
use tabula_robot::description::Gripper;
use tabula_robot::driver::{JointState, RobotDriver};
use tabula_robot::robots::NamedRobot;

/// Debug log of the decision's progress, with its CPU time so far.
struct Marks {
    start: f64,
    trace: bool,
}

impl Marks {
    fn mark(&self, what: &str) {
        if self.trace {
            tracing::debug!("{:>9.1} ms  {what}", (thread_cpu() - self.start) * 1e3);
        }
    }
}

/// The candidate chosen: its arm's group, its stages, its kind.
type Chosen = (MoveGroup, Sequence, GraspKind);

pub(super) fn run(
    driver: &mut impl RobotDriver,
    robot: &NamedRobot,
    request: &PickPlaceRequest,
    params: &PickPlaceParams,
    report: &mut PickPlaceReport,
) -> Result<(), PickPlaceError> {
    if !(request.pick.is_finite() && request.place.is_finite()) {
        return Err(PickPlaceError::ObjectNotFound(
            "positions must be finite".into(),
        ));
    }
    let full = full_grippers(driver, robot, request)?;
    let mut views = look_around(driver, robot, request, params, report)?;
    let marks = Marks {
        start: thread_cpu(),
        trace: tracing::enabled!(tracing::Level::DEBUG),
    };
    // What the other hands hold moves with them: it is carried in the planning scene,
    // not left in it as an obstacle.
    let (state, world_from_root) = (driver.joint_state()?, driver.world_from_root()?);
    let held = held_in_grippers(robot, &full, &state, world_from_root, &mut views, params);
    for h in &held {
        report.held_elsewhere.push(h.gripper.name.clone());
        marks.mark(&format!(
            "{} holds something ({} points seen)",
            h.gripper.name, h.points
        ));
    }
    let scene = perceive(&views, request, params, report)?;
    marks.mark("perceived");
    let state = planning_state(driver.joint_state()?, robot, &full);
    let world_from_root = driver.world_from_root()?;
    let arms = arms_nearest_first(robot, request, &full, &state, world_from_root);
    let chooser = Chooser {
        robot,
        scene: &scene,
        held: &held,
        request,
        params,
        state: &state,
        world_from_root,
        marks: &marks,
    };
    let (chosen, setup_cpu) = chooser.choose(&arms, report)?;
    let decision = thread_cpu() - marks.start - setup_cpu + views.cpu;
    report.decision_cpu_ms = decision * 1e3;
    report.phases.push(Phase {
        name: "plan".into(),
        ms: report.decision_cpu_ms,
        ok: chosen.is_ok(),
        plan_ms: None,
    });
    marks.mark("planned");
    let (group, seq, kind) = chosen?;
    report.arm = Some(group.arm.name.clone());
    report.grasp = Some(kind);
    report.planned_object_position = Some(seq.planned_object.translation.to_array());
    let gripper = group.gripper.clone().ok_or(PickPlaceError::Unreachable)?;
    for g in robot
        .description
        .grippers
        .iter()
        .filter(|g| !holds(&full, g))
    {
        driver.open(&g.name)?;
    }
    execute(driver, &gripper, &seq, report, marks.trace)
}

/// Grippers that already hold something: they stay closed, pick nothing, and what they
/// hold is carried in the planning scene (with a shared torso joint it turns too).
fn full_grippers(
    driver: &mut impl RobotDriver,
    robot: &NamedRobot,
    request: &PickPlaceRequest,
) -> Result<Vec<Gripper>, PickPlaceError> {
    let mut full = Vec::new();
    for g in &robot.description.grippers {
        if driver.grip_state(&g.name)?.holding {
            full.push(g.clone());
        }
    }
    if let Some(a) = &request.arm {
        let group = robot
            .description
            .arm(a)
            .map_err(|e| PickPlaceError::Driver(e.to_string()))?;
        if robot
            .description
            .gripper_of(group)
            .is_some_and(|g| holds(&full, g))
        {
            return Err(PickPlaceError::HandFull(a.clone()));
        }
    }
    Ok(full)
}

fn holds(full: &[Gripper], g: &Gripper) -> bool {
    full.iter().any(|f| f.name == g.name)
}

/// The state plans are made in: every empty gripper open, as it will be (it opens
/// before the first motion); a full one stays closed.
fn planning_state(mut state: JointState, robot: &NamedRobot, full: &[Gripper]) -> JointState {
    for g in robot
        .description
        .grippers
        .iter()
        .filter(|g| !holds(full, g))
    {
        if let (Some(j), Some(i)) = (
            robot.model.joint(&g.finger_joint),
            state.names.iter().position(|n| *n == g.finger_joint),
        ) {
            state.positions[i] = robot.model.joints[j].limits.upper;
        }
    }
    state
}

/// The arms to try: the request's, else every arm with an empty gripper, the one whose
/// shoulder is nearest the object first.
fn arms_nearest_first(
    robot: &NamedRobot,
    request: &PickPlaceRequest,
    full: &[Gripper],
    state: &JointState,
    world_from_root: Pose,
) -> Vec<String> {
    if let Some(a) = &request.arm {
        return vec![a.clone()];
    }
    let mut v: Vec<(f64, String)> = robot
        .description
        .arms
        .iter()
        .filter(|a| {
            robot
                .description
                .gripper_of(a)
                .is_some_and(|g| !holds(full, g))
        })
        .filter_map(|a| {
            let chain = a.chain(&robot.model).ok()?;
            let fk = robot
                .model
                .forward_kinematics(&state.model_values(&robot.model))
                .ok()?;
            let first = chain.joint_indices.get(1).or(chain.joint_indices.first())?;
            let shoulder = world_from_root * fk[robot.model.joints[*first].child].translation;
            Some(((shoulder - request.pick).length(), a.name.clone()))
        })
        .collect();
    v.sort_by(|a, b| a.0.total_cmp(&b.0));
    v.into_iter().map(|(_, n)| n).collect()
}

/// What choosing a candidate works with.
struct Chooser<'a> {
    robot: &'a NamedRobot,
    scene: &'a Scene,
    held: &'a [HeldElsewhere],
    request: &'a PickPlaceRequest,
    params: &'a PickPlaceParams,
    /// The state plans start from and where the robot stands.
    state: &'a JointState,
    world_from_root: Pose,
    marks: &'a Marks,
}

impl Chooser<'_> {
    /// Sets up the move group (the allowed-collision matrix, sampled once per robot as
    /// MoveIt keeps it in the SRDF, is setup, not decision: its CPU seconds are
    /// returned) and plans candidates arm by arm until one plans whole — or the most
    /// telling failure.
    fn choose(
        &self,
        arms: &[String],
        report: &mut PickPlaceReport,
    ) -> Result<(Result<Chosen, PickPlaceError>, f64), PickPlaceError> {
        let (robot, params, marks) = (self.robot, self.params, self.marks);
        let c0 = thread_cpu();
        let first = arms.first().ok_or(PickPlaceError::Unreachable)?;
        let mut template = MoveGroup::new(
            robot,
            first,
            self.state,
            self.world_from_root,
            params.motion.clone(),
        )
        .map_err(|e| PickPlaceError::Driver(e.to_string()))?;
        for (k, h) in self.held.iter().enumerate() {
            template
                .attach_to_gripper(
                    &h.gripper,
                    &format!("held {k}"),
                    h.shape.clone(),
                    Pose::IDENTITY,
                )
                .map_err(motion_error)?;
        }
        let setup_cpu = thread_cpu() - c0;
        marks.mark("allowed collisions sampled");
        add_occupancy(
            &mut template.world,
            &self.scene.occupancy,
            params.observe.voxel,
        )
        .map_err(|e| PickPlaceError::Driver(e.to_string()))?;
        marks.mark("move group");
        let mut last_error = PickPlaceError::Unreachable;
        for arm in arms {
            let mut group = match template.for_arm(robot, arm) {
                Ok(g) => g,
                Err(e) => {
                    last_error = PickPlaceError::Driver(e.to_string());
                    continue;
                }
            };
            let Some(gripper) = group.gripper.clone() else {
                continue;
            };
            let hand =
                Hand::new(robot, &gripper).map_err(|e| PickPlaceError::Driver(e.to_string()))?;
            let start = group.arm_values(self.state);
            let landing = Job::landing_world(&group.world)?;
            let job = Job {
                scene: self.scene,
                request: self.request,
                params,
                start: &start,
                landing: &landing,
            };
            let candidates = grasp_candidates(&group, &job, &hand)?;
            marks.mark(&format!("{} grasp candidates for {arm}", candidates.len()));
            for grasp in candidates {
                report.candidates_tried += 1;
                let mut stage = "";
                let full = group.world.clone();
                let planned = plan_sequence(&mut group, &full, &job, &grasp, &mut stage);
                group.world = full;
                match planned {
                    Ok(seq) => return Ok((Ok((group, seq, grasp.kind)), setup_cpu)),
                    Err(e) => {
                        marks.mark(&format!("candidate failed at {stage}"));
                        let a = grasp.approach;
                        report.rejected.push(format!(
                            "{arm} {:?} approach ({:.2}, {:.2}, {:.2}) at {stage}: {e}",
                            grasp.kind, a.x, a.y, a.z
                        ));
                        // Keep the most telling failure: a path problem beats "unreachable".
                        if !matches!(e, PickPlaceError::Unreachable)
                            || matches!(last_error, PickPlaceError::Unreachable)
                        {
                            last_error = e;
                        }
                    }
                }
            }
        }
        Ok((Err(last_error), setup_cpu))
    }
}

/// Executes one planned motion as phase `name` of `report`.
fn motion(
    driver: &mut impl RobotDriver,
    report: &mut PickPlaceReport,
    name: &str,
    plan: &Plan,
    trace: bool,
) -> Result<(), PickPlaceError> {
    report.trajectories.push(plan.trajectory.clone());
    if trace {
        tracing::debug!(
            "phase {name}: {:.2} s of motion",
            plan.trajectory.duration()
        );
    }
    let out = timed(&mut report.phases, "pick-place", name, Clock::Wall, || {
        Ok::<_, PickPlaceError>(driver.execute(&plan.trajectory)?)
    });
    if let Some(p) = report.phases.last_mut() {
        p.plan_ms = Some(plan.planning_time * 1e3);
    }
    out
}

/// Executes the planned stages, each a phase of `report`; stops with
/// [`PickPlaceError::GraspSlipped`] when the gripper closes on nothing.
fn execute(
    driver: &mut impl RobotDriver,
    gripper: &Gripper,
    seq: &Sequence,
    report: &mut PickPlaceReport,
    trace: bool,
) -> Result<(), PickPlaceError> {
    motion(driver, report, "move to pre-grasp", &seq.to_pregrasp, trace)?;
    motion(driver, report, "approach", &seq.approach, trace)?;
    let grip = timed(
        &mut report.phases,
        "pick-place",
        "grasp",
        Clock::Wall,
        || Ok::<_, PickPlaceError>(driver.close(&gripper.name)?),
    )?;
    if !grip.holding {
        if let Some(p) = report.phases.last_mut() {
            p.ok = false;
        }
        driver.open(&gripper.name)?;
        return Err(PickPlaceError::GraspSlipped);
    }
    motion(driver, report, "lift", &seq.lift, trace)?;
    motion(driver, report, "retreat", &seq.retreat, trace)?;
    motion(driver, report, "transfer", &seq.transfer, trace)?;
    motion(driver, report, "place", &seq.place, trace)?;
    timed(
        &mut report.phases,
        "pick-place",
        "release",
        Clock::Wall,
        || Ok::<_, PickPlaceError>(driver.open(&gripper.name)?),
    )?;
    motion(
        driver,
        report,
        "retreat from object",
        &seq.release_retreat,
        trace,
    )?;
    motion(driver, report, "return", &seq.home, trace)?;
    Ok(())
}
