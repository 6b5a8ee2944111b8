//! The IK benchmark protocol of seed 001 (SPEC §2.4), for any solver and chain.
//!
//! Targets are FK of uniformly random joint values within limits (so every target is
//! reachable); each is solved from the mid-range seed and checked with the chain's own
//! FK — not the solver's — for position and rotation error and joint limits.
//!
//! "No solution" is timed on two further sets made from the same targets:
//! * *pushed out*: each position moved radially to 1.5× its distance from the first
//!   joint (the seed's "reachable ones pushed outside the workspace"). Most leave the
//!   workspace, but nothing guarantees it, so only the targets answered "no solution"
//!   are timed and the rejected fraction is reported; a solver must work for its "no"
//!   here (the closed form decides it, a numeric solver spends its budget).
//! * *beyond reach*: each position moved past [`Chain::reach_bound`], certainly
//!   unreachable; this times the cheap reach test every solver does first.

use super::{IkError, IkMode, IkSolver};
use crate::Chain;
use rand::SeedableRng;
use rand_chacha::ChaCha8Rng;
use std::time::Instant;
use tabula_geom::{Mat3, Pose, Vec3, rpy_from_mat3};

/// Success threshold of the protocol: the analytic acceptance of issue 2 (1e-6 m, 1e-6 rad).
pub const SUCCESS_POSITION_M: f64 = 1e-6;
pub const SUCCESS_ROTATION_RAD: f64 = 1e-6;

/// A Mann–Whitney U test of two independent samples (seed 001 §5.1 compares solvers
/// so, at α = 0.05): rank-based, no assumption of normality — solve times are skewed
/// and errors span orders of magnitude.
#[derive(Debug, Clone, Copy, serde::Serialize)]
pub struct MannWhitney {
    /// U of the first sample: pairs (a, b) with a > b, ties counted half.
    pub u: f64,
    /// The normal approximation's z (tie-corrected, with continuity correction).
    pub z: f64,
    /// Two-sided p-value.
    pub p: f64,
    /// U / (n_a · n_b): the probability that a value of the first sample exceeds one of
    /// the second (0.5: no difference).
    pub effect: f64,
    pub n_a: usize,
    pub n_b: usize,
}

/// The Mann–Whitney U test of `a` against `b` (non-finite values left out), with the
/// normal approximation as SciPy's `mannwhitneyu(method="asymptotic")` computes it;
/// `None` when either sample is empty.
pub fn mann_whitney(a: &[f64], b: &[f64]) -> Option<MannWhitney> {
    let a: Vec<f64> = a.iter().copied().filter(|v| v.is_finite()).collect();
    let b: Vec<f64> = b.iter().copied().filter(|v| v.is_finite()).collect();
    let (na, nb) = (a.len(), b.len());
    if na == 0 || nb == 0 {
        return None;
    }
    // Ranks of the pooled sample, ties given their average rank.
    let mut pooled: Vec<(f64, bool)> = a
        .iter()
        .map(|v| (*v, true))
        .chain(b.iter().map(|v| (*v, false)))
        .collect();
    pooled.sort_by(|x, y| x.0.total_cmp(&y.0));
    let n = pooled.len();
    let (mut rank_sum_a, mut ties) = (0.0, 0.0);
    let mut i = 0;
    while i < n {
        let mut j = i + 1;
        while j < n && pooled[j].0 == pooled[i].0 {
            j += 1;
        }
        let t = (j - i) as f64;
        let rank = (i + j + 1) as f64 / 2.0;
        rank_sum_a += rank * pooled[i..j].iter().filter(|e| e.1).count() as f64;
        ties += t * t * t - t;
        i = j;
    }
    let (na_f, nb_f, n_f) = (na as f64, nb as f64, n as f64);
    let u = rank_sum_a - na_f * (na_f + 1.0) / 2.0;
    let mean = na_f * nb_f / 2.0;
    let var = na_f * nb_f / 12.0 * ((n_f + 1.0) - ties / (n_f * (n_f - 1.0)).max(1.0));
    let (z, p) = if var > 0.0 {
        let d = u - mean;
        let z = (d - 0.5 * d.signum()) / var.sqrt();
        let z = if d.abs() <= 0.5 { 0.0 } else { z };
        (z, libm::erfc(z.abs() / std::f64::consts::SQRT_2).min(1.0))
    } else {
        // Every value equal: nothing tells the samples apart.
        (0.0, 1.0)
    };
    Some(MannWhitney {
        u,
        z,
        p,
        effect: u / (na_f * nb_f),
        n_a: na,
        n_b: nb,
    })
}

