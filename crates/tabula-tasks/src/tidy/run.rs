//! The tidying loop: look, take the nearest object either hand can, have placing put it
//! on another surface, come back.

use super::{Failure, TidyError, TidyParams, TidyReport, TidyRequest};
use crate::place::{PlaceRequest, place};
use crate::scene::{Attempts, Observer, SeenObject, Table, on_pairs};
use crate::skills::base::{BACK_OFF, drive_back, step_up_to, world_from_base};
use crate::skills::hand::HandArm;
use crate::skills::motion::arms_to;
use crate::skills::pick::{PickMotion, Take};
use crate::skills::reach::{Pick, Picker};
use crate::skills::{GraspPlanner, SkillError};
use tabula_geom::parry::shape::SharedShape;
use tabula_geom::{Pose, Vec3};
use tabula_motion::MoveGroup;
use tabula_motion::group::thread_cpu;
use tabula_robot::driver::{JointState, RobotDriver};
use tabula_robot::robots::NamedRobot;

/// How near the base's front steps up to the table's edge (m).
const STEP_GAP: f64 = 0.04;

pub(super) struct Run<'a, D> {
    driver: &'a mut D,
    robot: &'a NamedRobot,
    params: &'a TidyParams,
    request: &'a TidyRequest,
    takers: Vec<HandArm>,
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
    motion: PickMotion,
    /// Where objects failed, and how often.
    tried: Attempts,
    report: TidyReport,
    decisions: Vec<f64>,
}

impl<'a, D: RobotDriver> Run<'a, D> {
    pub(super) fn new(
        driver: &'a mut D,
        robot: &'a NamedRobot,
        request: &'a TidyRequest,
        params: &'a TidyParams,
    ) -> Result<Self, TidyError> {
        let takers = HandArm::all(robot, request.arm.as_deref())?;
        let start = world_from_base(robot, driver)?;
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
        let (tried, report, decisions) = (Attempts::new(0.05), TidyReport::default(), Vec::new());
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
            motion: PickMotion {
                pregrasp: params.pregrasp,
                lift: params.lift,
                open_at_pregrasp: true,
            },
            tried,
            report,
            decisions,
        })
    }

    pub(super) fn run(mut self) -> Result<TidyReport, TidyError> {
        for frame in 0.. {
            // The arms back in before the base drives (the last table seen in the way).
            let arms = (&self.template, self.takers.as_slice());
            let table = self.table_prism.as_ref();
            arms_to(self.driver, self.robot, arms, &self.ready, table);
            match self.return_to_start() {
                Ok(()) => {}
                Err(TidyError::Driver(e)) if frame > 0 => {
                    // Stuck on the way back: what is placed stays placed.
                    self.report.stop = format!("could not drive back: {e}");
                    break;
                }
                Err(e) => return Err(e),
            }
            let _ = self.driver.look_at(self.look);
            let p = self.params;
            let eye = Observer::new(&p.camera, p.decimate, p.self_filter_padding, &p.tabletop);
            let seen = eye.observe(self.driver, self.robot)?;
            let (table, objects) = (seen.table, seen.objects);
            if frame == 0 {
                self.report.objects = objects.len();
            }
            let c0 = thread_cpu();
            let chosen = self.choose(&table, &objects);
            self.decisions.push((thread_cpu() - c0) * 1e3);
            let Some(choice) = chosen else {
                // Out of reach from here: step up to the table and look again.
                let (edge, z) = (&table.outline, table.z);
                if objects.is_empty() {
                    self.report.stop = "table clear".into();
                } else if let Some(pose) = step_up_to(self.driver, self.robot, edge, z, STEP_GAP)? {
                    self.start = pose;
                    continue;
                } else {
                    self.report.stop = "nothing left that can be taken".into();
                }
                break;
            };
            self.report.actions += 1;
            let i = choice.object;
            match self.move_one(&table, &objects, choice) {
                Ok(()) => self.report.placed += 1,
                Err((reason, message)) => self.fail(&objects[i], reason, message),
            }
        }
        self.report.decision_ms = crate::clear::Stats::of(&self.decisions);
        Ok(self.report)
    }

    /// Drives back to where the run started when the base moved.
    fn return_to_start(&mut self) -> Result<(), TidyError> {
        Ok(drive_back(self.driver, self.robot, &self.start, BACK_OFF)?)
    }

    /// The nearest object nothing stands on and not given up on that either hand can
    /// pick (see [`Picker::choose`]).
    fn choose(&mut self, table: &Table, objects: &[SeenObject]) -> Option<Pick> {
        let p = self.params;
        let takeable = |o: &SeenObject| {
            self.takers.iter().any(|t| {
                !p.grasp
                    .candidates(&o.grasp_target(), &t.hand, table.up)
                    .is_empty()
            })
        };
        let on = on_pairs(objects, table.z, &takeable);
        let me = self.start.translation.truncate();
        let mut order: Vec<usize> = (0..objects.len())
            .filter(|&i| {
                !on.iter().any(|&(_, under)| under == i)
                    && self.tried.at(objects[i].center()) < self.params.max_attempts
            })
            .collect();
        order.sort_by(|&a, &b| {
            let d = |i: usize| objects[i].rect.center.distance(me);
            d(a).total_cmp(&d(b))
        });
        self.table_prism = table.prism();
        let picker = Picker {
            robot: self.robot,
            hands: &self.takers,
            template: &self.template,
            planner: &p.grasp,
            motion: self.motion,
            clearance: p.clearance,
        };
        let state = self.driver.joint_state().ok()?;
        picker.choose(&state, (table, objects, &on), &order)
    }

    /// Takes the chosen object and has placing put it on another surface; the typed
    /// reason and message when that fails.
    fn move_one(
        &mut self,
        table: &Table,
        objects: &[SeenObject],
        pick: Pick,
    ) -> Result<(), (String, String)> {
        let p = self.params;
        let (k, mut group, i, grasp, ik) =
            (pick.hand, pick.group, pick.object, pick.grasp, pick.ik);
        let motion = self.motion;
        let t = &self.takers[k];
        let mut arm = t.manipulator((&mut *self.driver, self.robot), &mut group, table.up);
        let take = Take {
            objects,
            i,
            grasp: &grasp,
            ik,
            nudged: &[],
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
            self.put_back(k, &mut group, taken_at, table.up);
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
                self.put_back(k, &mut group, taken_at, table.up);
                Err((e.kind().to_string(), e.to_string()))
            }
        }
    }

    /// Puts the held object back down where hand `k` took it (`at`, the grasp pose):
    /// back to the start, above it, straight down, open, straight up — or opens the
    /// hand where it is when that fails.
    fn put_back(&mut self, k: usize, group: &mut MoveGroup, at: Pose, up: Vec3) {
        let back = self.return_to_start().is_ok();
        let t = &self.takers[k];
        let mut arm = t.manipulator((&mut *self.driver, self.robot), group, up);
        if !back || arm.put_down(&at, self.params.pregrasp).is_err() {
            let _ = self.driver.open(&t.gripper.name);
        }
    }

    fn fail(&mut self, o: &SeenObject, reason: String, message: String) {
        let at = o.center();
        self.tried.failed(at);
        self.report.failed.push(Failure {
            object: at.to_array(),
            reason,
            message,
        });
    }
}
