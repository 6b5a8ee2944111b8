//! The tidying loop: from where the robot started, look at the table, take the nearest
//! object a top grasp of either hand reaches without touching a neighbour, hand it to
//! placing (which scans it, finds another surface, drives there and puts it down
//! stably), come back.

use super::{Failure, TidyError, TidyParams, TidyReport, TidyRequest};
use crate::place::{PlaceRequest, place};
use crate::scene::tabletop::{decimated, filtered_cloud, perceive};
use crate::scene::{SeenObject, Table, on_pairs};
use crate::skills::base::{drive_back, step_up_to, world_from_base};
use crate::skills::motion::run_phase;
use crate::skills::pick::{Manipulator, PickMotion, Take, grasp_blockers, object_name};
use crate::skills::{GraspCandidate, GraspPlanner, Hand, SkillError, arm_with_gripper};
use tabula_geom::parry::shape::SharedShape;
use tabula_geom::{Pose, Vec3};
use tabula_motion::MoveGroup;
use tabula_motion::group::thread_cpu;
use tabula_robot::description::Gripper;
use tabula_robot::driver::{JointState, RobotDriver};
use tabula_robot::robots::NamedRobot;

/// How far the base backs away before driving back to its start (m).
const BACK_OFF: f64 = 0.4;
/// How near the base's front steps up to the table's edge (m).
const STEP_GAP: f64 = 0.04;

/// An arm that can take things: its name, gripper and hand.
struct Taker {
    arm: String,
    gripper: Gripper,
    hand: Hand,
}

/// One frame's view: the table, its objects, which stands on which.
#[derive(Clone, Copy)]
struct Frame<'f> {
    table: &'f Table,
    objects: &'f [SeenObject],
    on: &'f [(usize, usize)],
}

/// A chosen grasp: the arm (index), its group, the object, the grasp, its pre-grasp IK.
type Choice = (usize, MoveGroup, usize, GraspCandidate, Vec<f64>);

pub(super) struct Run<'a, D> {
    driver: &'a mut D,
    robot: &'a NamedRobot,
    params: &'a TidyParams,
    request: &'a TidyRequest,
    takers: Vec<Taker>,
    /// The first arm's group: its allowed-collision matrix is sampled once (setup).
    template: MoveGroup,
    /// Where the base started (it comes back for every object) and where it looks.
    start: Pose,
    /// Where the run began: placing searches and drives from there (stepped up to the
    /// table, the base has no room to turn).
    origin: Pose,
    /// The robot's joints at the start (the arms out of the way) and the last table
    /// seen (down to the floor): the arms go back there before the base drives.
    ready: JointState,
    table_prism: Option<SharedShape>,
    look: Vec3,
    /// Where objects failed, and how often.
    tried: Vec<(Vec3, usize)>,
    report: TidyReport,
    decisions: Vec<f64>,
}

