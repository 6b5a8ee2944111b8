//! Taking an object off a tabletop and carrying it: the motion sequence every task that
//! grasps from above shares — open to the grasp's width, to the pre-grasp the decision
//! solved, straight down, close, attach what is held, straight up — planned
//! collision-free against the other objects' hulls, phase by phase.

use super::motion::{current_arm, run_phase};
use super::{GraspCandidate, Hand, SkillError};
use crate::scene::{SeenObject, hits, hull_vertices, hulls_touch};
use tabula_geom::parry::shape::SharedShape;
use tabula_geom::{Pose, Quat, Vec3};
use tabula_motion::{MoveGroup, Plan};
use tabula_robot::description::Gripper;
use tabula_robot::driver::RobotDriver;
use tabula_robot::robots::NamedRobot;

/// How many IK solutions of each yaw's pre-grasp [`Manipulator::take`] tries when the
/// decision's cannot follow the lines down and up.
const LINE_STARTS: usize = 3;

/// The name an object's hull has in the planning world.
pub fn object_name(o: &SeenObject) -> String {
    format!("obj:{}", o.id)
}

/// A pose and its copies every 3 cm up to `height` along `up` (the way down to it).
pub fn descent_poses(pose: &Pose, up: Vec3, height: f64) -> Vec<Pose> {
    let steps = (height / 0.03).ceil().max(1.0) as usize;
    (0..=steps)
        .map(|k| {
            Pose::from_parts(
                pose.translation + up * (height * k as f64 / steps as f64),
                pose.rotation,
            )
        })
        .collect()
}

/// The objects (indices) the open gripper of `grasp` meets at the grasp or on its way
/// down from `pregrasp` above it, within `clearance` of their hulls, except those
/// `skip` names.
pub fn grasp_blockers(
    objects: &[SeenObject],
    grasp: &GraspCandidate,
    hand: &Hand,
    (up, pregrasp, clearance): (Vec3, f64, f64),
    skip: &dyn Fn(usize) -> bool,
) -> Vec<usize> {
    let poses = descent_poses(&grasp.poses[0], up, pregrasp);
    let shapes = hand.open_for(grasp.width).1;
    (0..objects.len())
        .filter(|&a| !skip(a))
        .filter(|&a| {
            poses
                .iter()
                .any(|p| hits(shapes, p, &objects[a], clearance))
        })
        .collect()
}

/// The first of `candidates` (grasps of object `i` of `objects`) that no other object
/// is in the way of (except those `skip` names), whose pre-grasp has collision-free IK
/// and whose straight lines down to the grasp and up to the lift the arm can follow:
/// the grasp and its pre-grasp joint values.
pub fn first_reachable(
    group: &MoveGroup,
    hand: &Hand,
    candidates: Vec<GraspCandidate>,
    (objects, skip): (&[SeenObject], &dyn Fn(usize) -> bool),
    (up, motion, clearance): (Vec3, PickMotion, f64),
    seed: &[f64],
) -> Option<(GraspCandidate, Vec<f64>)> {
    let shifted = |pose: &Pose, h: f64| Pose::from_parts(pose.translation + up * h, pose.rotation);
    candidates.into_iter().find_map(|g| {
        if !grasp_blockers(objects, &g, hand, (up, motion.pregrasp, clearance), skip).is_empty() {
            return None;
        }
        let q = g.poses.iter().find_map(|pose| {
            // A numeric IK reaches both ends of a line it cannot follow.
            let sols = group.valid_ik(&shifted(pose, motion.pregrasp), seed).ok()?;
            sols.into_iter().take(3).find(|q| {
                group.cartesian(q, pose).is_ok_and(|down| {
                    group
                        .cartesian(down.end(), &shifted(pose, motion.lift))
                        .is_ok()
                })
            })
        })?;
        Some((g, q))
    })
}

