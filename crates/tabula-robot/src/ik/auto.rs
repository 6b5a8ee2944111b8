//! The solver an arm gets when its description says `numeric`: a closed form when the
//! chain's geometry allows one (UR-type arms, [`ThreeParallelIk`]), for full poses; the
//! numeric solver for everything else and for orientation-free goals.

use super::{IkError, IkMode, IkSolution, IkSolver, NumericIk, ThreeParallelIk};
use crate::Chain;
use tabula_geom::Pose;

/// A closed form where it applies, numeric otherwise.
pub struct AutoIk {
    analytic: Option<ThreeParallelIk>,
    numeric: NumericIk,
}

impl AutoIk {
    pub fn new(numeric: NumericIk) -> Self {
        Self {
            analytic: ThreeParallelIk::new(numeric.chain()),
            numeric,
        }
    }

    /// Whether full poses are solved in closed form.
    pub fn is_analytic(&self) -> bool {
        self.analytic.is_some()
    }
}

impl IkSolver for AutoIk {
    fn chain(&self) -> &Chain {
        self.numeric.chain()
    }

    fn solve(&self, target: &Pose, mode: IkMode, seed: &[f64]) -> Result<Vec<IkSolution>, IkError> {
        match (&self.analytic, mode) {
            (Some(a), IkMode::Full) => a.solve(target, mode, seed),
            _ => self.numeric.solve(target, mode, seed),
        }
    }
}
