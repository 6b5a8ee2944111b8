//! Numeric IK for any chain: Levenberg–Marquardt on the geometric Jacobian with joint
//! limits and random restarts.
//!
//! Each attempt iterates damped least-squares steps
//! `dq = Jᵀ (J Jᵀ + λ I)⁻¹ e` with λ = μ (½|e|² + λ₀) (Sugihara's error-dependent
//! damping: large far from the target, tiny near it, so convergence ends quadratic-like),
//! clamps `q` into the limits, and accepts a step only if it lowers the error (else μ
//! grows ×10, as in classic LM). An attempt that stalls is abandoned and the next starts
//! from a random configuration. The first attempt starts at the caller's seed, so the
//! answer is usually the solution nearest it. Solving in the 6×6 (or 3×3) task space
//! keeps each iteration a fixed-size Cholesky whatever the chain's length.

use super::{IkError, IkMode, IkSolution, IkSolver, pose_error, sort_and_dedup, validate_request};
use crate::Chain;
use nalgebra::{SMatrix, SVector};
use rand::SeedableRng;
use rand_chacha::ChaCha8Rng;
use std::time::{Duration, Instant};
use tabula_geom::input::{Validate, check_count, check_in, check_non_negative, check_positive};
use tabula_geom::{Pose, Vec3, rotation_vector, wrap_angle};

/// Parameters of [`NumericIk`]; loadable from TOML (missing keys keep their default).
///
/// The seeds give no numeric-IK settings; the defaults follow the benchmark protocol of
/// SPEC §2.4 and its anchors (TRAC-IK's 5 ms budget, 1e-6 tolerances as the analytic
/// solver's acceptance).
#[derive(Debug, Clone, serde::Serialize, serde::Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct NumericIkParams {
    /// Wall-clock budget per solve in seconds; `None` makes the solve fully
    /// deterministic (only `max_attempts` bounds it).
    pub timeout_s: Option<f64>,
    /// Attempts (the seed, then random restarts) per solve.
    pub max_attempts: usize,
    /// LM iterations per attempt.
    pub max_iterations: usize,
    /// Position tolerance (m).
    pub position_tolerance: f64,
    /// Orientation tolerance (rad).
    pub rotation_tolerance: f64,
    /// Keep restarting until this many distinct solutions are found (or the budget
    /// ends); they are returned nearest-to-seed first.
    pub max_solutions: usize,
    /// Base damping λ₀ (m²).
    pub damping: f64,
    /// Seed of the restart sampler: same seed, same answer.
    pub random_seed: u64,
    /// Solutions closer than this (rad, Euclidean over the joints) count as one when
    /// collecting `max_solutions`.
    pub min_separation: f64,
}

impl Default for NumericIkParams {
    fn default() -> Self {
        Self {
            timeout_s: Some(0.005),
            max_attempts: 10_000,
            max_iterations: 60,
            position_tolerance: 1e-6,
            rotation_tolerance: 1e-6,
            max_solutions: 1,
            damping: 1e-4,
            random_seed: 0,
            min_separation: 0.05,
        }
    }
}

/// Levenberg–Marquardt IK with restarts for any [`Chain`].
#[derive(Debug, Clone)]
pub struct NumericIk {
    chain: Chain,
    pub params: NumericIkParams,
    reach_center: Vec3,
    reach_bound: f64,
}

/// Statistics of the last solve (for benchmarks).
#[derive(Debug, Clone, Copy, Default)]
pub struct SolveStats {
    pub attempts: usize,
    pub iterations: usize,
}

impl NumericIk {
    pub fn new(chain: Chain, params: NumericIkParams) -> Self {
        let reach_center = chain.reach_center();
        let reach_bound = chain.reach_bound();
        Self {
            chain,
            params,
            reach_center,
            reach_bound,
        }
    }

