//! The clearing loop: a frame in, one action out, until the table is clear.

use super::decide::{Decider, Decision};
use super::left::left_objects;
use super::predicates::{Geometry, TableView};
use super::track::{Track, split_merged, track};
use super::{
    ActionKind, ClearError, ClearEvent, ClearParams, ClearReport, ClearRequest, DOMAIN,
    FrameReport, SeenObject, Table,
};
use crate::skills::Hand;
use tabula_motion::MoveGroup;
use tabula_motion::group::thread_cpu;
use tabula_pddl::Domain;
use tabula_robot::description::Gripper;
use tabula_robot::driver::{JointState, RobotDriver};
use tabula_robot::robots::NamedRobot;

/// A chosen action.
pub(super) struct Act {
    pub(super) i: usize,
    pub(super) kind: ActionKind,
    pub(super) ik: Vec<f64>,
    pub(super) nudged: Vec<usize>,
}

/// What a run sets up once and carries from frame to frame.
pub(super) struct Run<'a, D> {
    pub(super) driver: &'a mut D,
    pub(super) robot: &'a NamedRobot,
    pub(super) request: &'a ClearRequest,
    pub(super) params: &'a ClearParams,
    pub(super) gripper: Gripper,
    pub(super) hand: Hand,
    pub(super) domain: Domain,
    pub(super) group: MoveGroup,
    /// Out of the camera's view between actions: the arm's tucked pose, else where it
    /// started.
    pub(super) home: Vec<f64>,
    /// Perception runs on one thread, so its CPU time is all of the work.
    pub(super) single: rayon::ThreadPool,
    pub(super) tracks: Vec<Track>,
    pub(super) report: ClearReport,
}

/// Clears the table the driver's camera sees. `watch` is told before and after every
/// action (the simulator's harness judges collisions with it); pass `|_, _| {}` when
/// nobody watches.
pub fn clear<D: RobotDriver>(
    driver: &mut D,
    robot: &NamedRobot,
    request: &ClearRequest,
    params: &ClearParams,
    watch: &mut dyn FnMut(&mut D, ClearEvent<'_>),
) -> Result<ClearReport, ClearError> {
    let mut run = Run::new(driver, robot, request, params)?;
    let mut no_plan_run = 0usize;
    let mut max_actions = request.max_actions;
    loop {
        let frame_no = run.report.frames.len();
        let Seen {
            table,
            objects,
            state,
            frame: mut fr,
        } = match run.perceive()? {
            Ok(x) => x,
            Err(e) if frame_no == 0 => return Err(e),
            Err(e) => {
                run.report.stop = format!("lost the table: {e}");
                break;
            }
        };
        if frame_no == 0 {
            run.report.objects = objects.len();
            max_actions.get_or_insert(3 * objects.len() + 5);
        }
        if objects.is_empty() {
            run.report.stop = "table clear".into();
            break;
        }
        if run.report.actions >= max_actions.unwrap_or(usize::MAX) {
            run.stop("action limit".into(), &objects, None);
            break;
        }
        let (chosen, geometry) = run.decide(&objects, &table, &state, &mut fr);
        run.report.ik_backtracks += fr.ik_backtracks;
        log_decision(frame_no, &fr);
        run.report.frames.push(fr);
        let act = match chosen {
            Decision::Act(i, kind, ik, nudged) => Act {
                i,
                kind,
                ik,
                nudged,
            },
            Decision::NothingRemovable => {
                run.stop(
                    "nothing left that can be removed".into(),
                    &objects,
                    Some(&geometry),
                );
                break;
            }
            Decision::NoPlan => {
                run.report.no_plan_frames += 1;
                no_plan_run += 1;
                if no_plan_run >= params.max_no_plan_frames {
                    run.stop("no plan".into(), &objects, Some(&geometry));
                    break;
                }
                continue;
            }
        };
        no_plan_run = 0;
        let step = Step {
            frame_no,
            objects: &objects,
            geometry: &geometry,
            table: &table,
        };
        if let Err(e) = run.act(&step, act, watch) {
            run.stop(format!("driver failed: {e}"), &objects, None);
            break;
        }
    }
    run.report.summarise();
    Ok(run.report)
}

fn log_decision(frame_no: usize, fr: &FrameReport) {
    tracing::info!(
        frame = frame_no,
        objects = fr.objects,
        decision_ms = fr.decision_ms,
        perception_ms = fr.perception_ms,
        predicates_ms = fr.predicates_ms,
        planning_ms = fr.planning_ms,
        ik_ms = fr.ik_ms,
        plan = fr.plan.join(" "),
        "clear: decision"
    );
}

/// What a frame shows: the table, its objects (tracked), the robot's state, and the
/// frame's report so far.
struct Seen {
    table: Table,
    objects: Vec<SeenObject>,
    state: JointState,
    frame: FrameReport,
}

/// One frame's view of the table, for executing its action.
pub(super) struct Step<'a> {
    pub(super) frame_no: usize,
    pub(super) objects: &'a [SeenObject],
    pub(super) geometry: &'a Geometry,
    pub(super) table: &'a Table,
}

