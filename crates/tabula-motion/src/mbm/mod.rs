//! MotionBenchMaker (Chamzas et al. 2022) on tabula: every problem of a set of MoveIt
//! scene + request pairs planned on one world per group, built once and cloned per
//! problem; planning time is the CPU time of the planning thread for plan + shortcut,
//! the way VAMP and OMPL report theirs. Paths are kept for outside checking.

mod load;

pub use load::{MAX_FILES, MbmProblem, load};

use crate::group::thread_cpu;
use crate::moveit::MoveItError;
use crate::rrt::{PlanError, PlannerParams, fitted_world, rrt_connect, shortcut};
use crate::world::CollisionWorld;
use rand::SeedableRng;
use rand_chacha::ChaCha8Rng;
use std::collections::HashMap;

/// Why a problem set could not be read.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum MbmError {
    #[error("{0}")]
    Io(String),
    #[error("no MotionBenchMaker problems (sceneNNNN.yaml + requestNNNN.yaml) in {0}")]
    Empty(String),
    #[error("{0}")]
    Unpaired(String),
    #[error("{0}")]
    Parse(String),
    #[error("too large: {0}")]
    TooLarge(String),
}

/// What became of one problem.
#[derive(Debug, Clone, serde::Serialize)]
#[serde(tag = "status", rename_all = "snake_case")]
pub enum Outcome {
    /// A certified path: CPU µs for planning and for shortcutting, and the path.
    Solved {
        plan_us: f64,
        shortcut_us: f64,
        /// Configurations checked (planning and shortcutting).
        checks: u64,
        path: Vec<Vec<f64>>,
    },
    /// The start or the goal touches something on the exact geometry: no path exists.
    Invalid { why: String },
    /// A valid problem left unsolved (time limit, or start/goal only within the padding).
    Unsolved { why: String },
    /// The scene or request does not fit the robot.
    Error { why: String },
}

/// One problem's result.
#[derive(Debug, Clone, serde::Serialize)]
pub struct ProblemResult {
    pub set: String,
    pub index: u32,
    pub joint_names: Vec<String>,
    #[serde(flatten)]
    pub outcome: Outcome,
}

/// Plans every problem. `world_for_group` builds the robot's empty world for a planning
/// group (called once per group); `each` sees every result as it is made.
pub fn run(
    problems: &[MbmProblem],
    params: &PlannerParams,
    mut world_for_group: impl FnMut(&str) -> Result<CollisionWorld, String>,
    mut each: impl FnMut(&ProblemResult),
) -> Vec<ProblemResult> {
    let mut worlds: HashMap<String, Result<CollisionWorld, String>> = HashMap::new();
    let mut out = Vec::with_capacity(problems.len());
    for p in problems {
        let base = worlds
            .entry(p.request.group.clone())
            .or_insert_with(|| world_for_group(&p.request.group));
        let (joint_names, outcome) = match base {
            Ok(base) => (base.chain.joint_names.clone(), solve(base, p, params)),
            Err(why) => (Vec::new(), Outcome::Error { why: why.clone() }),
        };
        let result = ProblemResult {
            set: p.set.clone(),
            index: p.index,
            joint_names,
            outcome,
        };
        each(&result);
        out.push(result);
    }
    out
}

/// One problem on a clone of `base`: the scene and the start state applied (not timed),
/// then RRT-Connect and shortcutting timed together on this thread's CPU clock.
fn solve(base: &CollisionWorld, p: &MbmProblem, params: &PlannerParams) -> Outcome {
    let mut world = base.clone();
    let setup = |e: MoveItError| Outcome::Error { why: e.to_string() };
    if let Err(e) = p.scene.apply(&mut world) {
        return setup(e);
    }
    let problem = match p.request.problem(&mut world) {
        Ok(problem) => problem,
        Err(e) => return setup(e),
    };
    if !problem.pose_goals.is_empty() {
        return Outcome::Error {
            why: "pose goals are not benchmarked (MotionBenchMaker's are joint goals)".into(),
        };
    }
    for (what, q) in std::iter::once(("start", &problem.start))
        .chain(problem.joint_goals.iter().map(|g| ("goal", g)))
    {
        if let Ok(Some((a, b))) = world.exact_collision(q) {
            return Outcome::Invalid {
                why: format!("{what}: {}", world.why_invalid(q, &(a, b))),
            };
        }
    }
    let t0 = thread_cpu();
    // Timed: a copy with a thinner padding when an endpoint is within it.
    let world = fitted_world(&world, &problem.start, &problem.joint_goals, params);
    let checks0 = world.checks();
    let planned = rrt_connect(&world, &problem.start, &problem.joint_goals, params);
    let t1 = thread_cpu();
    match planned {
        Ok(mut path) => {
            let mut rng = ChaCha8Rng::seed_from_u64(params.seed);
            shortcut(&world, &mut path, params, &mut rng);
            let t2 = thread_cpu();
            Outcome::Solved {
                plan_us: (t1 - t0) * 1e6,
                shortcut_us: (t2 - t1) * 1e6,
                checks: world.checks() - checks0,
                path: path.waypoints,
            }
        }
        Err(
            e @ (PlanError::StartInvalid(_) | PlanError::GoalInvalid(_) | PlanError::NoValidGoal),
        ) => Outcome::Unsolved {
            why: format!("{e} (valid without the padding)"),
        },
        Err(e) => Outcome::Unsolved { why: e.to_string() },
    }
}