    /// Like [`IkSolver::solve`], also returning how much work it took.
    pub fn solve_with_stats(
        &self,
        target: &Pose,
        mode: IkMode,
        seed: &[f64],
    ) -> Result<(Vec<IkSolution>, SolveStats), IkError> {
        validate_request(&self.chain, target, mode, seed)?;
        let target = Pose::from_parts(target.translation, target.rotation.normalize());
        let mut stats = SolveStats::default();
        // Farther from the first joint than any configuration reaches: say so at once.
        if (target.translation - self.reach_center).length()
            > self.reach_bound + self.params.position_tolerance
        {
            return Err(IkError::NoSolution);
        }
        let start = Instant::now();
        let deadline = self
            .params
            .timeout_s
            .map(|s| start + Duration::from_secs_f64(s.max(0.0)));
        let mut rng = ChaCha8Rng::seed_from_u64(self.params.random_seed);
        let mut solutions = Vec::new();
        let mut ws = Workspace::default();
        let mut q = seed.to_vec();
        self.chain.clamp(&mut q);
        for attempt in 0..self.params.max_attempts.max(1) {
            if attempt > 0 {
                if deadline.is_some_and(|d| Instant::now() >= d) {
                    break;
                }
                q = self.chain.random_configuration(&mut rng);
            }
            stats.attempts += 1;
            let converged = match mode {
                IkMode::PositionOnly => {
                    self.attempt::<3>(&target, mode, &mut q, &mut ws, &mut stats, deadline)
                }
                _ => self.attempt::<6>(&target, mode, &mut q, &mut ws, &mut stats, deadline),
            };
            if converged {
                for (i, v) in q.iter_mut().enumerate() {
                    if !self.chain.lower[i].is_finite() && !self.chain.var_prismatic[i] {
                        *v = seed[i] + wrap_angle(*v - seed[i]);
                    }
                }
                let reached = self.chain.fk_unchecked(&q);
                let (position_error, rotation_error) = pose_error(&reached, &target, mode);
                solutions.push(IkSolution {
                    joints: q.clone(),
                    position_error,
                    rotation_error,
                });
                solutions =
                    sort_and_dedup(&self.chain, solutions, seed, self.params.min_separation);
                if solutions.len() >= self.params.max_solutions.max(1) {
                    break;
                }
            }
        }
        if solutions.is_empty() {
            Err(IkError::NotFound {
                attempts: stats.attempts,
            })
        } else {
            Ok((solutions, stats))
        }
    }

    /// Task-space error (first K rows used) and the Jacobian rows it needs.
    fn error_and_jacobian<const K: usize>(
        &self,
        target: &Pose,
        mode: IkMode,
        q: &[f64],
        ws: &mut Workspace,
    ) -> SVector<f64, K> {
        let tip = self.chain.fk_and_jacobian(q, &mut ws.columns);
        let dp = target.translation - tip.translation;
        let mut e = SVector::<f64, K>::zeros();
        e[0] = dp.x;
        e[1] = dp.y;
        e[2] = dp.z;
        if K == 6 {
            let rot = match mode {
                IkMode::PositionAxis { tool_axis } => {
                    let a = tool_axis.normalize();
                    let cur = tip.rotation * a;
                    let want = target.rotation * a;
                    // Rotation about the current axis is free: drop it from every column.
                    for c in ws.columns.iter_mut() {
                        let w = Vec3::new(c[3], c[4], c[5]);
                        let w = w - cur * cur.dot(w);
                        c[3] = w.x;
                        c[4] = w.y;
                        c[5] = w.z;
                    }
                    let axis = cur.cross(want);
                    let s = axis.length();
                    if s < 1e-300 {
                        if cur.dot(want) < 0.0 {
                            cur.any_orthonormal_vector() * std::f64::consts::PI
                        } else {
                            Vec3::ZERO
                        }
                    } else {
                        axis * (s.atan2(cur.dot(want)) / s)
                    }
                }
                _ => rotation_vector(target.rotation * tip.rotation.inverse()),
            };
            e[3] = rot.x;
            e[4] = rot.y;
            e[5] = rot.z;
        }
        e
    }

    fn converged<const K: usize>(&self, e: &SVector<f64, K>) -> bool {
        let p2 = e[0] * e[0] + e[1] * e[1] + e[2] * e[2];
        let tol_p = self.params.position_tolerance;
        if p2 > tol_p * tol_p {
            return false;
        }
        if K == 6 {
            let r2 = e[3] * e[3] + e[4] * e[4] + e[5] * e[5];
            let tol_r = self.params.rotation_tolerance;
            return r2 <= tol_r * tol_r;
        }
        true
    }

