//! A move group (MoveIt's `MoveGroupInterface` over a planning scene): one arm of a
//! described robot, its own IK solver, a collision world of the whole robot at its
//! current joint state plus the world's objects and what the gripper holds; plans to a
//! joint goal, to a pose goal and along Cartesian lines, each answer a timed trajectory
//! with its start, its planning time and a typed failure reason.

use crate::goals::follow_line;
use crate::rrt::{
    PlanError, PlannerParams, Trajectory, TrajectoryTooLong, fitted_world, rrt_connect,
    segment_certified, shortcut, time_parameterize, time_parameterize_along,
};
use crate::world::{CollisionWorld, WorldError, WorldParams};
use rand::SeedableRng;
use rand_chacha::ChaCha8Rng;
use tabula_geom::input::{Validate, check_count, check_in, check_non_negative, nested};
use tabula_geom::parry::shape::SharedShape;
use tabula_geom::{Pose, Vec3};
use tabula_robot::description::{ArmGroup, Gripper};
use tabula_robot::driver::{JointState, JointTrajectory};
use tabula_robot::ik::{IkMode, IkSolver, NumericIkParams};
use tabula_robot::robots::NamedRobot;

/// Parameters of a move group.
#[derive(Debug, Clone, serde::Deserialize, serde::Serialize)]
#[serde(default, deny_unknown_fields)]
pub struct MoveGroupParams {
    pub planner: PlannerParams,
    pub world: WorldParams,
    /// Joint acceleration limit (rad/s², m/s²); URDF gives none.
    pub max_acceleration: f64,
    /// Fraction of each joint's URDF velocity limit used.
    pub velocity_scaling: f64,
    /// Trajectory sample spacing (s).
    pub sample_dt: f64,
    /// Cartesian paths: IK every `cartesian_step` m …
    pub cartesian_step: f64,
    /// … and no joint may jump more than this between two (rad): a branch flip.
    pub cartesian_max_jump: f64,
    /// IK solutions tried per pose goal.
    pub pose_goal_solutions: usize,
    /// When no straight line exists (an arm with fewer joints than a line needs), a
    /// joint-space segment is accepted if the tip stays within this distance (m) of
    /// the line and `cartesian_angle_tolerance` (rad) of its orientation throughout;
    /// 0 demands the line itself.
    pub cartesian_tolerance: f64,
    pub cartesian_angle_tolerance: f64,
}

impl Default for MoveGroupParams {
    fn default() -> Self {
        Self {
            planner: PlannerParams::default(),
            world: WorldParams::default(),
            max_acceleration: 2.0,
            velocity_scaling: 1.0,
            sample_dt: 0.05,
            cartesian_step: 0.01,
            cartesian_max_jump: 0.3,
            pose_goal_solutions: 8,
            cartesian_tolerance: 0.0,
            cartesian_angle_tolerance: 0.05,
        }
    }
}

/// Why a move group gave no plan.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum MoveError {
    /// The pose has no IK solution within the joint limits.
    #[error("unreachable: no IK solution for the pose")]
    Unreachable,
    /// IK solutions exist but every one collides.
    #[error("every IK solution for the pose collides ({0})")]
    GoalInCollision(String),
    /// A joint goal that is not a valid configuration (outside the limits, colliding).
    #[error("the joint goal is invalid: {0}")]
    JointGoalInvalid(String),
    /// The start state is not a valid configuration.
    #[error("the start is invalid: {0}")]
    StartInvalid(String),
    #[error("no collision-free path: {0}")]
    NoPath(String),
    /// A Cartesian line could be followed only part of the way.
    #[error("Cartesian path stops at {fraction:.0}% of the line: {why}", fraction = .fraction * 100.0)]
    CartesianIncomplete { fraction: f64, why: String },
    #[error("{0}")]
    World(String),
}

impl From<WorldError> for MoveError {
    fn from(e: WorldError) -> Self {
        MoveError::World(e.to_string())
    }
}

/// A planned motion: where it starts, the timed trajectory, the path it times, and how
/// long planning took (CPU seconds of this thread).
#[derive(Debug, Clone)]
pub struct Plan {
    pub start: Vec<f64>,
    pub path: Vec<Vec<f64>>,
    pub trajectory: JointTrajectory,
    /// Joint velocities at each of the trajectory's samples.
    pub velocities: Vec<Vec<f64>>,
    pub planning_time: f64,
}