/// Median, 95th percentile and maximum of a sample.
#[derive(Debug, Clone, Copy, Default, serde::Serialize)]
pub struct Spread {
    pub median: f64,
    pub p95: f64,
    pub max: f64,
}

impl Spread {
    pub fn of(values: &[f64]) -> Self {
        if values.is_empty() {
            return Self::default();
        }
        let mut v = values.to_vec();
        v.sort_by(f64::total_cmp);
        let at = |q: f64| v[((v.len() - 1) as f64 * q).round() as usize];
        Self {
            median: at(0.5),
            p95: at(0.95),
            max: v[v.len() - 1],
        }
    }
}

/// Per-axis absolute errors of the best solution against its target.
#[derive(Debug, Clone, Default, serde::Serialize)]
pub struct AxisErrors {
    pub x: Spread,
    pub y: Spread,
    pub z: Spread,
    pub roll: Spread,
    pub pitch: Spread,
    pub yaw: Spread,
}

/// Everything the protocol measures.
#[derive(Debug, Clone, serde::Serialize)]
pub struct IkBenchReport {
    pub solver: String,
    pub base: String,
    pub tip: String,
    pub dof: usize,
    pub mode: String,
    pub poses: usize,
    pub seed: u64,
    pub success_rate: f64,
    /// Fraction of reachable targets solved with a single attempt from the seed
    /// (numeric solvers only).
    pub one_attempt_success_rate: Option<f64>,
    /// Wall time per solve of reachable targets (µs).
    pub solve_us: Spread,
    /// Wall time per "no solution" answer on the pushed-out targets (µs).
    pub fail_us: Spread,
    /// Fraction of pushed-out targets answered "no solution" (the rest were solved,
    /// and verified, so they were inside the workspace after all).
    pub unreachable_rejected_rate: f64,
    /// Wall time per answer on targets beyond the reach bound (µs).
    pub beyond_reach_fail_us: Spread,
    /// Fraction of beyond-reach targets answered "no solution" (must be 1).
    pub beyond_reach_rejected_rate: f64,
    /// Thread CPU time over all reachable solves divided by their count (µs).
    pub cpu_us_per_solve: f64,
    pub max_pos_err_m: f64,
    pub max_rot_err_rad: f64,
    pub errors: AxisErrors,
    pub solutions_per_pose: Spread,
    pub mean_solutions_per_pose: f64,
    /// Every reachable solve's wall time (µs), for distributions in reports.
    #[serde(skip)]
    pub solve_us_samples: Vec<f64>,
    /// Every solution's error per axis (x y z in m, roll pitch yaw in rad).
    #[serde(skip)]
    pub axis_error_samples: [Vec<f64>; 6],
}

/// CPU time of the calling thread (s), for benchmarks that report CPU rather than wall time.
pub fn thread_cpu_seconds() -> f64 {
    let mut ts = libc::timespec {
        tv_sec: 0,
        tv_nsec: 0,
    };
    // SAFETY: clock_gettime writes into the timespec we own; the clock id is valid on Linux.
    let rc = unsafe { libc::clock_gettime(libc::CLOCK_THREAD_CPUTIME_ID, &mut ts) };
    if rc != 0 {
        return 0.0;
    }
    ts.tv_sec as f64 + ts.tv_nsec as f64 * 1e-9
}

/// The protocol's targets: FK of random configurations (seeded).
pub fn reachable_targets(chain: &Chain, count: usize, seed: u64) -> Vec<Pose> {
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    (0..count)
        .map(|_| chain.fk_unchecked(&chain.random_configuration(&mut rng)))
        .collect()
}