/// Distances of a grasp's motions (m): the pre-grasp above the grasp (SPEC §3.2: 10
/// cm) and the lift after it (SPEC §3.2: 20 cm).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PickMotion {
    pub pregrasp: f64,
    pub lift: f64,
    /// Open the fingers at the pre-grasp rather than before moving there: an arm
    /// tucked against the body cannot open where it is.
    pub open_at_pregrasp: bool,
}

/// An arm acting on a tabletop: the driver, its move group (whose world holds the
/// objects' hulls), its hand and gripper, the table's normal.
pub struct Manipulator<'a, D> {
    pub driver: &'a mut D,
    pub robot: &'a NamedRobot,
    pub group: &'a mut MoveGroup,
    pub hand: &'a Hand,
    pub gripper: &'a Gripper,
    /// The table's normal (world, unit).
    pub up: Vec3,
}

/// A grasp to take: of object `i` of `objects`, the IK solution the decision found for
/// its pre-grasp (`ik`), and the neighbours its fingers push aside (`nudged`).
pub struct Take<'a> {
    pub objects: &'a [SeenObject],
    pub i: usize,
    pub grasp: &'a GraspCandidate,
    pub ik: Vec<f64>,
    pub nudged: &'a [usize],
}

impl<D: RobotDriver> Manipulator<'_, D> {
    /// Puts an object's hull back into the planning world.
    pub fn add(&mut self, o: &SeenObject) -> Result<(), SkillError> {
        Ok(self
            .group
            .add_object(&object_name(o), o.hull.clone(), Pose::IDENTITY)?)
    }

    /// The group set to the robot's state now; the arm's values.
    pub fn sync(&mut self) -> Result<Vec<f64>, SkillError> {
        let state = self.driver.joint_state()?;
        self.group.set_state(self.robot, &state)?;
        Ok(self.group.arm_values(&state))
    }

    /// Plans from `q` to the decision's IK solution (else to `pre`, a pose) and goes
    /// there.
    pub fn approach_start(
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
    pub fn line_to(&mut self, to: &Pose, phase: &str) -> Result<(), SkillError> {
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

    /// Takes the object and lifts it; returns the grasp pose it was taken at. A grasp
    /// whose gripper closes on nothing backs up and fails with
    /// [`SkillError::Slipped`], the object back in the world.
    pub fn take(&mut self, a: &Take<'_>, motion: PickMotion) -> Result<Pose, SkillError> {
        let o = &a.objects[a.i];
        if !motion.open_at_pregrasp {
            self.driver.open_to(&self.gripper.name, a.grasp.width)?;
        }
        let q = self.sync()?;
        let (g, start) = self.followable_start(a, motion)?;
        let pre = Pose::from_parts(g.translation + self.up * motion.pregrasp, g.rotation);
        self.approach_start(&q, start, &pre, "to pre-grasp")?;
        if motion.open_at_pregrasp {
            self.driver.open_to(&self.gripper.name, a.grasp.width)?;
            self.sync()?;
        }
        self.moving_out(a)?;
        self.line_to(&g, "descend")?;
        let held = self.driver.close(&self.gripper.name)?;
        if !held.holding {
            self.line_to(&pre, "back up")?;
            self.add(o)?;
            return Err(SkillError::Slipped);
        }
        self.attach_held(o)?;
        self.lift(a, &g, motion.lift)?;
        Ok(g)
    }

    /// The target and what a nudge grasp's fingers push aside on the way down: out of
    /// the world (until the object is lifted).
    fn moving_out(&mut self, a: &Take<'_>) -> Result<(), SkillError> {
        self.group.remove_object(&object_name(&a.objects[a.i]))?;
        for &n in a.nudged {
            self.group.remove_object(&object_name(&a.objects[n]))?;
        }
        Ok(())
    }

    /// The grasp pose and the pre-grasp joint values to take it from: the decision's
    /// IK solution first, then up to [`LINE_STARTS`] other solutions of either yaw's
    /// pre-grasp — the first from which the lines down to the grasp and up to the lift
    /// can be followed. An IK solution at each end is not enough: near a wrist
    /// singularity the line between them makes a joint jump, and every try of the grasp
    /// would fail the same way, the arm already over the object. `Err` (the first
    /// candidate's) when none can, before anything moves.
    fn followable_start(
        &mut self,
        a: &Take<'_>,
        motion: PickMotion,
    ) -> Result<(Pose, Vec<f64>), SkillError> {
        let up = self.up;
        let shifted = |g: &Pose, h: f64| Pose::from_parts(g.translation + up * h, g.rotation);
        let solved = self.solved_yaw(a.grasp, &a.ik);
        let other = a.grasp.poses.iter().copied().find(|p| *p != solved);
        let mut candidates = vec![(solved, a.ik.clone())];
        for g in std::iter::once(solved).chain(other) {
            if let Ok(sols) = self.group.valid_ik(&shifted(&g, motion.pregrasp), &a.ik) {
                candidates.extend(sols.into_iter().take(LINE_STARTS).map(|q| (g, q)));
            }
        }
        let moving: Vec<&SeenObject> = std::iter::once(a.i)
            .chain(a.nudged.iter().copied())
            .map(|k| &a.objects[k])
            .collect();
        let mut first_error = None;
        let mut chosen = None;
        for (g, q) in candidates {
            // (The lift's check puts touching neighbours back, a nudged one among them.)
            for o in &moving {
                let _ = self.group.remove_object(&object_name(o));
            }
            let lines = self
                .group
                .cartesian(&q, &g)
                .map_err(SkillError::from)
                .and_then(|down| self.line_beside(a, down.end(), &shifted(&g, motion.lift)));
            match lines {
                Ok(_) => {
                    chosen = Some((g, q));
                    break;
                }
                Err(e) => {
                    first_error.get_or_insert(e);
                }
            }
        }
        for o in &moving {
            let _ = self.group.remove_object(&object_name(o));
            self.add(o)?;
        }
        match (chosen, first_error) {
            (Some(c), _) => Ok(c),
            (None, Some(e)) => Err(e),
            (None, None) => Err(SkillError::Motion("no pre-grasp to take it from".into())),
        }
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

    /// Lifts `height` straight up from grasp pose `g`. Straight up cannot hit what
    /// stands beside the object: its neighbours (within 2 cm of its hull) are out of the
    /// world while the lift is planned; what a nudge grasp pushed aside comes back
    /// after it.
    fn lift(&mut self, a: &Take<'_>, g: &Pose, height: f64) -> Result<(), SkillError> {
        let lifted = Pose::from_parts(g.translation + self.up * height, g.rotation);
        self.line_beside_neighbours(a, &lifted, "lift")?;
        let o = &a.objects[a.i];
        for &k in a.nudged {
            let n = &a.objects[k];
            if !hulls_touch(o, n, 0.02) {
                self.add(n)?;
            }
        }
        Ok(())
    }

    /// Puts the held object back where it was taken (grasp pose `g`, from straight
    /// above it), lets go and rises `rise` again: the way the lift came, planned the
    /// same way.
    pub fn put_back(&mut self, a: &Take<'_>, g: &Pose, rise: f64) -> Result<(), SkillError> {
        let release = Pose::from_parts(g.translation + self.up * 0.005, g.rotation);
        self.line_beside_neighbours(a, &release, "put back")?;
        self.driver.open(&self.gripper.name)?;
        // Let go of: the next frame sees where it lies.
        self.group.remove_object(&object_name(&a.objects[a.i]))?;
        let above = Pose::from_parts(g.translation + self.up * rise, g.rotation);
        self.line_to(&above, "up from putting back")
    }

    /// A straight line of the tool to `to`, planned with the held object's neighbours
    /// (within 2 cm of its hull) out of the world: a line straight up or down beside
    /// them cannot hit them, and seen hulls of touching objects overlap by noise.
    fn line_beside_neighbours(
        &mut self,
        a: &Take<'_>,
        to: &Pose,
        phase: &str,
    ) -> Result<(), SkillError> {
        let q = current_arm(self.driver, self.group)?;
        let line = self.line_beside(a, &q, to)?;
        run_phase(self.driver, &line, phase)
    }

    /// The straight line from `q` to `to` planned with the held object's neighbours
    /// (within 2 cm of its hull) out of the world (see [`Self::line_beside_neighbours`]).
    fn line_beside(&mut self, a: &Take<'_>, q: &[f64], to: &Pose) -> Result<Plan, SkillError> {
        let o = &a.objects[a.i];
        let neighbours: Vec<&SeenObject> = a
            .objects
            .iter()
            .enumerate()
            .filter(|&(j, n)| j != a.i && hulls_touch(o, n, 0.02))
            .map(|(_, n)| n)
            .collect();
        for n in &neighbours {
            // (What a nudge grasp pushed aside may be out already.)
            let _ = self.group.remove_object(&object_name(n));
        }
        let line = self.group.cartesian(q, to);
        for n in &neighbours {
            self.add(n)?;
        }
        Ok(line?)
    }

    /// Puts the held object down with the tool at `at` (world; where it was taken):
    /// above it by `pregrasp`, straight down, open, straight up.
    pub fn put_down(&mut self, at: &Pose, pregrasp: f64) -> Result<(), SkillError> {
        let pre = Pose::from_parts(at.translation + self.up * pregrasp, at.rotation);
        let q = self.sync()?;
        let plan = self.group.plan_to_pose(&q, &pre)?;
        run_phase(self.driver, &plan, "over the spot")?;
        let release = Pose::from_parts(at.translation + self.up * 0.005, at.rotation);
        self.line_to(&release, "put down")?;
        self.driver.open(&self.gripper.name)?;
        self.line_to(&pre, "up")
    }

    /// Carries the held object with the fingertips `over` (world), the hand turned as
    /// it holds the object or any of four ways. Level first: straight across at the
    /// higher of the two heights, then down, the hand pointing down all the way. A
    /// free path tilted it 56° on the median carry of six piles (over 90° on one in
    /// ten): what rests on the held object slid off and was flung off the table (pile
    /// seeds 3, 49, 155). Where no level line is free, such a path.
    pub fn carry_over(&mut self, over: Vec3, phase: &str) -> Result<(), SkillError> {
        let (hand, up) = (self.hand, self.up);
        let q = current_arm(self.driver, self.group)?;
        let now = self.group.tip_pose(&q)?;
        let held_closing = now.rotation * hand.closing;
        let turns = std::iter::once(held_closing).chain(
            (0..4).map(|a| Quat::from_rotation_z(a as f64 * std::f64::consts::FRAC_PI_4) * Vec3::X),
        );
        let poses: Vec<Pose> = turns
            .map(|closing| hand.pose(over - up * hand.tip, closing, up))
            .collect();
        if let Some((across, down)) = poses.iter().find_map(|to| self.level_lines(&q, &now, to)) {
            run_phase(self.driver, &across, phase)?;
            return run_phase(self.driver, &down, phase);
        }
        let mut last = Err(SkillError::Motion("no drop pose".into()));
        for pose in &poses[1..] {
            match self.group.plan_to_pose(&q, pose) {
                Ok(p) => {
                    last = Ok(p);
                    break;
                }
                Err(e) => last = Err(e.into()),
            }
        }
        run_phase(self.driver, &last?, phase)
    }

    /// Straight lines from `q` (the tip at `now`) across to above `to` at the higher
    /// of their heights, then along `up` down to `to`; `None` if either is blocked.
    fn level_lines(&self, q: &[f64], now: &Pose, to: &Pose) -> Option<(Plan, Plan)> {
        let up = self.up;
        let rise = (now.translation - to.translation).dot(up).max(0.0);
        let above = Pose::from_parts(to.translation + up * rise, to.rotation);
        let across = self.group.cartesian_continuous(q, &above).ok()?;
        let down = self.group.cartesian_continuous(across.end(), to).ok()?;
        Some((across, down))
    }
}