/// Median, 95th percentile and maximum.
#[derive(Debug, Clone, Copy, Default, serde::Serialize)]
pub struct Spread {
    pub median: f64,
    pub p95: f64,
    pub max: f64,
}

impl Spread {
    pub fn of(mut v: Vec<f64>) -> Self {
        if v.is_empty() {
            return Self {
                median: f64::NAN,
                p95: f64::NAN,
                max: f64::NAN,
            };
        }
        v.sort_by(f64::total_cmp);
        let at = |q: f64| v[((v.len() - 1) as f64 * q).round() as usize];
        Self {
            median: at(0.5),
            p95: at(0.95),
            max: v[v.len() - 1],
        }
    }
}

/// Counts and times of a group of results.
#[derive(Debug, Clone, serde::Serialize)]
pub struct Tally {
    pub total: usize,
    /// Problems whose start and goal are collision-free on the exact geometry.
    pub valid: usize,
    pub solved: usize,
    pub invalid: usize,
    pub errors: usize,
    /// Plan + shortcut, CPU µs, over solved problems.
    pub time_us: Spread,
    /// Planning alone (before shortcutting).
    pub plan_us: Spread,
    /// Configurations checked per solved problem.
    pub checks: Spread,
}

impl Tally {
    pub fn of<'a>(results: impl IntoIterator<Item = &'a ProblemResult>) -> Self {
        let (mut total, mut solved, mut invalid, mut errors) = (0, 0, 0, 0);
        let (mut time, mut plan, mut counts) = (Vec::new(), Vec::new(), Vec::new());
        for r in results {
            total += 1;
            match &r.outcome {
                Outcome::Solved {
                    plan_us,
                    shortcut_us,
                    checks,
                    ..
                } => {
                    solved += 1;
                    counts.push(*checks as f64);
                    time.push(plan_us + shortcut_us);
                    plan.push(*plan_us);
                }
                Outcome::Invalid { .. } => invalid += 1,
                Outcome::Error { .. } => errors += 1,
                Outcome::Unsolved { .. } => {}
            }
        }
        Self {
            total,
            valid: total - invalid - errors,
            solved,
            invalid,
            errors,
            time_us: Spread::of(time),
            plan_us: Spread::of(plan),
            checks: Spread::of(counts),
        }
    }
}

/// The whole run: all problems, and per set.
#[derive(Debug, Clone, serde::Serialize)]
pub struct MbmReport {
    #[serde(flatten)]
    pub all: Tally,
    pub sets: Vec<(String, Tally)>,
    /// Every problem not solved, with why.
    pub not_solved: Vec<(String, u32, String)>,
}

impl MbmReport {
    pub fn of(results: &[ProblemResult]) -> Self {
        let mut names: Vec<&str> = results.iter().map(|r| r.set.as_str()).collect();
        names.dedup();
        let sets = names
            .iter()
            .map(|s| {
                (
                    s.to_string(),
                    Tally::of(results.iter().filter(|r| r.set == *s)),
                )
            })
            .collect();
        let not_solved = results
            .iter()
            .filter_map(|r| match &r.outcome {
                Outcome::Solved { .. } => None,
                Outcome::Invalid { why } | Outcome::Unsolved { why } | Outcome::Error { why } => {
                    Some((r.set.clone(), r.index, why.clone()))
                }
            })
            .collect();
        Self {
            all: Tally::of(results),
            sets,
            not_solved,
        }
    }
}