impl Plan {
    /// The configuration the plan ends at.
    pub fn end(&self) -> &[f64] {
        self.path.last().map(Vec::as_slice).unwrap_or(&self.start)
    }
}

/// One arm of a robot over a planning scene.
pub struct MoveGroup {
    pub arm: ArmGroup,
    pub gripper: Option<Gripper>,
    ik: Box<dyn IkSolver + Send + Sync>,
    /// The robot (every joint at the current state) and the world's objects.
    pub world: CollisionWorld,
    pub params: MoveGroupParams,
    vmax: Vec<f64>,
}

impl MoveGroup {
    /// A move group for `arm` at `driver`'s state, with `obstacles` (name, shape, world
    /// pose) as its planning scene.
    pub fn at_driver(
        driver: &impl tabula_robot::driver::RobotDriver,
        (robot, arm): (&NamedRobot, &str),
        obstacles: &[(String, SharedShape, Pose)],
        params: &MoveGroupParams,
    ) -> Result<Self, MoveError> {
        let driver_error = |e: tabula_robot::driver::DriverError| MoveError::World(e.to_string());
        let state = driver.joint_state().map_err(driver_error)?;
        let root = driver.world_from_root().map_err(driver_error)?;
        let mut group = Self::new(robot, arm, &state, root, params.clone())?;
        for (k, (name, shape, pose)) in obstacles.iter().enumerate() {
            group.add_object(&format!("{name}#{k}"), shape.clone(), *pose)?;
        }
        Ok(group)
    }

    /// The group `arm` of `robot`, at the joint state `state` with its root at
    /// `world_from_root`. The allowed-collision matrix is sampled here; build one group
    /// per robot and use [`Self::for_arm`] / [`Self::set_state`] for the rest.
    pub fn new(
        robot: &NamedRobot,
        arm: &str,
        state: &JointState,
        world_from_root: Pose,
        params: MoveGroupParams,
    ) -> Result<Self, MoveError> {
        let (group, chain) = arm_and_chain(robot, arm)?;
        let mut world_params = params.world.clone();
        if world_params.srdf.is_none() {
            world_params.srdf = robot.srdf.clone();
        }
        let world = CollisionWorld::new(
            robot.model.clone(),
            chain,
            world_from_root,
            Some(state.model_values(&robot.model)),
            world_params,
        )?;
        Self::assemble(robot, group, world, params)
    }

    fn assemble(
        robot: &NamedRobot,
        arm: ArmGroup,
        world: CollisionWorld,
        params: MoveGroupParams,
    ) -> Result<Self, MoveError> {
        let ik = arm
            .ik_solver(
                &robot.model,
                NumericIkParams {
                    timeout_s: None,
                    max_attempts: 300,
                    max_solutions: params.pose_goal_solutions.max(1),
                    random_seed: params.planner.seed,
                    ..NumericIkParams::default()
                },
            )
            .map_err(|e| MoveError::World(e.to_string()))?;
        let vmax = world
            .chain
            .joint_indices
            .iter()
            .map(|&j| {
                let v = robot.model.joints[j].limits.velocity;
                let v = if v.is_finite() && v > 0.0 { v } else { 1.0 };
                v * params.velocity_scaling.clamp(1e-3, 1.0)
            })
            .collect();
        Ok(Self {
            gripper: robot.description.gripper_of(&arm).cloned(),
            arm,
            ik,
            world,
            params,
            vmax,
        })
    }

    /// The same scene (objects, allowed collisions) for another arm of the robot.
    pub fn for_arm(&self, robot: &NamedRobot, arm: &str) -> Result<Self, MoveError> {
        let (group, chain) = arm_and_chain(robot, arm)?;
        let world = self.world.rebased(
            chain,
            self.world.values().to_vec(),
            self.world.world_from_root(),
        )?;
        Self::assemble(robot, group, world, self.params.clone())
    }

    /// Takes a new joint state (joints outside the arm move the rest of the robot).
    pub fn set_state(&mut self, robot: &NamedRobot, state: &JointState) -> Result<(), MoveError> {
        self.world = self.world.rebased(
            self.world.chain.clone(),
            state.model_values(&robot.model),
            self.world.world_from_root(),
        )?;
        Ok(())
    }

