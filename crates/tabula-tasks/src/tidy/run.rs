//! The tidying loop: from where the robot started, look at the table, take the nearest
//! object a top grasp reaches without touching a neighbour, hand it to placing (which
//! scans it, finds another surface, drives there and puts it down stably), come back.

use super::{Failure, TidyError, TidyParams, TidyReport, TidyRequest};
use crate::place::{PlaceRequest, place};
use crate::scene::tabletop::{decimated, filtered_cloud, perceive};
use crate::scene::{SeenObject, Table, on_pairs};
use crate::skills::base::{heading, world_from_base};
use crate::skills::motion::go_home;
use crate::skills::pick::{Manipulator, PickMotion, Take, grasp_blockers, object_name};
use crate::skills::{GraspCandidate, GraspPlanner, Hand, SkillError, arm_with_gripper};
use tabula_geom::parry::shape::SharedShape;
use tabula_geom::{Pose, Vec3};
use tabula_motion::MoveGroup;
use tabula_motion::group::thread_cpu;
use tabula_robot::description::{ArmGroup, Gripper};
use tabula_robot::driver::RobotDriver;
use tabula_robot::robots::NamedRobot;

/// A chosen grasp: the object (index), the grasp, the IK of its pre-grasp.
type Choice = (usize, GraspCandidate, Vec<f64>);

pub(super) struct Run<'a, D> {
    driver: &'a mut D,
    robot: &'a NamedRobot,
    params: &'a TidyParams,
    request: &'a TidyRequest,
    arm: ArmGroup,
    gripper: Gripper,
    hand: Hand,
    /// Where the base started: it comes back here for every object.
    start: Pose,
    /// Where the table to clear is looked at (world).
    look: Vec3,
    /// Objects that failed, with their attempts.
    tried: Vec<(Vec3, usize)>,
    report: TidyReport,
    decisions: Vec<f64>,
}

fn skill_error(e: SkillError) -> TidyError {
    match e {
        SkillError::Robot(m) => TidyError::Robot(m),
        other => TidyError::Driver(other.to_string()),
    }
}

impl<'a, D: RobotDriver> Run<'a, D> {
    pub(super) fn new(
        driver: &'a mut D,
        robot: &'a NamedRobot,
        request: &'a TidyRequest,
        params: &'a TidyParams,
    ) -> Result<Self, TidyError> {
        let (arm, gripper) =
            arm_with_gripper(robot, request.arm.as_deref()).map_err(skill_error)?;
        let hand = Hand::new(robot, &gripper).map_err(skill_error)?;
        let start = world_from_base(robot, driver).map_err(skill_error)?;
        let ahead = start.rotation * Vec3::X;
        let look = request
            .from
            .unwrap_or(start.translation.with_z(0.75) + Vec3::new(ahead.x, ahead.y, 0.0) * 0.8);
        if !look.is_finite() {
            return Err(TidyError::Params("the table's point must be finite".into()));
        }
        Ok(Self {
            driver,
            robot,
            params,
            request,
            arm,
            gripper,
            hand,
            start,
            look,
            tried: Vec::new(),
            report: TidyReport::default(),
            decisions: Vec::new(),
        })
    }

    pub(super) fn run(mut self) -> Result<TidyReport, TidyError> {
        // Every object can be tried `max_attempts` times; a table never empties only
        // when objects fail for good.
        for frame in 0.. {
            self.return_to_start()?;
            let (table, objects) = self.look_at_table()?;
            if frame == 0 {
                self.report.objects = objects.len();
            }
            let c0 = thread_cpu();
            let mut group = self.group(&table, &objects)?;
            let chosen = self.choose(&mut group, &table, &objects);
            self.decisions.push((thread_cpu() - c0) * 1e3);
            let Some((i, grasp, ik)) = chosen else {
                self.report.stop = if objects.is_empty() {
                    "table clear".into()
                } else {
                    "nothing left that can be taken".into()
                };
                break;
            };
            self.report.actions += 1;
            if let Err((reason, message)) =
                self.move_one(&mut group, &table, &objects, (i, grasp, ik))
            {
                self.fail(&objects[i], reason, message);
            } else {
                self.report.placed += 1;
            }
        }
        self.report.decision_ms = crate::clear::Stats::of(&self.decisions);
        let _ = self.return_to_start();
        Ok(self.report)
    }

