//! RRT-Connect in joint space (Kuffner & LaValle 2000, as OMPL's default in MoveIt),
//! random shortcutting, and time parameterisation under velocity and acceleration limits.

mod edge;
mod grow;
mod shortcut;
mod timing;

pub use edge::{segment_certified, segment_valid, segment_valid_advancing, spacing_certifies};
pub use shortcut::shortcut;
pub use timing::{
    MAX_TRAJECTORY_SAMPLES, Trajectory, TrajectoryTooLong, time_parameterize,
    time_parameterize_along,
};

use crate::world::CollisionWorld;
use std::time::{Duration, Instant};
use tabula_geom::input::{Validate, check_in};

/// Planner parameters; defaults follow the seed's use of RRT-Connect (SPEC §6: 1 s limit).
#[derive(Debug, Clone, serde::Deserialize, serde::Serialize)]
#[serde(default, deny_unknown_fields)]
pub struct PlannerParams {
    /// Time limit (s), SPEC §6.
    pub timeout_s: f64,
    /// Longest tree extension (rad, max over joints).
    pub range: f64,
    /// Edge checking resolution (rad, max over joints).
    pub resolution: f64,
    /// Random shortcut attempts on the found path.
    pub shortcut_attempts: usize,
    pub seed: u64,
    /// Dynamic-domain sampling (Yershova et al. 2005; VAMP's RRT-Connect): a node whose
    /// extension failed takes samples only within a radius of it (rad, Euclidean), so
    /// nodes against obstacles stop drawing the tree into them.
    pub dynamic_domain: bool,
    /// The radius a node gets at its first failed extension (rad, Euclidean).
    pub domain_radius: f64,
    /// The least the radius shrinks to after further failures (rad, Euclidean).
    pub domain_min_radius: f64,
    /// Each success or failure grows or shrinks the radius by this fraction.
    pub domain_alpha: f64,
    /// Grow the smaller tree while one is over twice the other's size (VAMP's balance).
    pub balance: bool,
    /// A start or goal that is clear of everything but within the padding (a grasp
    /// millimetres from its object) is planned for in a world whose padding is halved
    /// until it fits, at most [`PADDING_HALVINGS`] times: the path is still certified
    /// free of contact, with a thinner margin. Off, such an endpoint is refused.
    pub shrink_padding_to_endpoints: bool,
}

impl Default for PlannerParams {
    fn default() -> Self {
        Self {
            timeout_s: 1.0,
            range: 0.6,
            resolution: 0.02,
            shortcut_attempts: 50,
            seed: 0,
            dynamic_domain: true,
            domain_radius: 4.0,
            domain_min_radius: 1.0,
            domain_alpha: 1e-4,
            balance: true,
            shrink_padding_to_endpoints: false,
        }
    }
}

/// Why planning gave no path.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum PlanError {
    #[error("the start is invalid: {0}")]
    StartInvalid(String),
    #[error("the goal is invalid: {0}")]
    GoalInvalid(String),
    #[error("no goal: every goal candidate is invalid")]
    NoValidGoal,
    #[error("no path found within {0:.3} s")]
    Timeout(f64),
    #[error("{0}")]
    World(String),
}

/// A collision-free path of waypoints (joint space, chain order).
#[derive(Debug, Clone)]
pub struct Path {
    pub waypoints: Vec<Vec<f64>>,
    /// Planning time (s), tree sizes.
    pub planning_time: f64,
    pub tree_nodes: usize,
}

impl Path {
    /// Joint-space length (sum of Euclidean segment lengths).
    pub fn length(&self) -> f64 {
        self.waypoints.windows(2).map(|w| dist(&w[0], &w[1])).sum()
    }
}

fn dist(a: &[f64], b: &[f64]) -> f64 {
    a.iter()
        .zip(b)
        .map(|(x, y)| (x - y) * (x - y))
        .sum::<f64>()
        .sqrt()
}

fn linf(a: &[f64], b: &[f64]) -> f64 {
    a.iter()
        .zip(b)
        .map(|(x, y)| (x - y).abs())
        .fold(0.0, f64::max)
}

/// How many times [`fitted_world`] may halve the padding (to 1/64 of it).
pub const PADDING_HALVINGS: usize = 6;