    /// The arm's joint names, in the order of every configuration here.
    pub fn joint_names(&self) -> &[String] {
        &self.world.chain.joint_names
    }

    /// The arm's joints in `state` (missing ones at mid-range).
    pub fn arm_values(&self, state: &JointState) -> Vec<f64> {
        let mid = self.world.chain.mid_configuration();
        self.joint_names()
            .iter()
            .zip(mid)
            .map(|(n, m)| state.get(n).unwrap_or(m))
            .collect()
    }

    /// `world_from_tip` at arm configuration `q`.
    pub fn tip_pose(&self, q: &[f64]) -> Result<Pose, MoveError> {
        Ok(self.world.tip_pose(q)?)
    }

    /// Every IK solution of `world_from_tip`, nearest `seed` first, with whether it is
    /// collision-free. `Err(Unreachable)` when there is none.
    pub fn ik(&self, world_from_tip: &Pose, seed: &[f64]) -> Result<Vec<Vec<f64>>, MoveError> {
        let base = self.world.world_from_chain_base()?;
        let target = base.inverse() * *world_from_tip;
        let sols = self
            .ik
            .solve(&target, IkMode::Full, seed)
            .map_err(|_| MoveError::Unreachable)?;
        Ok(sols.into_iter().map(|s| s.joints).collect())
    }

    /// Collision-free IK solutions of a pose, nearest `seed` first.
    pub fn valid_ik(
        &self,
        world_from_tip: &Pose,
        seed: &[f64],
    ) -> Result<Vec<Vec<f64>>, MoveError> {
        let all = self.ik(world_from_tip, seed)?;
        let mut why = String::new();
        let valid: Vec<Vec<f64>> = all
            .into_iter()
            .filter(|q| match self.world.first_collision(q) {
                Ok(None) => true,
                Ok(Some((a, b))) => {
                    why = format!("{a} touches {b}");
                    false
                }
                Err(e) => {
                    why = e.to_string();
                    false
                }
            })
            .collect();
        if valid.is_empty() {
            return Err(MoveError::GoalInCollision(why));
        }
        Ok(valid)
    }

    /// A collision-free path from `start` to any of `goals`, shortcut and timed.
    pub fn plan_to_joints(&self, start: &[f64], goals: &[Vec<f64>]) -> Result<Plan, MoveError> {
        let t0 = thread_cpu();
        let world = fitted_world(&self.world, start, goals, &self.params.planner);
        let mut path =
            rrt_connect(&world, start, goals, &self.params.planner).map_err(|e| match e {
                PlanError::GoalInvalid(why) => MoveError::JointGoalInvalid(why),
                PlanError::StartInvalid(why) => MoveError::StartInvalid(why),
                other => MoveError::NoPath(other.to_string()),
            })?;
        let mut rng = ChaCha8Rng::seed_from_u64(self.params.planner.seed);
        shortcut(&world, &mut path, &self.params.planner, &mut rng);
        self.timed(start, path.waypoints, thread_cpu() - t0)
    }

    /// A collision-free path from `start` to a pose of the tip.
    pub fn plan_to_pose(&self, start: &[f64], world_from_tip: &Pose) -> Result<Plan, MoveError> {
        let t0 = thread_cpu();
        let goals = self.valid_ik(world_from_tip, start)?;
        let mut plan = self.plan_to_joints(start, &goals).map_err(|e| match e {
            MoveError::JointGoalInvalid(why) => MoveError::GoalInCollision(why),
            other => other,
        })?;
        plan.planning_time = thread_cpu() - t0;
        Ok(plan)
    }

    /// The tip along a straight line from its pose at `start` to `world_from_goal`
    /// (translation linear, rotation slerped), IK every `cartesian_step` m seeded by the
    /// previous solution, every segment collision-checked. Anything short of the whole
    /// line is [`MoveError::CartesianIncomplete`].
    pub fn cartesian(&self, start: &[f64], world_from_goal: &Pose) -> Result<Plan, MoveError> {
        let t0 = thread_cpu();
        match self.straight_line(start, world_from_goal) {
            Ok(path) => self.timed(start, path, thread_cpu() - t0),
            Err(e) if self.params.cartesian_tolerance > 0.0 => {
                match self.near_line(start, world_from_goal) {
                    Some(path) => self.timed(start, path, thread_cpu() - t0),
                    None => Err(e),
                }
            }
            Err(e) => Err(e),
        }
    }

