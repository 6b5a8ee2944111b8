//! RRT-Connect in joint space (Kuffner & LaValle 2000, as OMPL's default in MoveIt),
//! random shortcutting, and time parameterisation under velocity and acceleration limits.

use crate::world::CollisionWorld;
use rand::{RngExt, SeedableRng};
use rand_chacha::ChaCha8Rng;
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
}

impl Default for PlannerParams {
    fn default() -> Self {
        Self {
            timeout_s: 1.0,
            range: 0.6,
            resolution: 0.02,
            shortcut_attempts: 50,
            seed: 0,
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

/// True when the straight segment a→b is valid: configurations are checked at most
/// `resolution` rad apart (max over joints) and close enough that no point of the robot
/// moves more than the world's `max_step_displacement` between two — so with that much
/// padding, nothing in between can touch. Checked in bisection order so a collision in
/// the middle is found early.
pub fn segment_valid(world: &CollisionWorld, a: &[f64], b: &[f64], resolution: f64) -> bool {
    segment_valid_spaced(world, a, b, resolution, world.params.max_step_displacement)
}

/// Whether edges are checked at fixed spacing (nothing moves more than the world's
/// `max_step_displacement` between two configurations, the padding covering the gaps),
/// or — when the padding is under half that step (an exact world: MotionBenchMaker's
/// grasps sit millimetres from the object) — certified by conservative advancement.
/// The tasks' 8 mm padding with a 10 mm step stays on fixed spacing, as it always has.
pub fn spacing_certifies(world: &CollisionWorld) -> bool {
    world.max_padding() >= 0.5 * world.params.max_step_displacement
}

/// Whether the straight segment a→b is valid *everywhere*, not only at its samples:
/// fixed spacing where the padding covers the gaps ([`spacing_certifies`]), else
/// conservative advancement.
pub fn segment_certified(world: &CollisionWorld, a: &[f64], b: &[f64], resolution: f64) -> bool {
    if spacing_certifies(world) {
        segment_valid(world, a, b, resolution)
    } else {
        segment_valid_advancing(world, a, b, resolution)
    }
}

/// Most configurations one certification may measure: an edge that needs more is
/// treated as blocked.
const MAX_ADVANCES: usize = 20_000;

/// Conservative advancement along a→b, in bisection order: the margin `m` measured at
/// a configuration (in the segment's length, [`CollisionWorld::time_margin`]: each
/// pair's distance beyond the padding over how fast that pair can close) keeps the
/// stretch within `m` of it clear by the padding, so a stretch whose two ends' margins
/// together cover its length is certified whole; any other is split at its middle.
/// Long stretches of open space are certified in a few queries, a contact in the
/// middle is met early, and the whole segment keeps the padding, not only its samples.
/// Near an obstacle the stretches shrink; one with less than 10 µm of motion in its
/// margins is checked at fixed spacing where the padding certifies that, and is
/// blocked otherwise.
pub fn segment_valid_advancing(
    world: &CollisionWorld,
    a: &[f64],
    b: &[f64],
    resolution: f64,
) -> bool {
    let spaced_fallback = spacing_certifies(world);
    let pad = world.max_padding();
    let rates = world.sweep_rates(a, b);
    let fastest = rates.fastest();
    // Margins beyond 10 cm of motion buy little but cost distance queries.
    let cap = 0.1;
    let mut q = a.to_vec();
    let mut margin_at = |t: f64| -> Option<f64> {
        for k in 0..a.len() {
            q[k] = a[k] + (b[k] - a[k]) * t;
        }
        let m = world.time_margin(&q, &rates, pad, cap).ok()?;
        (m > 0.0).then_some(m)
    };
    let (Some(ma), Some(mb)) = (margin_at(0.0), margin_at(1.0)) else {
        return false;
    };
    let mut pending = std::collections::VecDeque::from([(0.0, 1.0, ma, mb)]);
    let mut measured = 2;
    while let Some((t0, t1, m0, m1)) = pending.pop_front() {
        if t1 - t0 <= m0 + m1 {
            continue;
        }
        if (m0 + m1) * fastest < 1e-5 || measured >= MAX_ADVANCES {
            // Hugging an obstacle: where the padding certifies fixed spacing, check the
            // stretch that way; otherwise it is blocked.
            if !spaced_fallback {
                return false;
            }
            let at =
                |t: f64| -> Vec<f64> { a.iter().zip(b).map(|(x, y)| x + (y - x) * t).collect() };
            if !segment_valid(world, &at(t0), &at(t1), resolution) {
                return false;
            }
            continue;
        }
        let tm = 0.5 * (t0 + t1);
        let Some(mm) = margin_at(tm) else {
            return false;
        };
        measured += 1;
        pending.push_back((t0, tm, m0, mm));
        pending.push_back((tm, t1, mm, m1));
    }
    true
}

/// 1..=n in van der Corput order (by their bits reversed: n/2 first, then the
/// quarters, …), generated without sorting.
fn van_der_corput(n: usize) -> impl Iterator<Item = usize> {
    let n = n.min(u32::MAX as usize >> 1) as u32;
    let bits = 32 - n.leading_zeros();
    (0..1u64 << bits)
        .map(move |j| {
            (j as u32)
                .reverse_bits()
                .checked_shr(32 - bits)
                .unwrap_or(0) as usize
        })
        .filter(move |&i| (1..=n as usize).contains(&i))
}

fn segment_valid_spaced(
    world: &CollisionWorld,
    a: &[f64],
    b: &[f64],
    resolution: f64,
    displacement: f64,
) -> bool {
    let by_angle = linf(a, b) / resolution.max(1e-9);
    let by_motion = world.displacement_bound(a, b) / displacement.max(1e-4);
    let steps = by_angle.max(by_motion).ceil() as usize;
    if steps <= 1 {
        return world.is_valid(b);
    }
    let mut q = vec![0.0; a.len()];
    for i in van_der_corput(steps) {
        let t = i as f64 / steps as f64;
        for k in 0..a.len() {
            q[k] = a[k] + (b[k] - a[k]) * t;
        }
        if !world.is_valid(&q) {
            return false;
        }
    }
    true
}

struct Tree {
    nodes: Vec<Vec<f64>>,
    parent: Vec<usize>,
}

impl Tree {
    fn nearest(&self, q: &[f64]) -> usize {
        let mut best = (f64::INFINITY, 0);
        for (i, n) in self.nodes.iter().enumerate() {
            let d: f64 = n.iter().zip(q).map(|(x, y)| (x - y) * (x - y)).sum();
            if d < best.0 {
                best = (d, i);
            }
        }
        best.1
    }

    fn path_to_root(&self, mut i: usize) -> Vec<Vec<f64>> {
        let mut out = vec![self.nodes[i].clone()];
        while self.parent[i] != usize::MAX {
            i = self.parent[i];
            out.push(self.nodes[i].clone());
        }
        out
    }
}

enum Extend {
    Trapped,
    Advanced(usize),
    Reached(usize),
}

fn extend(
    world: &CollisionWorld,
    tree: &mut Tree,
    q: &[f64],
    p: &PlannerParams,
    spacing: f64,
) -> Extend {
    let near = tree.nearest(q);
    let from = tree.nodes[near].clone();
    let d = linf(&from, q);
    let (target, reached) = if d <= p.range {
        (q.to_vec(), true)
    } else {
        let s = p.range / d;
        (
            from.iter().zip(q).map(|(a, b)| a + (b - a) * s).collect(),
            false,
        )
    };
    if !segment_valid_spaced(world, &from, &target, p.resolution, spacing) {
        return Extend::Trapped;
    }
    tree.nodes.push(target);
    tree.parent.push(near);
    let i = tree.nodes.len() - 1;
    if reached {
        Extend::Reached(i)
    } else {
        Extend::Advanced(i)
    }
}

/// Plans from `start` to any of `goals` (several goals: e.g. IK solutions of a pose).
///
/// Lazy in the edge checks: the trees grow with edges checked at four times the world's
/// step displacement, and only the final path is checked at the full density; if it
/// fails there (rare: a thin obstacle between two coarse samples), planning runs again
/// with full-density checks in the time that is left.
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
        if segment_valid_advancing(world, start, g, p.resolution) {
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
    for &spacing in spacings {
        match grow(world, start, &valid_goals, p, spacing, deadline) {
            Some(mut path) => {
                let verified = path
                    .waypoints
                    .windows(2)
                    .all(|w| segment_certified(world, &w[0], &w[1], p.resolution));
                if verified {
                    path.planning_time = t0.elapsed().as_secs_f64();
                    return Ok(path);
                }
            }
            None => break,
        }
    }
    Err(PlanError::Timeout(p.timeout_s))
}

/// The RRT-Connect loop with edges checked at `spacing`; `None` at the deadline.
fn grow(
    world: &CollisionWorld,
    start: &[f64],
    goals: &[Vec<f64>],
    p: &PlannerParams,
    spacing: f64,
    deadline: Instant,
) -> Option<Path> {
    // Straight line first: in open space that is the answer.
    for g in goals {
        if segment_valid_spaced(world, start, g, p.resolution, spacing) {
            return Some(Path {
                waypoints: vec![start.to_vec(), g.clone()],
                planning_time: 0.0,
                tree_nodes: 2,
            });
        }
    }
    let mut rng = ChaCha8Rng::seed_from_u64(p.seed);
    let mut a = Tree {
        nodes: vec![start.to_vec()],
        parent: vec![usize::MAX],
    };
    let mut b = Tree {
        nodes: goals.to_vec(),
        parent: vec![usize::MAX; goals.len()],
    };
    let mut a_is_start = true;
    let chain = &world.chain;
    let mut q = vec![0.0; start.len()];
    let mut iter = 0usize;
    loop {
        iter += 1;
        if iter.is_multiple_of(16) && Instant::now() >= deadline {
            return None;
        }
        for (i, v) in q.iter_mut().enumerate() {
            let (lo, hi) = chain.sample_range(i);
            *v = rng.random_range(lo..=hi);
        }
        let new = match extend(world, &mut a, &q, p, spacing) {
            Extend::Trapped => None,
            Extend::Advanced(i) | Extend::Reached(i) => Some(i),
        };
        if let Some(ai) = new {
            // Connect the other tree towards the new node greedily.
            let target = a.nodes[ai].clone();
            loop {
                match extend(world, &mut b, &target, p, spacing) {
                    Extend::Trapped => break,
                    Extend::Advanced(_) => continue,
                    Extend::Reached(bi) => {
                        let mut from_a = a.path_to_root(ai);
                        from_a.reverse();
                        let from_b = b.path_to_root(bi);
                        let mut waypoints = from_a;
                        waypoints.extend(from_b.into_iter().skip(1));
                        if !a_is_start {
                            waypoints.reverse();
                        }
                        let mut path = Path {
                            waypoints,
                            planning_time: 0.0,
                            tree_nodes: a.nodes.len() + b.nodes.len(),
                        };
                        shortcut_spaced(world, &mut path, p, &mut rng, spacing);
                        return Some(path);
                    }
                }
            }
        }
        std::mem::swap(&mut a, &mut b);
        a_is_start = !a_is_start;
    }
}

/// Random shortcutting: replace the stretch between two random waypoints by the
/// straight segment whenever that segment is valid.
/// Random shortcutting of a certified path: every shortcut taken is certified too.
pub fn shortcut(world: &CollisionWorld, path: &mut Path, p: &PlannerParams, rng: &mut ChaCha8Rng) {
    shortcut_with(path, p, rng, |a, b| {
        segment_certified(world, a, b, p.resolution)
    });
}

/// Shortcutting with edges checked at `spacing` (the trees' coarse checks).
fn shortcut_spaced(
    world: &CollisionWorld,
    path: &mut Path,
    p: &PlannerParams,
    rng: &mut ChaCha8Rng,
    spacing: f64,
) {
    shortcut_with(path, p, rng, |a, b| {
        segment_valid_spaced(world, a, b, p.resolution, spacing)
    });
}

/// Replaces the stretch between two random waypoints by the straight segment whenever
/// `segment_ok` accepts it, `shortcut_attempts` times.
fn shortcut_with(
    path: &mut Path,
    p: &PlannerParams,
    rng: &mut ChaCha8Rng,
    segment_ok: impl Fn(&[f64], &[f64]) -> bool,
) {
    for _ in 0..p.shortcut_attempts {
        let n = path.waypoints.len();
        if n < 3 {
            return;
        }
        let i = rng.random_range(0..n - 2);
        let j = rng.random_range(i + 2..n);
        if segment_ok(&path.waypoints[i], &path.waypoints[j]) {
            path.waypoints.drain(i + 1..j);
        }
    }
}

/// A timed trajectory: samples `(t, q, q̇)`.
#[derive(Debug, Clone)]
pub struct Trajectory {
    pub times: Vec<f64>,
    pub positions: Vec<Vec<f64>>,
    /// Joint velocities at each sample (exact, from the profile).
    pub velocities: Vec<Vec<f64>>,
}

impl Trajectory {
    pub fn duration(&self) -> f64 {
        self.times.last().copied().unwrap_or(0.0)
    }
}

/// The most samples a timed trajectory may have: 200,000 (over 2.7 hours at the 0.05 s
/// default, half an hour at 0.01 s). More means a velocity or acceleration limit too
/// small to be meant (a URDF's `velocity="1e-300"`), and a sampler that would fill the
/// memory; such a path is refused with the limit named.
pub const MAX_TRAJECTORY_SAMPLES: usize = 200_000;

/// A path whose timing would exceed [`MAX_TRAJECTORY_SAMPLES`].
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[error(
    "the trajectory would last {} s ({samples} samples, over the bound of {MAX_TRAJECTORY_SAMPLES}): \
     joint {joint}'s velocity limit {} or the acceleration limit {} is too small",
    tabula_geom::input::shown(*.seconds),
    tabula_geom::input::shown(*.velocity),
    tabula_geom::input::shown(*.acceleration)
)]
pub struct TrajectoryTooLong {
    pub seconds: f64,
    pub samples: f64,
    /// The joint (index in the path) that sets the slowest segment's time.
    pub joint: usize,
    pub velocity: f64,
    pub acceleration: f64,
}

/// Each segment's duration under the limits and the joint that sets it.
fn segment_durations(path: &[Vec<f64>], vmax: &[f64], amax: &[f64]) -> Vec<(f64, usize)> {
    path.windows(2)
        .map(|w| {
            let (a, b) = (&w[0], &w[1]);
            let mut slowest = (0.0f64, 0);
            for k in 0..a.len() {
                let d = (b[k] - a[k]).abs();
                let (v, acc) = (vmax[k].max(1e-9), amax[k].max(1e-9));
                let t = (d / (0.75 * v)).max((d / (0.1875 * acc)).sqrt());
                if t > slowest.0 {
                    slowest = (t, k);
                }
            }
            slowest
        })
        .collect()
}

/// Times a path under per-joint velocity and acceleration limits: each segment follows
/// one fixed rest-to-rest profile in the path parameter (accelerate for a quarter of the
/// segment, cruise, decelerate for a quarter), stretched until every joint's peak
/// velocity `d/(0.75 T)` and acceleration `d/(0.1875 T²)` are within its limits, so all
/// joints stay on the straight segment. Sampled every `dt` seconds, at most
/// [`MAX_TRAJECTORY_SAMPLES`] samples.
pub fn time_parameterize(
    path: &[Vec<f64>],
    vmax: &[f64],
    amax: &[f64],
    dt: f64,
) -> Result<Trajectory, TrajectoryTooLong> {
    let dt = dt.max(1e-6);
    let durations = segment_durations(path, vmax, amax);
    let samples: f64 = durations.iter().map(|(d, _)| (d / dt).ceil()).sum();
    if samples.is_nan() || samples > MAX_TRAJECTORY_SAMPLES as f64 {
        let (_, joint) = durations
            .iter()
            .copied()
            .fold((0.0, 0), |m, x| if x.0 > m.0 { x } else { m });
        return Err(TrajectoryTooLong {
            seconds: durations.iter().map(|(d, _)| d).sum(),
            samples,
            joint,
            velocity: vmax.get(joint).copied().unwrap_or(f64::NAN),
            acceleration: amax.get(joint).copied().unwrap_or(f64::NAN),
        });
    }
    let mut times = vec![0.0];
    let mut positions = vec![path.first().cloned().unwrap_or_default()];
    let mut velocities = vec![vec![0.0; positions[0].len()]];
    let mut t_start = 0.0;
    for (w, &(duration, _)) in path.windows(2).zip(&durations) {
        let (a, b) = (&w[0], &w[1]);
        if duration <= 0.0 {
            continue;
        }
        let ta = duration / 4.0;
        let vs = 1.0 / (duration - ta);
        let s_of = |t: f64| {
            if t < ta {
                0.5 * vs / ta * t * t
            } else if t < duration - ta {
                0.5 * vs * ta + vs * (t - ta)
            } else {
                let r = duration - t;
                1.0 - 0.5 * vs / ta * r * r
            }
        };
        let ds_of = |t: f64| {
            if t < ta {
                vs / ta * t
            } else if t < duration - ta {
                vs
            } else {
                vs / ta * (duration - t).max(0.0)
            }
        };
        let n = (duration / dt).ceil().max(1.0) as usize;
        for i in 1..=n {
            let t = (i as f64 * duration / n as f64).min(duration);
            let s = s_of(t).clamp(0.0, 1.0);
            // Rest at every waypoint: the segment's last sample exactly, not by rounding.
            let ds = if i == n { 0.0 } else { ds_of(t) };
            times.push(t_start + t);
            positions.push(a.iter().zip(b).map(|(x, y)| x + (y - x) * s).collect());
            velocities.push(a.iter().zip(b).map(|(x, y)| (y - x) * ds).collect());
        }
        t_start += duration;
    }
    Ok(Trajectory {
        times,
        positions,
        velocities,
    })
}

impl Validate for PlannerParams {
    fn check(&self, at: &str) -> Result<(), String> {
        check_in(at, "timeout_s", self.timeout_s, 1e-6, 1e6)?;
        // Steps under a milliradian never reach the goal within any time limit, and a
        // checking resolution under 1e-5 rad is millions of checks per edge.
        check_in(at, "range", self.range, 1e-3, 1e3)?;
        check_in(at, "resolution", self.resolution, 1e-5, 1.0)
    }
}

#[cfg(test)]
mod tests {
    #[test]
    fn van_der_corput_is_the_bit_reversed_sort() {
        for n in 0..300usize {
            let mut sorted: Vec<usize> = (1..=n).collect();
            sorted.sort_by_key(|&i| (i as u32).reverse_bits());
            assert_eq!(
                super::van_der_corput(n).collect::<Vec<_>>(),
                sorted,
                "n = {n}"
            );
        }
    }
}