impl<'a, D: RobotDriver> Run<'a, D> {
    /// Ends the loop for `reason` with `objects` still on the table: the report says
    /// why it stopped and why each object stays (see [`left_objects`]).
    fn stop(&mut self, reason: String, objects: &[SeenObject], geometry: Option<&Geometry>) {
        self.report.left = left_objects(objects, geometry, &self.tracks, self.params, &reason);
        self.report.stop = reason;
    }

    fn new(
        driver: &'a mut D,
        robot: &'a NamedRobot,
        request: &'a ClearRequest,
        params: &'a ClearParams,
    ) -> Result<Self, ClearError> {
        let (arm, gripper) = crate::skills::arm_with_gripper(robot, request.arm.as_deref())?;
        params.validate()?;
        if !(request.drop_point.is_finite() && request.drop_spread.is_finite()) {
            return Err(ClearError::Params("the drop point must be finite".into()));
        }
        let hand = Hand::new(robot, &gripper)?;
        let domain =
            tabula_pddl::parse_domain(DOMAIN).map_err(|e| ClearError::Planner(e.to_string()))?;
        let state = driver.joint_state()?;
        let world_from_root = driver.world_from_root()?;
        // The hand and what it holds keep the predicates' clearance, not the arm's
        // padding: what the predicates call free, the planner must too.
        let mut motion = params.motion.clone();
        for link in [
            &gripper.palm,
            &gripper.fingers[0],
            &gripper.fingers[1],
            &gripper.tool_link,
        ] {
            motion
                .world
                .link_padding
                .entry(link.clone())
                .or_insert(params.clearance);
        }
        let robot_error = |e: tabula_motion::MoveError| ClearError::Robot(e.to_string());
        // The allowed-collision matrix is sampled once per run (setup, not a decision).
        let mut group = MoveGroup::new(robot, &arm.name, &state, world_from_root, motion)
            .map_err(robot_error)?;
        for (i, (name, shape, pose)) in request.obstacles.iter().enumerate() {
            group
                .add_object(&format!("fixed{i}:{name}"), shape.clone(), *pose)
                .map_err(robot_error)?;
        }
        let start = group.arm_values(&state);
        let home: Vec<f64> = group
            .joint_names()
            .iter()
            .zip(&start)
            .map(|(n, s)| arm.tucked.get(n).copied().unwrap_or(*s))
            .collect();
        let single = rayon::ThreadPoolBuilder::new()
            .num_threads(1)
            .build()
            .map_err(|e| ClearError::Perception(e.to_string()))?;
        Ok(Self {
            driver,
            robot,
            request,
            params,
            gripper,
            hand,
            domain,
            group,
            home,
            single,
            tracks: Vec::new(),
            report: ClearReport::default(),
        })
    }