    /// The straight line of [`Self::cartesian`] (no tolerance), timed as one motion
    /// rather than resting at every 1 cm waypoint: a hand carrying something level
    /// across a metre in seconds, not tens of seconds.
    pub fn cartesian_continuous(
        &self,
        start: &[f64],
        world_from_goal: &Pose,
    ) -> Result<Plan, MoveError> {
        let t0 = thread_cpu();
        let path = self.straight_line(start, world_from_goal)?;
        let amax = vec![self.params.max_acceleration; self.vmax.len()];
        let t = time_parameterize_along(&path, &self.vmax, &amax, self.params.sample_dt)
            .map_err(|e| self.too_long(e))?;
        Ok(self.plan_of(start, path, t, thread_cpu() - t0))
    }

    /// A joint-space segment from `start` to an IK solution of the goal along which the
    /// tip stays within the Cartesian tolerances of the straight line.
    fn near_line(&self, start: &[f64], world_from_goal: &Pose) -> Option<Vec<Vec<f64>>> {
        let from = self.tip_pose(start).ok()?;
        let goals = self.valid_ik(world_from_goal, start).ok()?;
        let line = world_from_goal.translation - from.translation;
        let length = line.length();
        'goal: for goal in goals.into_iter().take(4) {
            let n =
                ((length / self.params.cartesian_step.max(1e-4)).ceil() as usize).clamp(4, 1000);
            for i in 1..n {
                let s = i as f64 / n as f64;
                let q: Vec<f64> = start
                    .iter()
                    .zip(&goal)
                    .map(|(a, b)| a + (b - a) * s)
                    .collect();
                let tip = self.tip_pose(&q).ok()?;
                // Distance from the segment, and from the slerped orientation.
                let t = if length > 1e-9 {
                    ((tip.translation - from.translation).dot(line) / (length * length))
                        .clamp(0.0, 1.0)
                } else {
                    0.0
                };
                let nearest = from.translation + line * t;
                let want = from.rotation.slerp(world_from_goal.rotation, s);
                if (tip.translation - nearest).length() > self.params.cartesian_tolerance
                    || tabula_geom::rotation_angle_between(tip.rotation, want)
                        > self.params.cartesian_angle_tolerance
                {
                    continue 'goal;
                }
            }
            if segment_certified(&self.world, start, &goal, self.params.planner.resolution) {
                return Some(vec![start.to_vec(), goal]);
            }
        }
        None
    }

    /// The straight line itself, IK step by step (the arm's own solver).
    fn straight_line(
        &self,
        start: &[f64],
        world_from_goal: &Pose,
    ) -> Result<Vec<Vec<f64>>, MoveError> {
        if let Some((a, b)) = self.world.first_collision(start)? {
            return Err(MoveError::CartesianIncomplete {
                fraction: 0.0,
                why: format!("the start collides: {a} touches {b}"),
            });
        }
        let (waypoints, stop) = follow_line(
            &self.world,
            start,
            world_from_goal,
            self.params.cartesian_step,
            self.params.cartesian_max_jump,
            self.params.planner.resolution,
            |pose, seed| self.ik(pose, seed).ok()?.into_iter().next(),
        );
        match stop {
            None => Ok(waypoints),
            Some(s) => Err(MoveError::CartesianIncomplete {
                fraction: s.fraction,
                why: s.why,
            }),
        }
    }

    /// Times a path under the arm's velocity and acceleration limits.
    pub fn timed(
        &self,
        start: &[f64],
        path: Vec<Vec<f64>>,
        planning_time: f64,
    ) -> Result<Plan, MoveError> {
        let amax = vec![self.params.max_acceleration; self.vmax.len()];
        let t = time_parameterize(&path, &self.vmax, &amax, self.params.sample_dt)
            .map_err(|e| self.too_long(e))?;
        Ok(self.plan_of(start, path, t, planning_time))
    }

    /// A timing's refusal with the joint named.
    fn too_long(&self, e: TrajectoryTooLong) -> MoveError {
        let joint = self.joint_names().get(e.joint).cloned().unwrap_or_default();
        MoveError::World(e.to_string().replace(
            &format!("joint {}'s", e.joint),
            &format!("joint `{joint}`'s"),
        ))
    }

    /// The plan of a timed path.
    fn plan_of(
        &self,
        start: &[f64],
        path: Vec<Vec<f64>>,
        t: Trajectory,
        planning_time: f64,
    ) -> Plan {
        Plan {
            start: start.to_vec(),
            trajectory: JointTrajectory {
                joint_names: self.joint_names().to_vec(),
                times: t.times,
                positions: t.positions,
            },
            velocities: t.velocities,
            path,
            planning_time,
        }
    }

    /// Adds a world object.
    pub fn add_object(
        &mut self,
        name: &str,
        shape: SharedShape,
        world_from_object: Pose,
    ) -> Result<(), MoveError> {
        Ok(self.world.add_object(name, shape, world_from_object)?)
    }

    pub fn remove_object(&mut self, name: &str) -> Result<(), MoveError> {
        Ok(self.world.remove_object(name)?)
    }

    /// Attaches an object to the gripper's tool frame (it may touch the palm and
    /// fingers), as MoveIt attaches a grasped object.
    pub fn attach(
        &mut self,
        name: &str,
        shape: SharedShape,
        tool_from_object: Pose,
    ) -> Result<(), MoveError> {
        let g = self
            .gripper
            .clone()
            .ok_or_else(|| MoveError::World(format!("arm `{}` has no gripper", self.arm.name)))?;
        self.attach_to_gripper(&g, name, shape, tool_from_object)
    }

    /// Attaches an object to any gripper of the robot. Held in another arm's hand it
    /// still moves with this group where the arms share joints (Golem-III's torso
    /// rotation θ1 turns both arms), so this group's plans keep it clear of the world.
    pub fn attach_to_gripper(
        &mut self,
        g: &Gripper,
        name: &str,
        shape: SharedShape,
        tool_from_object: Pose,
    ) -> Result<(), MoveError> {
        let touch = [
            g.palm.as_str(),
            g.fingers[0].as_str(),
            g.fingers[1].as_str(),
        ];
        Ok(self
            .world
            .attach(name, shape, &g.tool_link, tool_from_object, &touch)?)
    }

    /// The approach direction of the gripper in the world at `q`.
    pub fn approach_in_world(&self, q: &[f64]) -> Result<Vec3, MoveError> {
        let a = self.gripper.as_ref().map_or(Vec3::X, Gripper::approach);
        Ok(self.tip_pose(q)?.rotation * a)
    }
}