    /// One LM descent from `q`; true when it converged (then `q` is the solution).
    fn attempt<const K: usize>(
        &self,
        target: &Pose,
        mode: IkMode,
        q: &mut [f64],
        ws: &mut Workspace,
        stats: &mut SolveStats,
        deadline: Option<Instant>,
    ) -> bool {
        let n = self.chain.dof();
        let mut e = self.error_and_jacobian::<K>(target, mode, q, ws);
        let mut err2 = e.norm_squared();
        let mut mu = 1.0;
        let mut trial = vec![0.0; n];
        let mut trial_cols = Vec::with_capacity(n);
        for it in 0..self.params.max_iterations {
            stats.iterations += 1;
            if self.converged(&e) {
                return true;
            }
            if it % 16 == 15 && deadline.is_some_and(|d| Instant::now() >= d) {
                return false;
            }
            // A = J Jᵀ over the K task rows.
            let mut a = SMatrix::<f64, K, K>::zeros();
            for c in &ws.columns {
                for r in 0..K {
                    for s in r..K {
                        a[(r, s)] += c[r] * c[s];
                    }
                }
            }
            for r in 0..K {
                for s in 0..r {
                    a[(r, s)] = a[(s, r)];
                }
            }
            let mut accepted = false;
            for _ in 0..6 {
                let lambda = mu * (0.5 * err2 + self.params.damping);
                let mut damped = a;
                for r in 0..K {
                    damped[(r, r)] += lambda;
                }
                let Some(chol) = damped.cholesky() else {
                    mu *= 10.0;
                    continue;
                };
                let y = chol.solve(&e);
                let mut max_step: f64 = 0.0;
                for (i, c) in ws.columns.iter().enumerate() {
                    trial[i] = (0..K).map(|r| c[r] * y[r]).sum();
                    max_step = max_step.max(trial[i].abs());
                }
                // Large steps leave the region where the linearisation means anything.
                let scale = if max_step > 1.0 { 1.0 / max_step } else { 1.0 };
                for i in 0..n {
                    trial[i] =
                        (q[i] + scale * trial[i]).clamp(self.chain.lower[i], self.chain.upper[i]);
                }
                std::mem::swap(&mut ws.columns, &mut trial_cols);
                let e_new = self.error_and_jacobian::<K>(target, mode, &trial, ws);
                let err2_new = e_new.norm_squared();
                if err2_new < err2 {
                    q.copy_from_slice(&trial);
                    e = e_new;
                    // Make progress slow to a crawl a reason to restart instead.
                    let stalled = err2_new > 0.999 * err2 && err2_new > 1e-12;
                    err2 = err2_new;
                    mu = (mu * 0.5).max(1e-3);
                    accepted = !stalled;
                    break;
                }
                std::mem::swap(&mut ws.columns, &mut trial_cols);
                mu *= 10.0;
            }
            if !accepted {
                return self.converged(&e);
            }
        }
        self.converged(&e)
    }
}

#[derive(Default)]
struct Workspace {
    columns: Vec<[f64; 6]>,
}

impl IkSolver for NumericIk {
    fn chain(&self) -> &Chain {
        &self.chain
    }

    fn solve(&self, target: &Pose, mode: IkMode, seed: &[f64]) -> Result<Vec<IkSolution>, IkError> {
        self.solve_with_stats(target, mode, seed).map(|(s, _)| s)
    }
}

impl Validate for NumericIkParams {
    fn check(&self, at: &str) -> Result<(), String> {
        if let Some(t) = self.timeout_s {
            check_in(at, "timeout_s", t, 1e-6, 1e6)?;
        }
        check_count(at, "max_attempts", self.max_attempts, 1)?;
        check_count(at, "max_iterations", self.max_iterations, 1)?;
        check_positive(at, "position_tolerance", self.position_tolerance)?;
        check_positive(at, "rotation_tolerance", self.rotation_tolerance)?;
        check_count(at, "max_solutions", self.max_solutions, 1)?;
        check_non_negative(at, "damping", self.damping)?;
        check_non_negative(at, "min_separation", self.min_separation)
    }
}
