//! Comparing two IK solvers on the same targets (seed 001 §5.1): solve time and the six
//! per-axis errors, each tested with Mann–Whitney U.

use serde::Serialize;
use tabula_robot::Chain;
use tabula_robot::ik::IkSolution;
use tabula_robot::ik::bench::{IkBenchReport, MannWhitney, Spread, mann_whitney};

/// One measure of a comparison: its medians for A and B and the test between them.
#[derive(Serialize)]
pub struct Compared {
    pub measure: &'static str,
    pub unit: &'static str,
    pub median_a: f64,
    pub median_b: f64,
    pub test: Option<MannWhitney>,
    /// p < 0.05.
    pub different: bool,
}

/// Solve time and the errors along x, y, z, roll, pitch, yaw of runs `a` and `b`.
pub fn compare(a: &IkBenchReport, b: &IkBenchReport) -> Vec<Compared> {
    let axes = [
        ("x error", "m"),
        ("y error", "m"),
        ("z error", "m"),
        ("roll error", "rad"),
        ("pitch error", "rad"),
        ("yaw error", "rad"),
    ];
    let mut rows = vec![("solve time", "µs", &a.solve_us_samples, &b.solve_us_samples)];
    for (k, (name, unit)) in axes.into_iter().enumerate() {
        rows.push((
            name,
            unit,
            &a.axis_error_samples[k],
            &b.axis_error_samples[k],
        ));
    }
    rows.into_iter()
        .map(|(measure, unit, x, y)| {
            let test = mann_whitney(x, y);
            Compared {
                measure,
                unit,
                median_a: Spread::of(x).median,
                median_b: Spread::of(y).median,
                different: test.is_some_and(|t| t.p < 0.05),
                test,
            }
        })
        .collect()
}

/// The solutions as a table: the chain's joints, then one row per solution with its
/// position and rotation errors, nearest to the seed first.
pub fn solution_lines(chain: &Chain, sols: &[IkSolution]) -> Vec<String> {
    let names: Vec<String> = (1..=chain.dof())
        .map(|i| format!("{:>10}", format!("q{i}")))
        .collect();
    let mut lines = vec![
        format!("  joints: {}", chain.joint_names.join(", ")),
        format!("  #  {}   pos err (m)  rot err (rad)", names.join(" ")),
    ];
    for (i, s) in sols.iter().enumerate() {
        let vals: Vec<String> = s.joints.iter().map(|v| format!("{v:>10.5}")).collect();
        lines.push(format!(
            "{:>3}  {}   {:.2e}     {:.2e}",
            i + 1,
            vals.join(" "),
            s.position_error,
            s.rotation_error
        ));
    }
    lines.push(format!(
        "  {} solution(s), nearest to the seed first",
        sols.len()
    ));
    lines
}