/// The arm group called `arm` and its chain.
fn arm_and_chain(
    robot: &NamedRobot,
    arm: &str,
) -> Result<(ArmGroup, tabula_robot::Chain), MoveError> {
    let world_error = |e: tabula_robot::RobotError| MoveError::World(e.to_string());
    let group = robot.description.arm(arm).map_err(world_error)?.clone();
    let chain = group.chain(&robot.model).map_err(world_error)?;
    Ok((group, chain))
}

/// CPU time of the calling thread (s): planning is measured in CPU time, as the
/// benchmarks compare it.
pub fn thread_cpu() -> f64 {
    tabula_robot::ik::bench::thread_cpu_seconds()
}

impl Validate for MoveGroupParams {
    fn check(&self, at: &str) -> Result<(), String> {
        self.planner.check(&nested(at, "planner"))?;
        self.world.check(&nested(at, "world"))?;
        // Below 1e-3 rad/s² a move of a radian takes minutes; above 1e4 no arm follows.
        check_in(at, "max_acceleration", self.max_acceleration, 1e-3, 1e4)?;
        check_in(at, "velocity_scaling", self.velocity_scaling, 1e-3, 1.0)?;
        check_in(at, "sample_dt", self.sample_dt, 1e-4, 1.0)?;
        // A tenth of a millimetre to a metre: finer steps are millions of IK calls.
        check_in(at, "cartesian_step", self.cartesian_step, 1e-4, 1.0)?;
        check_in(
            at,
            "cartesian_max_jump",
            self.cartesian_max_jump,
            1e-3,
            std::f64::consts::TAU,
        )?;
        check_count(at, "pose_goal_solutions", self.pose_goal_solutions, 1)?;
        // 0 is the default: the straight line itself, no tolerance.
        check_non_negative(at, "cartesian_tolerance", self.cartesian_tolerance)?;
        check_in(
            at,
            "cartesian_angle_tolerance",
            self.cartesian_angle_tolerance,
            1e-6,
            std::f64::consts::PI,
        )
    }
}
