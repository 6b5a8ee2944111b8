//! Executing the chosen action through the driver: a grasp that drops the object into
//! the bin, or a push with the closed gripper — each planned collision-free against the
//! other objects' hulls, phase by phase, and back home out of the camera's view.

use super::push::Push;
use super::{ClearParams, SeenObject, Table, hull_vertices, hulls_touch};
use crate::skills::motion::{current_arm, go_home, run_phase};
use crate::skills::{GraspCandidate, Hand, SkillError};
use tabula_geom::parry::shape::SharedShape;
use tabula_geom::{Pose, Quat, Vec3};
use tabula_motion::MoveGroup;
use tabula_robot::description::Gripper;
use tabula_robot::driver::RobotDriver;
use tabula_robot::robots::NamedRobot;

/// The `k`-th spot of a 3 × 3 grid over the drop square (centre first, then around).
pub(super) fn drop_offset(k: usize, spread: f64) -> Vec3 {
    const SPOTS: [(f64, f64); 9] = [
        (0.0, 0.0),
        (1.0, 1.0),
        (-1.0, -1.0),
        (1.0, -1.0),
        (-1.0, 1.0),
        (0.0, 1.0),
        (1.0, 0.0),
        (0.0, -1.0),
        (-1.0, 0.0),
    ];
    let (x, y) = SPOTS[k % SPOTS.len()];
    Vec3::new(x * spread, y * spread, 0.0)
}

fn object_name(o: &SeenObject) -> String {
    format!("obj:{}", o.id)
}

/// What executing an action works with.
pub(super) struct Executor<'a, D> {
    pub(super) driver: &'a mut D,
    pub(super) robot: &'a NamedRobot,
    pub(super) group: &'a mut MoveGroup,
    pub(super) hand: &'a Hand,
    pub(super) gripper: &'a Gripper,
    pub(super) table: &'a Table,
    /// The arm's joint values out of the camera's view.
    pub(super) home: &'a [f64],
    pub(super) params: &'a ClearParams,
}

/// A grasp to execute: of object `i` of `objects`, at the yaw whose pre-grasp the
/// decision solved (`ik`), dropped with its bottom over `drop_at`; `nudged` are the
/// neighbours its fingers push aside.
pub(super) struct GraspAction<'a> {
    pub(super) objects: &'a [SeenObject],
    pub(super) i: usize,
    pub(super) grasp: &'a GraspCandidate,
    pub(super) ik: Vec<f64>,
    pub(super) nudged: &'a [usize],
    pub(super) drop_at: Vec3,
}

