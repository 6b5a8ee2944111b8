//! `tabula.plan_pddl`: a plan for a PDDL domain and problem, in process.

use crate::value_error;
use pyo3::prelude::*;
use std::time::Duration;
use tabula_pddl::{GroundOptions, NoPlan, Planner, SearchMode, parse_domain, parse_problem};

/// The plan's actions as `(name arg…)` strings; `None` when the problem has no plan.
/// `optimal` finds a cheapest plan (A*), else any plan fast (greedy best-first);
/// `timeout_s` bounds the search (`TimeoutError` past it).
#[pyfunction]
#[pyo3(signature = (domain, problem, optimal=true, timeout_s=None))]
pub fn plan_pddl(
    py: Python<'_>,
    domain: &str,
    problem: &str,
    optimal: bool,
    timeout_s: Option<f64>,
) -> PyResult<Option<Vec<String>>> {
    let timeout = match timeout_s {
        Some(t) if t.is_finite() && t > 0.0 => Some(Duration::from_secs_f64(t.min(1e6))),
        Some(t) => {
            return Err(value_error(format!(
                "timeout_s must be a positive number of seconds, not {t}"
            )));
        }
        None => None,
    };
    let domain = parse_domain(domain).map_err(value_error)?;
    let problem = parse_problem(problem, &domain).map_err(value_error)?;
    let mode = if optimal {
        SearchMode::Optimal
    } else {
        SearchMode::Fast
    };
    let plan = py.detach(|| {
        Planner::new(domain, problem, GroundOptions::default())
            .map_err(NoPlan::from)
            .and_then(|p| p.plan(mode, timeout))
    });
    match plan {
        Ok(plan) => Ok(Some(plan.steps.iter().map(ToString::to_string).collect())),
        Err(NoPlan::Unsolvable) => Ok(None),
        Err(NoPlan::Timeout) => Err(pyo3::exceptions::PyTimeoutError::new_err(
            NoPlan::Timeout.to_string(),
        )),
        Err(e) => Err(value_error(e)),
    }
}