/// The world to plan in: `world` itself, or — with `shrink_padding_to_endpoints`, when
/// the start or every goal is within the padding but clear of contact — a copy whose
/// padding is halved until the start and a goal fit. Plan and shortcut in it alike.
pub fn fitted_world<'a>(
    world: &'a CollisionWorld,
    start: &[f64],
    goals: &[Vec<f64>],
    p: &PlannerParams,
) -> std::borrow::Cow<'a, CollisionWorld> {
    use std::borrow::Cow;
    let fits = |w: &CollisionWorld| w.is_valid(start) && goals.iter().any(|g| w.is_valid(g));
    if !p.shrink_padding_to_endpoints || fits(world) {
        return Cow::Borrowed(world);
    }
    let exact = |q: &[f64]| matches!(world.exact_collision(q), Ok(None));
    if !exact(start) || !goals.iter().any(|g| exact(g)) {
        return Cow::Borrowed(world);
    }
    let mut thinner = world.clone();
    for _ in 0..PADDING_HALVINGS {
        thinner.scale_padding(0.5);
        if fits(&thinner) {
            return Cow::Owned(thinner);
        }
    }
    Cow::Borrowed(world)
}

/// Plans from `start` to any of `goals` (several goals: e.g. IK solutions of a pose).
///
/// Lazy in the edge checks: the trees grow with edges checked at four times the world's
/// step displacement, and only the final path is certified; if it fails there (a thin
/// obstacle between two coarse samples, or an edge grazing one closer than
/// certification can prove clear), planning runs again with denser checks and a new
/// seed in the time that is left.
pub fn rrt_connect(
    world: &CollisionWorld,
    start: &[f64],
    goals: &[Vec<f64>],
    p: &PlannerParams,
) -> Result<Path, PlanError> {
    let t0 = Instant::now();
    if let Some(c) = world
        .first_collision(start)
        .map_err(|e| PlanError::StartInvalid(e.to_string()))?
    {
        return Err(PlanError::StartInvalid(world.why_invalid(start, &c)));
    }
    let mut valid_goals = Vec::new();
    let mut last_problem = None;
    for g in goals {
        match world.first_collision(g) {
            Ok(None) => valid_goals.push(g.clone()),
            Ok(Some(c)) => last_problem = Some(world.why_invalid(g, &c)),
            Err(e) => return Err(PlanError::GoalInvalid(e.to_string())),
        }
    }
    if valid_goals.is_empty() {
        return Err(match (goals.len(), last_problem) {
            (1, Some(why)) => PlanError::GoalInvalid(why),
            _ => PlanError::NoValidGoal,
        });
    }
    // Straight line first, checked exactly: in open space that is the answer.
    for g in &valid_goals {
        if !edge::refused_early(world, start, g, p.resolution)
            && segment_valid_advancing(world, start, g, p.resolution)
        {
            return Ok(Path {
                waypoints: vec![start.to_vec(), g.clone()],
                planning_time: t0.elapsed().as_secs_f64(),
                tree_nodes: 2,
            });
        }
    }
    let deadline = t0 + Duration::from_secs_f64(p.timeout_s.max(0.0));
    let fine = world.params.max_step_displacement;
    // Trees grow on coarse checks; only the path found is certified. A contact missed
    // between coarse samples sends the search back with denser ones.
    let spacings: &[f64] = if spacing_certifies(world) {
        &[4.0 * fine, fine]
    } else {
        &[4.0 * fine, fine, fine / 4.0]
    };
    // Each round grows new trees from its own seed: a path that failed certification
    // would otherwise be found again the same way. Rounds go on until the deadline.
    for round in 0u64.. {
        if Instant::now() >= deadline {
            break;
        }
        let spacing = spacings[(round as usize).min(spacings.len() - 1)];
        let seeded = PlannerParams {
            seed: p.seed.wrapping_add(round),
            ..p.clone()
        };
        let Some(mut path) = grow::grow(world, start, &valid_goals, &seeded, spacing, deadline)
        else {
            break;
        };
        let verified = path
            .waypoints
            .windows(2)
            .all(|w| segment_valid_advancing(world, &w[0], &w[1], p.resolution));
        if verified {
            path.planning_time = t0.elapsed().as_secs_f64();
            return Ok(path);
        }
    }
    Err(PlanError::Timeout(p.timeout_s))
}

impl Validate for PlannerParams {
    fn check(&self, at: &str) -> Result<(), String> {
        check_in(at, "timeout_s", self.timeout_s, 1e-6, 1e6)?;
        // Steps under a milliradian never reach the goal within any time limit, and a
        // checking resolution under 1e-5 rad is millions of checks per edge.
        check_in(at, "range", self.range, 1e-3, 1e3)?;
        check_in(at, "resolution", self.resolution, 1e-5, 1.0)?;
        check_in(at, "domain_radius", self.domain_radius, 1e-3, 1e3)?;
        check_in(
            at,
            "domain_min_radius",
            self.domain_min_radius,
            1e-3,
            self.domain_radius,
        )?;
        // Under 1e-9 the radius would never change within a run: a typo, not a setting.
        check_in(at, "domain_alpha", self.domain_alpha, 1e-9, 0.5)
    }
}