impl<D: RobotDriver> Executor<'_, D> {
    fn add(&mut self, o: &SeenObject) -> Result<(), SkillError> {
        Ok(self
            .group
            .add_object(&object_name(o), o.hull.clone(), Pose::IDENTITY)?)
    }

    /// The group set to the robot's state now; the arm's values.
    fn sync(&mut self) -> Result<Vec<f64>, SkillError> {
        let state = self.driver.joint_state()?;
        self.group.set_state(self.robot, &state)?;
        Ok(self.group.arm_values(&state))
    }

    /// Plans from `q` to the decision's IK solution (else to `pre`, a pose) and goes
    /// there.
    fn approach_start(
        &mut self,
        q: &[f64],
        ik: Vec<f64>,
        pre: &Pose,
        phase: &str,
    ) -> Result<(), SkillError> {
        let plan = self
            .group
            .plan_to_joints(q, &[ik])
            .or_else(|_| self.group.plan_to_pose(q, pre))?;
        run_phase(self.driver, &plan, phase)
    }

    /// A straight line of the tool to `to` from where the arm is.
    fn line_to(&mut self, to: &Pose, phase: &str) -> Result<(), SkillError> {
        let q = current_arm(self.driver, self.group)?;
        let plan = self.group.cartesian(&q, to)?;
        run_phase(self.driver, &plan, phase)
    }

    /// The grasp pose at the yaw closest to the decision's IK solution.
    fn solved_yaw(&self, grasp: &GraspCandidate, ik: &[f64]) -> Pose {
        let off = |y: usize| {
            self.group
                .tip_pose(ik)
                .map(|p| p.rotation.angle_between(grasp.poses[y].rotation))
                .unwrap_or(f64::INFINITY)
        };
        let yaw = (0..2)
            .min_by(|&a, &b| off(a).total_cmp(&off(b)))
            .unwrap_or(0);
        grasp.poses[yaw]
    }

    /// Grasps, lifts, carries over the bin and lets go, then goes home.
    pub(super) fn grasp(&mut self, a: GraspAction<'_>) -> Result<(), SkillError> {
        let o = &a.objects[a.i];
        let name = object_name(o);
        self.driver.open_to(&self.gripper.name, a.grasp.width)?;
        let q = self.sync()?;
        let g = self.solved_yaw(a.grasp, &a.ik);
        let up = self.table.up;
        let pre = Pose::from_parts(g.translation + up * self.params.pregrasp, g.rotation);
        self.approach_start(&q, a.ik.clone(), &pre, "to pre-grasp")?;
        self.group.remove_object(&name)?;
        // A nudge grasp's fingers push these aside on the way down: out of the world
        // until the object is lifted.
        for &n in a.nudged {
            self.group.remove_object(&object_name(&a.objects[n]))?;
        }
        self.line_to(&g, "descend")?;
        let held = self.driver.close(&self.gripper.name)?;
        if !held.holding {
            self.line_to(&pre, "back up")?;
            self.add(o)?;
            return Err(SkillError::Slipped);
        }
        self.attach_held(o)?;
        self.lift(&a, &g)?;
        // Over the bin, the object's bottom `drop_clearance` above the drop point.
        let hang = g.translation.dot(up) - o.bottom;
        let over = a.drop_at + up * (self.params.drop_clearance + hang.max(0.0));
        self.carry_over(over)?;
        self.driver.open(&self.gripper.name)?;
        self.group.remove_object(&name)?;
        go_home(self.driver, self.robot, self.group, self.home)
    }

    /// Attaches the held object's hull to the tool, its bottom taken off (it touches
    /// the table at the start of the lift, as the object does).
    fn attach_held(&mut self, o: &SeenObject) -> Result<(), SkillError> {
        let raised: Vec<Vec3> = hull_vertices(&o.hull)
            .into_iter()
            .map(|p| Vec3::new(p.x, p.y, p.z.max(o.bottom + 0.02)))
            .collect();
        let held_hull = SharedShape::convex_hull(&raised).unwrap_or_else(|| o.hull.clone());
        let q = current_arm(self.driver, self.group)?;
        let tool = self.group.tip_pose(&q)?;
        Ok(self
            .group
            .attach(&object_name(o), held_hull, tool.inverse())?)
    }

    /// Lifts straight up from grasp pose `g`. Straight up cannot hit what stands beside
    /// the object: its neighbours (within 2 cm of its hull) are out of the world while
    /// the lift is planned; what a nudge grasp pushed aside comes back after it.
    fn lift(&mut self, a: &GraspAction<'_>, g: &Pose) -> Result<(), SkillError> {
        let o = &a.objects[a.i];
        let neighbours: Vec<&SeenObject> = a
            .objects
            .iter()
            .enumerate()
            .filter(|&(j, n)| j != a.i && hulls_touch(o, n, 0.02))
            .map(|(_, n)| n)
            .collect();
        for n in &neighbours {
            // (What a nudge grasp pushed aside is out already.)
            let _ = self.group.remove_object(&object_name(n));
        }
        let lifted = Pose::from_parts(g.translation + self.table.up * self.params.lift, g.rotation);
        let q = current_arm(self.driver, self.group)?;
        let lift = self.group.cartesian(&q, &lifted);
        for n in &neighbours {
            self.add(n)?;
        }
        run_phase(self.driver, &lift?, "lift")?;
        for &k in a.nudged {
            let n = &a.objects[k];
            if !neighbours.iter().any(|x| x.id == n.id) {
                self.add(n)?;
            }
        }
        Ok(())
    }

    /// Carries the held object with the fingertips `over` (world), the hand turned
    /// whichever of four ways the arm reaches.
    fn carry_over(&mut self, over: Vec3) -> Result<(), SkillError> {
        let (hand, up) = (self.hand, self.table.up);
        let q = current_arm(self.driver, self.group)?;
        let mut last = Err(SkillError::Motion("no drop pose".into()));
        for a in 0..4 {
            let closing = Quat::from_rotation_z(a as f64 * std::f64::consts::FRAC_PI_4) * Vec3::X;
            let pose = hand.pose(over - up * hand.tip, closing, up);
            match self.group.plan_to_pose(&q, &pose) {
                Ok(p) => {
                    last = Ok(p);
                    break;
                }
                Err(e) => last = Err(e.into()),
            }
        }
        run_phase(self.driver, &last?, "to the bin")
    }

    /// Pushes object `i` of `objects` with the closed fingers, backs off, rises and
    /// goes home; `ik` solves the pre-push pose.
    pub(super) fn push(
        &mut self,
        objects: &[SeenObject],
        i: usize,
        push: &Push,
        ik: Vec<f64>,
    ) -> Result<(), SkillError> {
        let (up, params) = (self.table.up, self.params);
        let _ = self.driver.close(&self.gripper.name)?;
        let above =
            |p: &Pose| Pose::from_parts(p.translation + up * params.pre_push_height, p.rotation);
        let q = self.sync()?;
        self.approach_start(&q, ik, &above(&push.start), "to pre-push")?;
        self.line_to(&push.start, "down to the push")?;
        // The pushed object (and what it shoves) moves with the fingers: out of the
        // world for the push.
        self.group.remove_object(&object_name(&objects[i]))?;
        for &a in &push.chain {
            self.group.remove_object(&object_name(&objects[a]))?;
        }
        let d3 = push.direction3();
        let end = Pose::from_parts(
            push.start.translation + d3 * push.travel(params),
            push.start.rotation,
        );
        self.line_to(&end, "push")?;
        // Back off the object before rising, so the fingers do not drag it up with them.
        let back = Pose::from_parts(end.translation - d3 * params.push_back_off, end.rotation);
        let q = current_arm(self.driver, self.group)?;
        if let Ok(off) = self.group.cartesian(&q, &back) {
            run_phase(self.driver, &off, "back off")?;
        }
        self.line_to(&above(&back), "rise")?;
        go_home(self.driver, self.robot, self.group, self.home)
    }
}