    /// Captures a frame and perceives the table and its objects, tracked; `Err` when
    /// the driver fails, `Ok(Err)` when the frame shows no table.
    fn perceive(&mut self) -> Result<Result<Seen, ClearError>, ClearError> {
        let (robot, params) = (self.robot, self.params);
        let observer = params.observer();
        let captured = observer.capture(self.driver)?;
        let observed = self.single.install(|| observer.perceive(robot, &captured));
        if let Ok(o) = &observed
            && tracing::enabled!(tracing::Level::DEBUG)
        {
            tracing::debug!(
                "perception CPU {:.1} ms, of which transform + self-filter {:.1} ms",
                o.cpu_s * 1e3,
                o.filter_cpu_s * 1e3
            );
        }
        let state = captured.state;
        Ok(observed
            .map_err(|e| ClearError::Perception(e.to_string()))
            .map(|o| {
                let (table, mut objects, perception) = (o.table, o.objects, o.cpu_s);
                split_merged(&mut objects, &self.tracks);
                track(
                    &mut objects,
                    &mut self.tracks,
                    params.track_radius,
                    params.push_jam_share,
                );
                let frame = FrameReport {
                    objects: objects.len(),
                    perception_ms: perception * 1e3,
                    ..FrameReport::default()
                };
                Seen {
                    table,
                    objects,
                    state,
                    frame,
                }
            }))
    }

    /// Predicates, plan, IK of the first action with backtracking; the fallbacks when
    /// the seed's actions cannot go on. Times go into `fr`.
    fn decide(
        &mut self,
        objects: &[SeenObject],
        table: &Table,
        state: &JointState,
        fr: &mut FrameReport,
    ) -> (Decision, Geometry) {
        let view = TableView {
            objects,
            table,
            hand: &self.hand,
            params: self.params,
        };
        let c1 = thread_cpu();
        let mut geometry = view.predicates(false);
        let solo_predicates_ms = (thread_cpu() - c1) * 1e3;
        fr.predicates_ms = solo_predicates_ms;
        let c2 = thread_cpu();
        let mut decider = Decider {
            objects,
            tracks: &self.tracks,
            group: &mut self.group,
            robot: self.robot,
            state,
            table_z: table.z,
            params: self.params,
            frame: fr,
        };
        // The seed's actions first; chain pushes only when those cannot go on.
        let mut chosen = decider.decide(&geometry, &self.domain, &mut self.report);
        if matches!(chosen, Decision::NothingRemovable) {
            let c = thread_cpu();
            let chain = view.predicates(true);
            decider.frame.predicates_ms += (thread_cpu() - c) * 1e3;
            chosen = decider.decide_chain(&chain);
            // A chain push that frees no grasp is a guess; parting what may be two
            // objects seen as one is a better one. A split push replaces one of the
            // seed's pushes in the seed's geometry.
            let fruitless = match chosen {
                Decision::Act(i, ActionKind::Push(k), ..) => chain.pushes[i][k].gain == 0,
                _ => true,
            };
            let split = if fruitless {
                decider.decide_split(&view, &mut geometry)
            } else {
                Decision::NothingRemovable
            };
            if !matches!(split, Decision::NothingRemovable) {
                chosen = split;
            } else if matches!(chosen, Decision::NothingRemovable) && self.params.nudge_depth > 0.0
            {
                // A nudge grasp is one of the seed's grasps: it keeps the seed's geometry.
                chosen = decider.decide_nudge(&geometry, &self.hand, table);
            } else {
                geometry = chain;
            }
        }
        // Chain predicates (when needed) ran inside this span: counted as predicates.
        let decision_total = (thread_cpu() - c2) * 1e3;
        let chain_predicates_ms = fr.predicates_ms - solo_predicates_ms;
        fr.planning_ms = decision_total - fr.ik_ms - chain_predicates_ms;
        fr.decision_ms = fr.perception_ms + solo_predicates_ms + decision_total;
        (chosen, geometry)
    }
}