/// Reachable targets pushed radially from the first joint to `factor` × their distance.
pub fn pushed_out_targets(chain: &Chain, reachable: &[Pose], factor: f64) -> Vec<Pose> {
    let center = chain.reach_center();
    reachable
        .iter()
        .map(|t| Pose::from_parts(center + (t.translation - center) * factor, t.rotation))
        .collect()
}

/// Reachable targets pushed radially beyond the chain's reach bound.
pub fn beyond_reach_targets(chain: &Chain, reachable: &[Pose]) -> Vec<Pose> {
    let center = chain.reach_center();
    let radius = chain.reach_bound() * 1.1 + 0.1;
    reachable
        .iter()
        .map(|t| {
            let dir = (t.translation - center).try_normalize().unwrap_or(Vec3::X);
            Pose::from_parts(center + dir * radius, t.rotation)
        })
        .collect()
}

/// Times the answers on `targets`; returns (times of "no solution" answers, fraction rejected).
fn time_rejections(
    solver: &dyn IkSolver,
    targets: &[Pose],
    mode: IkMode,
    seed: &[f64],
) -> (Vec<f64>, f64) {
    let mut times = Vec::with_capacity(targets.len());
    for target in targets {
        let t0 = Instant::now();
        let r = solver.solve(target, mode, seed);
        let us = t0.elapsed().as_secs_f64() * 1e6;
        if matches!(r, Err(IkError::NoSolution | IkError::NotFound { .. })) {
            times.push(us);
        }
    }
    let rate = times.len() as f64 / targets.len().max(1) as f64;
    (times, rate)
}

