//! Executing the chosen action through the driver: a grasp that drops the object into
//! the bin, or a push with the closed gripper — each planned collision-free against the
//! other objects' hulls, phase by phase, and back home out of the camera's view.

use super::push::Push;
use super::{ClearParams, SeenObject};
use crate::skills::carried::{Lifted, points_carried_along};
use crate::skills::motion::{current_arm, go_home, run_phase};
use crate::skills::pick::{Manipulator, PickMotion, Take, object_name};
use crate::skills::{GraspCandidate, SkillError};
use tabula_geom::{Pose, Vec3};
use tabula_robot::driver::RobotDriver;

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

/// What executing an action works with: the arm on the table, where home is.
pub(super) struct Executor<'a, D> {
    pub(super) arm: Manipulator<'a, D>,
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
    fn home(&mut self) -> Result<(), SkillError> {
        let arm = &mut self.arm;
        go_home(arm.driver, arm.robot, arm.group, self.home)
    }

    /// Grasps, lifts, carries over the bin and lets go, then goes home.
    pub(super) fn grasp(&mut self, a: GraspAction<'_>) -> Result<(), SkillError> {
        let o = &a.objects[a.i];
        let take = Take {
            objects: a.objects,
            i: a.i,
            grasp: a.grasp,
            ik: a.ik,
            nudged: a.nudged,
        };
        let motion = PickMotion {
            pregrasp: self.params.pregrasp,
            lift: self.params.lift,
            open_at_pregrasp: false,
        };
        let g = self.arm.take(&take, motion)?;
        self.nothing_carried_along(&take, &g)?;
        // Over the bin, the object's bottom `drop_clearance` above the drop point.
        let up = self.arm.up;
        let hang = g.translation.dot(up) - o.bottom;
        let over = a.drop_at + up * (self.params.drop_clearance + hang.max(0.0));
        self.arm.carry_over(over, "to the bin")?;
        self.arm.driver.open(&self.arm.gripper.name)?;
        self.arm.group.remove_object(&object_name(o))?;
        self.home()
    }

    /// After the lift, a look: an object that came up with the held one (resting on
    /// it, leaning on it) would fall on the way to the bin, off the table. Then both
    /// are put back down where they were taken and the grasp fails
    /// ([`SkillError::CarriedAlong`]); the next frame sees how they lie.
    fn nothing_carried_along(&mut self, take: &Take<'_>, g: &Pose) -> Result<(), SkillError> {
        let observer = self.params.observer();
        let captured = observer.capture(self.arm.driver)?;
        let cloud = observer.world_cloud(self.arm.robot, &captured);
        let up = self.arm.up;
        let lifted = Lifted {
            objects: take.objects,
            held: take.i,
            moved: take.nudged,
            lift: up * self.params.lift,
            tool: g.translation + up * self.params.lift,
            up,
        };
        let n = points_carried_along(&cloud, &lifted, &self.params.carried);
        if n < self.params.carried.min_points {
            return Ok(());
        }
        tracing::info!(
            object = take.objects[take.i].id,
            points = n,
            "clear: lifted another object with it; putting both back"
        );
        self.arm.put_back(take, g, self.params.pregrasp)?;
        Err(SkillError::CarriedAlong(n))
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
        let (up, params) = (self.arm.up, self.params);
        let _ = self.arm.driver.close(&self.arm.gripper.name)?;
        let above =
            |p: &Pose| Pose::from_parts(p.translation + up * params.pre_push_height, p.rotation);
        let q = self.arm.sync()?;
        self.arm
            .approach_start(&q, ik, &above(&push.start), "to pre-push")?;
        self.arm.line_to(&push.start, "down to the push")?;
        // The pushed object (and what it shoves) moves with the fingers: out of the
        // world for the push.
        self.arm.group.remove_object(&object_name(&objects[i]))?;
        for &a in &push.chain {
            self.arm.group.remove_object(&object_name(&objects[a]))?;
        }
        let d3 = push.direction3();
        let end = Pose::from_parts(
            push.start.translation + d3 * push.travel(params),
            push.start.rotation,
        );
        self.arm.line_to(&end, "push")?;
        // Back off the object before rising, so the fingers do not drag it up with them.
        let back = Pose::from_parts(end.translation - d3 * params.push_back_off, end.rotation);
        let q = current_arm(self.arm.driver, self.arm.group)?;
        if let Ok(off) = self.arm.group.cartesian(&q, &back) {
            run_phase(self.arm.driver, &off, "back off")?;
        }
        self.arm.line_to(&above(&back), "rise")?;
        self.home()
    }
}
