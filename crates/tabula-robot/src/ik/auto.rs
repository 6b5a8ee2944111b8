//! The solver an arm gets when its description says `numeric`: a closed form when the
//! chain's geometry allows one, for full poses, and the numeric solver for everything
//! else and for orientation-free goals.
//!
//! UR-type 6R arms ([`ThreeParallelIk`]) and 6R arms with a spherical wrist
//! ([`SphericalWristIk`]) always get their closed form: it is complete (no solution there
//! means none exists). 7R arms with a spherical shoulder
//! ([`SphericalShoulderIk`]) get theirs from [`AutoIk::all_solutions`] — the kinematics
//! API (`tabula ik`, Python's `Robot.ik`): every solution at the last joint's first
//! feasible value from the seed's, 4 µs median on the Panda against the numeric
//! solver's 7 µs median and 45 µs mean. The tasks' arms keep the numeric descent
//! ([`AutoIk::new`]), which spends the redundancy on every joint from the seed: with the
//! closed form in place of its restarts, clearing the 50 `grid` tables (seeds 101–150)
//! went from 97.7 % to 96.2 % and failed grasps from 9 to 23 (BENCHMARKS.md).

use super::{
    IkError, IkMode, IkSolution, IkSolver, NumericIk, SphericalShoulderIk, SphericalWristIk,
    ThreeParallelIk,
};
use crate::Chain;
use tabula_geom::Pose;

enum Analytic {
    ThreeParallel(ThreeParallelIk),
    SphericalWrist(SphericalWristIk),
    SphericalShoulder(SphericalShoulderIk),
}

/// A closed form where it applies, numeric otherwise.
pub struct AutoIk {
    analytic: Option<Analytic>,
    numeric: NumericIk,
}

impl AutoIk {
    /// The tasks' solver: the 6R closed forms, numeric descent for everything else.
    pub fn new(numeric: NumericIk) -> Self {
        let analytic = six_r(numeric.chain());
        Self { analytic, numeric }
    }

    /// Every closed form that applies, spherical-shoulder 7R arms included; the numeric
    /// solver for what a sweep over the redundancy misses.
    pub fn all_solutions(numeric: NumericIk) -> Self {
        let chain = numeric.chain();
        let analytic = six_r(chain)
            .or_else(|| SphericalShoulderIk::new(chain).map(Analytic::SphericalShoulder));
        Self { analytic, numeric }
    }

    /// Whether full poses are solved in closed form.
    pub fn is_analytic(&self) -> bool {
        self.analytic.is_some()
    }
}

/// The complete closed forms of 6R arms that apply to `chain`.
fn six_r(chain: &Chain) -> Option<Analytic> {
    ThreeParallelIk::new(chain)
        .map(Analytic::ThreeParallel)
        .or_else(|| SphericalWristIk::new(chain).map(Analytic::SphericalWrist))
}

impl IkSolver for AutoIk {
    fn chain(&self) -> &Chain {
        self.numeric.chain()
    }

    fn solve(&self, target: &Pose, mode: IkMode, seed: &[f64]) -> Result<Vec<IkSolution>, IkError> {
        match (&self.analytic, mode) {
            (Some(Analytic::ThreeParallel(a)), IkMode::Full) => a.solve(target, mode, seed),
            (Some(Analytic::SphericalWrist(a)), IkMode::Full) => a.solve(target, mode, seed),
            (Some(Analytic::SphericalShoulder(a)), IkMode::Full) => {
                match a.solve(target, mode, seed) {
                    // What the sweep's step misses, the restarts may find.
                    Err(IkError::NoSolution) => self.numeric.solve(target, mode, seed),
                    answer => answer,
                }
            }
            _ => self.numeric.solve(target, mode, seed),
        }
    }
}