fn skill_error(e: SkillError) -> TidyError {
    match e {
        SkillError::Robot(m) => TidyError::Robot(m),
        SkillError::Driver(m) => TidyError::Driver(m),
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
        let names: Vec<String> = match &request.arm {
            Some(a) => vec![a.clone()],
            None => robot
                .description
                .arms
                .iter()
                .filter(|a| a.gripper.is_some())
                .map(|a| a.name.clone())
                .collect(),
        };
        if names.is_empty() {
            return Err(TidyError::Robot("no arm with a gripper".into()));
        }
        let mut takers = Vec::new();
        for name in names {
            let (arm, gripper) = arm_with_gripper(robot, Some(&name)).map_err(skill_error)?;
            let hand = Hand::new(robot, &gripper).map_err(skill_error)?;
            takers.push(Taker {
                arm: arm.name,
                gripper,
                hand,
            });
        }
        let start = world_from_base(robot, driver).map_err(skill_error)?;
        let ahead = (start.rotation * Vec3::X).with_z(0.0);
        let look = request
            .from
            .unwrap_or(start.translation.with_z(0.75) + ahead * 0.8);
        if !look.is_finite() {
            return Err(TidyError::Params("the table's point must be finite".into()));
        }
        let (state, root) = (driver.joint_state()?, driver.world_from_root()?);
        let template = MoveGroup::new(robot, &takers[0].arm, &state, root, params.motion.clone())
            .map_err(|e| TidyError::Robot(e.to_string()))?;
        let (tried, report, decisions) = (Vec::new(), TidyReport::default(), Vec::new());
        Ok(Self {
            driver,
            robot,
            params,
            request,
            takers,
            template,
            start,
            origin: start,
            ready: state.clone(),
            table_prism: None,
            look,
            tried,
            report,
            decisions,
        })
    }

    pub(super) fn run(mut self) -> Result<TidyReport, TidyError> {
        for frame in 0.. {
            self.arms_in();
            match self.return_to_start() {
                Ok(()) => {}
                Err(TidyError::Driver(e)) if frame > 0 => {
                    // Stuck on the way back: what is placed stays placed.
                    self.report.stop = format!("could not drive back: {e}");
                    break;
                }
                Err(e) => return Err(e),
            }
            let (table, objects) = self.look_at_table()?;
            if frame == 0 {
                self.report.objects = objects.len();
            }
            let c0 = thread_cpu();
            let chosen = self.choose(&table, &objects);
            self.decisions.push((thread_cpu() - c0) * 1e3);
            let Some(choice) = chosen else {
                // Out of reach from here: step up to the table and look again.
                if !objects.is_empty() && self.step_up(&table)? {
                    continue;
                }
                self.report.stop = if objects.is_empty() {
                    "table clear"
                } else {
                    "nothing left that can be taken"
                }
                .into();
                break;
            };
            self.report.actions += 1;
            let i = choice.2;
            match self.move_one(&table, &objects, choice) {
                Ok(()) => self.report.placed += 1,
                Err((reason, message)) => self.fail(&objects[i], reason, message),
            }
        }
        self.report.decision_ms = crate::clear::Stats::of(&self.decisions);
        Ok(self.report)
    }

    /// Brings every hand's arm back to where it was at the start before the base
    /// drives: an arm left low beside the body sweeps into tables. An arm that cannot
    /// get there stays.
    fn arms_in(&mut self) {
        let Ok(state) = self.driver.joint_state() else {
            return;
        };
        for k in 0..self.takers.len() {
            let Ok(mut g) = self.template.for_arm(self.robot, &self.takers[k].arm) else {
                continue;
            };
            if g.set_state(self.robot, &state).is_err() {
                continue;
            }
            if let Some(prism) = &self.table_prism {
                let _ = g.add_object("table", prism.clone(), Pose::IDENTITY);
            }
            let (now, ready) = (g.arm_values(&state), g.arm_values(&self.ready));
            if now.iter().zip(&ready).all(|(a, b)| (a - b).abs() < 0.05) {
                continue;
            }
            if let Ok(plan) = g.plan_to_joints(&now, &[ready]) {
                let _ = run_phase(self.driver, &plan, "arm in");
            }
        }
    }

    /// Drives back to where the run started when the base moved.
    fn return_to_start(&mut self) -> Result<(), TidyError> {
        drive_back(self.driver, self.robot, &self.start, BACK_OFF).map_err(skill_error)
    }

    /// Steps the base up to the table when it stands farther; whether it moved.
    fn step_up(&mut self, table: &Table) -> Result<bool, TidyError> {
        let moved = step_up_to(self.driver, self.robot, &table.outline, table.z, STEP_GAP)
            .map_err(skill_error)?;
        if let Some(pose) = moved {
            self.start = pose;
        }
        Ok(moved.is_some())
    }

    /// A frame of the table: its plane and outline, the objects on it.
    fn look_at_table(&mut self) -> Result<(Table, Vec<SeenObject>), TidyError> {
        let _ = self.driver.look_at(self.look);
        let p = self.params;
        let frame = self.driver.capture(&p.camera)?;
        let (state, root) = (self.driver.joint_state()?, self.driver.world_from_root()?);
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

    /// Arm `k`'s group at the robot's state with the table (its outline down to the
    /// floor) and the objects' hulls in its world.
    fn group(&mut self, k: usize, table: &Table, objects: &[SeenObject]) -> Option<MoveGroup> {
        let mut group = self
            .template
            .for_arm(self.robot, &self.takers[k].arm)
            .ok()?;
        group
            .set_state(self.robot, &self.driver.joint_state().ok()?)
            .ok()?;
        let body: Vec<Vec3> = table
            .outline
            .iter()
            .flat_map(|p| [p.extend(table.z - 0.005), p.extend(0.0)])
            .collect();
        let prism = SharedShape::convex_hull(&body)?;
        self.table_prism = Some(prism.clone());
        group.add_object("table", prism, Pose::IDENTITY).ok()?;
        for o in objects {
            group
                .add_object(&object_name(o), o.hull.clone(), Pose::IDENTITY)
                .ok()?;
        }
        Some(group)
    }

    /// The nearest object nothing stands on and not given up on, with a top grasp of
    /// either hand no neighbour is in the way of, whose pre-grasp has IK and whose
    /// straight lines down and up the arm can follow.
    fn choose(&mut self, table: &Table, objects: &[SeenObject]) -> Option<Choice> {
        let on = on_pairs(objects, table.z);
        let me = self.start.translation.truncate();
        let mut order: Vec<usize> = (0..objects.len())
            .filter(|&i| {
                !on.iter().any(|&(_, under)| under == i)
                    && self.attempts(&objects[i]) < self.params.max_attempts
            })
            .collect();
        order.sort_by(|&a, &b| {
            objects[a]
                .rect
                .center
                .distance(me)
                .total_cmp(&objects[b].rect.center.distance(me))
        });
        let mut groups: Vec<Option<MoveGroup>> = (0..self.takers.len())
            .map(|k| self.group(k, table, objects))
            .collect();
        let state = self.driver.joint_state().ok()?;
        let frame = Frame {
            table,
            objects,
            on: &on,
        };
        for i in order {
            for (k, slot) in groups.iter_mut().enumerate() {
                let Some(group) = slot.as_mut() else { continue };
                let seed = group.arm_values(&state);
                let name = object_name(&objects[i]);
                let _ = group.remove_object(&name);
                let found = self.grasp_of(group, k, frame, i, &seed);
                let _ = group.add_object(&name, objects[i].hull.clone(), Pose::IDENTITY);
                if let Some((g, q)) = found {
                    return Some((k, slot.take()?, i, g, q));
                }
            }
        }
        None
    }

    /// A top grasp of object `i` by hand `k` (see [`Self::choose`]).
    fn grasp_of(
        &self,
        group: &MoveGroup,
        k: usize,
        f: Frame<'_>,
        i: usize,
        seed: &[f64],
    ) -> Option<(GraspCandidate, Vec<f64>)> {
        let (p, hand, up, objects, on) = (
            self.params,
            &self.takers[k].hand,
            f.table.up,
            f.objects,
            f.on,
        );
        let skip = |a: usize| a == i || on.contains(&(a, i)) || on.contains(&(i, a));
        let shifted =
            |pose: &Pose, h: f64| Pose::from_parts(pose.translation + up * h, pose.rotation);
        p.grasp
            .candidates(&objects[i].grasp_target(), hand, up)
            .into_iter()
            .find_map(|g| {
                if !grasp_blockers(objects, &g, hand, (up, p.pregrasp, p.clearance), &skip)
                    .is_empty()
                {
                    return None;
                }
                let q = g.poses.iter().find_map(|pose| {
                    // A numeric IK reaches both ends of a line it cannot follow.
                    let sols = group.valid_ik(&shifted(pose, p.pregrasp), seed).ok()?;
                    sols.into_iter().take(3).find(|q| {
                        group.cartesian(q, pose).is_ok_and(|down| {
                            group.cartesian(down.end(), &shifted(pose, p.lift)).is_ok()
                        })
                    })
                })?;
                Some((g, q))
            })
    }

    /// Takes the chosen object and has placing put it on another surface; the typed
    /// reason and message when that fails.
    fn move_one(
        &mut self,
        table: &Table,
        objects: &[SeenObject],
        (k, mut group, i, grasp, ik): Choice,
    ) -> Result<(), (String, String)> {
        let p = self.params;
        let t = &self.takers[k];
        let mut arm = Manipulator {
            driver: &mut *self.driver,
            robot: self.robot,
            group: &mut group,
            hand: &t.hand,
            gripper: &t.gripper,
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
        let taken_at = match arm.take(&take, motion) {
            Ok(g) => g,
            Err(e) => {
                let _ = self.driver.open(&t.gripper.name);
                let kind = if e == SkillError::Slipped {
                    "grasp slipped"
                } else {
                    "no grasp motion"
                };
                return Err((kind.into(), e.to_string()));
            }
        };
        if let Err(e) = drive_back(self.driver, self.robot, &self.origin, BACK_OFF) {
            if self.put_back(k, &mut group, taken_at, table.up).is_err() {
                let _ = self.driver.open(&self.takers[k].gripper.name);
            }
            return Err(("driver".into(), e.to_string()));
        }
        // Not back onto the table it came from.
        let request = PlaceRequest {
            arm: Some(t.arm.clone()),
            not_on: vec![objects[i].rect.center.extend(table.z)],
            near: self.request.to,
        };
        let placed = place(self.driver, self.robot, &request, &p.place);
        self.decisions.push(placed.report.decision_ms);
        match placed.error {
            None => Ok(()),
            Some(e) => {
                // Still held: back where it came from, not dropped wherever the hand is.
                if self.put_back(k, &mut group, taken_at, table.up).is_err() {
                    let _ = self.driver.open(&self.takers[k].gripper.name);
                }
                Err((e.kind().to_string(), e.to_string()))
            }
        }
    }

    /// Puts the held object back down where hand `k` took it (`at`, the grasp pose):
    /// back to the start, above it, straight down, open, straight up.
    fn put_back(
        &mut self,
        k: usize,
        group: &mut MoveGroup,
        at: Pose,
        up: Vec3,
    ) -> Result<(), TidyError> {
        self.return_to_start()?;
        let t = &self.takers[k];
        let mut arm = Manipulator {
            driver: &mut *self.driver,
            robot: self.robot,
            group,
            hand: &t.hand,
            gripper: &t.gripper,
            up,
        };
        arm.put_down(&at, self.params.pregrasp).map_err(skill_error)
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