    /// Drives back to where the run started (when the base moved) and tucks the arm.
    fn return_to_start(&mut self) -> Result<(), TidyError> {
        let base = world_from_base(self.robot, self.driver).map_err(skill_error)?;
        let (h0, h) = (heading(&self.start), heading(&base));
        let turned = (h - h0 + std::f64::consts::PI).rem_euclid(std::f64::consts::TAU)
            - std::f64::consts::PI;
        if base
            .translation
            .truncate()
            .distance(self.start.translation.truncate())
            > 0.02
            || turned.abs() > 0.03
        {
            let s = self.start.translation;
            self.driver.drive_to(s.x, s.y, h0)?;
        }
        Ok(())
    }

    /// A frame of the table: its plane and outline, the objects on it.
    fn look_at_table(&mut self) -> Result<(Table, Vec<SeenObject>), TidyError> {
        let _ = self.driver.look_at(self.look);
        let frame = self.driver.capture(&self.params.camera)?;
        let state = self.driver.joint_state()?;
        let root = self.driver.world_from_root()?;
        let p = self.params;
        let cloud = filtered_cloud(
            &frame,
            self.robot,
            &state,
            root,
            p.decimate,
            p.self_filter_padding,
        );
        let tabletop = decimated(&p.tabletop, p.decimate);
        let (table, mut objects) = perceive(&cloud, frame.world_from_camera.translation, &tabletop)
            .map_err(|e| TidyError::Perception(e.to_string()))?;
        for (k, o) in objects.iter_mut().enumerate() {
            o.id = k;
        }
        Ok((table, objects))
    }

    /// The arm's move group with the table (its outline down to the floor) and the
    /// objects' hulls in its world.
    fn group(&mut self, table: &Table, objects: &[SeenObject]) -> Result<MoveGroup, TidyError> {
        let state = self.driver.joint_state()?;
        let root = self.driver.world_from_root()?;
        let robot_error = |e: tabula_motion::MoveError| TidyError::Robot(e.to_string());
        let mut group = MoveGroup::new(
            self.robot,
            &self.arm.name,
            &state,
            root,
            self.params.motion.clone(),
        )
        .map_err(robot_error)?;
        let body: Vec<Vec3> = table
            .outline
            .iter()
            .flat_map(|p| [p.extend(table.z - 0.005), p.extend(0.0)])
            .collect();
        if let Some(slab) = SharedShape::convex_hull(&body) {
            group
                .add_object("table", slab, Pose::IDENTITY)
                .map_err(robot_error)?;
        }
        for o in objects {
            group
                .add_object(&object_name(o), o.hull.clone(), Pose::IDENTITY)
                .map_err(robot_error)?;
        }
        Ok(group)
    }