/// Runs the protocol. `one_attempt`, if given, is the same solver limited to a single
/// attempt, run on the same targets for the one-attempt rate.
pub fn run(
    solver: &dyn IkSolver,
    one_attempt: Option<&dyn IkSolver>,
    solver_name: &str,
    mode: IkMode,
    poses: usize,
    seed: u64,
) -> IkBenchReport {
    let chain = solver.chain();
    let targets = reachable_targets(chain, poses, seed);
    let start_q = chain.mid_configuration();
    let mut solve_us = Vec::with_capacity(poses);
    let mut counts = Vec::with_capacity(poses);
    let mut axis: [Vec<f64>; 6] = Default::default();
    let (mut solved, mut max_pos, mut max_rot) = (0usize, 0.0f64, 0.0f64);
    // Timed: each answer dropped as a caller would drop it (holding ten thousand of
    // them timed the harness's page faults); checked below from a second, untimed solve
    // (every solver is deterministic).
    let cpu0 = thread_cpu_seconds();
    for target in &targets {
        let t0 = Instant::now();
        let r = solver.solve(target, mode, &start_q);
        solve_us.push(t0.elapsed().as_secs_f64() * 1e6);
        drop(std::hint::black_box(r));
    }
    let cpu_us_per_solve = (thread_cpu_seconds() - cpu0) * 1e6 / poses.max(1) as f64;
    for target in &targets {
        let r = &solver.solve(target, mode, &start_q);
        let Ok(sols) = r else {
            counts.push(0.0);
            continue;
        };
        counts.push(sols.len() as f64);
        let best = &sols[0];
        let reached = chain.fk_unchecked(&best.joints);
        let d = reached.translation - target.translation;
        let rot_err = Mat3::from_quat(target.rotation.inverse() * reached.rotation);
        let [roll, pitch, yaw] = rpy_from_mat3(&rot_err);
        let (pos, rot) = super::pose_error(&reached, target, mode);
        let positional = [d.x.abs(), d.y.abs(), d.z.abs()];
        let angular = if mode == IkMode::Full {
            [roll.abs(), pitch.abs(), yaw.abs()]
        } else {
            [0.0; 3]
        };
        for (k, v) in positional.iter().chain(&angular).enumerate() {
            axis[k].push(*v);
        }
        max_pos = max_pos.max(pos);
        max_rot = max_rot.max(rot);
        if pos < SUCCESS_POSITION_M
            && rot < SUCCESS_ROTATION_RAD
            && chain.within_limits(&best.joints, 1e-9)
        {
            solved += 1;
        }
    }
    let one_attempt_success_rate = one_attempt.map(|s| {
        let ok = targets
            .iter()
            .filter(|t| {
                s.solve(t, mode, &start_q).is_ok_and(|sols| {
                    let (p, r) = super::pose_error(&chain.fk_unchecked(&sols[0].joints), t, mode);
                    p < SUCCESS_POSITION_M && r < SUCCESS_ROTATION_RAD
                })
            })
            .count();
        ok as f64 / poses.max(1) as f64
    });
    let (fail_us, rejected_rate) = time_rejections(
        solver,
        &pushed_out_targets(chain, &targets, 1.5),
        mode,
        &start_q,
    );
    let (beyond_us, beyond_rate) = time_rejections(
        solver,
        &beyond_reach_targets(chain, &targets),
        mode,
        &start_q,
    );
    IkBenchReport {
        solver: solver_name.to_string(),
        base: chain.base_link.clone(),
        tip: chain.tip_link.clone(),
        dof: chain.dof(),
        mode: match mode {
            IkMode::Full => "full".into(),
            IkMode::PositionOnly => "position-only".into(),
            IkMode::PositionAxis { .. } => "position+axis".into(),
        },
        poses,
        seed,
        success_rate: solved as f64 / poses.max(1) as f64,
        one_attempt_success_rate,
        solve_us: Spread::of(&solve_us),
        fail_us: Spread::of(&fail_us),
        unreachable_rejected_rate: rejected_rate,
        beyond_reach_fail_us: Spread::of(&beyond_us),
        beyond_reach_rejected_rate: beyond_rate,
        cpu_us_per_solve,
        max_pos_err_m: max_pos,
        max_rot_err_rad: max_rot,
        errors: AxisErrors {
            x: Spread::of(&axis[0]),
            y: Spread::of(&axis[1]),
            z: Spread::of(&axis[2]),
            roll: Spread::of(&axis[3]),
            pitch: Spread::of(&axis[4]),
            yaw: Spread::of(&axis[5]),
        },
        mean_solutions_per_pose: counts.iter().sum::<f64>() / counts.len().max(1) as f64,
        solutions_per_pose: Spread::of(&counts),
        solve_us_samples: solve_us,
        axis_error_samples: axis,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Against SciPy 1.17 `mannwhitneyu(a, b, method="asymptotic")` (continuity
    /// correction on, two-sided).
    #[test]
    fn mann_whitney_matches_scipy() {
        let m = mann_whitney(&[1.0, 2.0, 3.0, 4.0, 5.0], &[6.0, 7.0, 8.0, 9.0, 10.0]).unwrap();
        assert_eq!(m.u, 0.0);
        assert!((m.p - 0.012_185_780_355_344_813).abs() < 1e-9, "{}", m.p);
        // Ties across the samples.
        let a = [1.0, 2.0, 2.0, 3.0, 5.0, 5.0, 7.0];
        let b = [2.0, 3.0, 3.0, 4.0, 6.0, 8.0, 8.0, 9.0];
        let m = mann_whitney(&a, &b).unwrap();
        assert_eq!(m.u, 16.0);
        assert!((m.p - 0.179_300_898_211_569_8).abs() < 1e-9, "{}", m.p);
        // Swapping the samples mirrors U and keeps p.
        let w = mann_whitney(&b, &a).unwrap();
        assert_eq!(w.u, 7.0 * 8.0 - 16.0);
        assert!((w.p - m.p).abs() < 1e-12);
        // Equal samples: p = 1; empty: no test; NaN left out.
        assert_eq!(mann_whitney(&[1.0; 4], &[1.0; 3]).unwrap().p, 1.0);
        assert!(mann_whitney(&[], &[1.0]).is_none());
        assert_eq!(mann_whitney(&[f64::NAN, 1.0], &[2.0]).unwrap().n_a, 1);
    }
}