    /// The nearest object nothing stands on, not given up on, with a top grasp no
    /// neighbour is in the way of and whose pre-grasp and grasp have IK.
    fn choose(
        &self,
        group: &mut MoveGroup,
        table: &Table,
        objects: &[SeenObject],
    ) -> Option<Choice> {
        let on = on_pairs(objects, table.z);
        let me = self.start.translation.truncate();
        let mut order: Vec<usize> = (0..objects.len())
            .filter(|&i| !on.iter().any(|&(_, under)| under == i))
            .filter(|&i| self.attempts(&objects[i]) < self.params.max_attempts)
            .collect();
        order.sort_by(|&a, &b| {
            let d = |i: usize| objects[i].rect.center.distance(me);
            d(a).total_cmp(&d(b))
        });
        let seed = group.arm_values(&self.driver.joint_state().ok()?);
        let p = self.params;
        order.into_iter().find_map(|i| {
            let o = &objects[i];
            let skip = |a: usize| a == i || on.contains(&(a, i)) || on.contains(&(i, a));
            let name = object_name(o);
            let _ = group.remove_object(&name);
            let found = p
                .grasp
                .candidates(&o.grasp_target(), &self.hand, table.up)
                .into_iter()
                .find_map(|g| {
                    if !grasp_blockers(
                        objects,
                        &g,
                        &self.hand,
                        (table.up, p.pregrasp, p.clearance),
                        &skip,
                    )
                    .is_empty()
                    {
                        return None;
                    }
                    g.poses.iter().find_map(|pose| {
                        let pre = Pose::from_parts(
                            pose.translation + table.up * p.pregrasp,
                            pose.rotation,
                        );
                        let lifted =
                            Pose::from_parts(pose.translation + table.up * p.lift, pose.rotation);
                        // The straight lines down and up must work too: a numeric IK
                        // reaches both ends of a line it cannot follow.
                        let sols = group.valid_ik(&pre, &seed).ok()?;
                        sols.into_iter().take(3).find_map(|q| {
                            let down = group.cartesian(&q, pose).ok()?;
                            group.cartesian(down.end(), &lifted).ok()?;
                            Some((i, g.clone(), q))
                        })
                    })
                });
            let _ = group.add_object(&name, o.hull.clone(), Pose::IDENTITY);
            found
        })
    }

    /// Takes object `i` and has placing put it on another surface; the typed reason
    /// and message when it fails.
    fn move_one(
        &mut self,
        group: &mut MoveGroup,
        table: &Table,
        objects: &[SeenObject],
        (i, grasp, ik): Choice,
    ) -> Result<(), (String, String)> {
        let p = self.params;
        let mut arm = Manipulator {
            driver: &mut *self.driver,
            robot: self.robot,
            group,
            hand: &self.hand,
            gripper: &self.gripper,
            up: table.up,
        };
        let take = Take {
            objects,
            i,
            grasp: &grasp,
            ik,
            nudged: &[],
        };
        let motion = PickMotion {
            pregrasp: p.pregrasp,
            lift: p.lift,
            open_at_pregrasp: true,
        };
        if let Err(e) = arm.take(&take, motion) {
            let _ = arm.driver.open(&self.gripper.name);
            let tucked = self.arm.tucked.clone();
            let home: Vec<f64> = arm
                .group
                .joint_names()
                .iter()
                .map(|n| tucked.get(n).copied().unwrap_or(0.0))
                .collect();
            let _ = go_home(arm.driver, arm.robot, arm.group, &home);
            let kind = if e == SkillError::Slipped {
                "grasp slipped"
            } else {
                "no grasp motion"
            };
            return Err((kind.into(), e.to_string()));
        }
        // Not back onto the table it came from.
        let request = PlaceRequest {
            arm: Some(self.arm.name.clone()),
            not_on: vec![objects[i].rect.center.extend(table.z)],
            near: self.request.to,
        };
        let placed = place(self.driver, self.robot, &request, &p.place);
        self.decisions.push(placed.report.decision_ms);
        match placed.error {
            None => Ok(()),
            Some(e) => {
                let _ = self.driver.open(&self.gripper.name);
                Err((e.kind().to_string(), e.to_string()))
            }
        }
    }

    fn attempts(&self, o: &SeenObject) -> usize {
        let at = o.center();
        self.tried
            .iter()
            .filter(|(q, _)| q.distance(at) < 0.05)
            .map(|(_, n)| *n)
            .sum()
    }

    fn fail(&mut self, o: &SeenObject, reason: String, message: String) {
        let at = o.center();
        match self.tried.iter_mut().find(|(q, _)| q.distance(at) < 0.05) {
            Some(t) => t.1 += 1,
            None => self.tried.push((at, 1)),
        }
        self.report.failed.push(Failure {
            object: at.to_array(),
            reason,
            message,
        });
    }
}
