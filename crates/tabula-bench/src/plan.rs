//! The task-planning benchmark: table-clearing problems in seed 002's PDDL domain,
//! grounded and planned in process — optimal plans, replanning after one IK-infeasible
//! fact (the seed's loop), greedy plans, ten decisions of the loop, the goal check.

use crate::stats::median;
use anyhow::Result;
use serde::Serialize;
use std::time::{Duration, Instant};
use tabula_pddl::generator::table_clearing_problem;
use tabula_pddl::{
    Domain, GroundAtom, GroundOptions, PlanStep, Planner, SearchMode, parse_problem,
};

/// One table size's medians (ms) and means over its problems (fields in the order
/// JSON has always listed them).
#[derive(Serialize)]
pub struct SizeRow {
    pub fast_ms: f64,
    pub goal_check_ms: f64,
    pub ground_ms: f64,
    pub ground_plus_optimal_ms: f64,
    pub loop10_ms: f64,
    pub mean_expanded: f64,
    pub mean_fast_length: f64,
    pub mean_optimal_length: f64,
    pub objects: usize,
    pub optimal_ms: f64,
    pub problems: u64,
    pub replan_ms: f64,
    pub solved: u64,
}

/// Times of one problem (ms); `None` where that step found no plan.
#[derive(Default)]
struct Times {
    ground: Vec<f64>,
    check: Vec<f64>,
    optimal: Vec<f64>,
    total: Vec<f64>,
    replan: Vec<f64>,
    fast: Vec<f64>,
    loop10: Vec<f64>,
    optimal_length: usize,
    fast_length: usize,
    expanded: usize,
    solved: u64,
}

/// The fact that marks a table-clearing step as having no IK solution (seed 002's
/// `ik_unfeasible_grasp` / `ik_unfeasible_<direction>`), as the task's loop sets it.
pub fn infeasible(step: &PlanStep) -> GroundAtom {
    GroundAtom {
        predicate: if step.action == "grasp" {
            "ik_unfeasible_grasp".into()
        } else {
            format!("ik_unfeasible_{}", step.action.trim_start_matches("push_"))
        },
        args: step.args.clone(),
    }
}

const PLAN_LIMIT: Duration = Duration::from_secs(60);

fn ms(t: Instant) -> f64 {
    t.elapsed().as_secs_f64() * 1e3
}

/// Problems `1..=problems` of `objects` objects in `domain`, each grounded and planned.
pub fn size_row(domain: &Domain, objects: usize, problems: u64) -> Result<SizeRow> {
    let mut t = Times::default();
    for seed in 1..=problems {
        one_problem(domain, objects, seed, &mut t)?;
    }
    let k = t.solved.max(1) as f64;
    let m = |v: &[f64]| median(v).unwrap_or(0.0);
    Ok(SizeRow {
        fast_ms: m(&t.fast),
        goal_check_ms: m(&t.check),
        ground_ms: m(&t.ground),
        ground_plus_optimal_ms: m(&t.total),
        loop10_ms: m(&t.loop10),
        mean_expanded: t.expanded as f64 / k,
        mean_fast_length: t.fast_length as f64 / k,
        mean_optimal_length: t.optimal_length as f64 / k,
        objects,
        optimal_ms: m(&t.optimal),
        problems,
        replan_ms: m(&t.replan),
        solved: t.solved,
    })
}

fn one_problem(domain: &Domain, n: usize, seed: u64, t: &mut Times) -> Result<()> {
    let problem = parse_problem(&table_clearing_problem(n, seed), domain)?;
    let t0 = Instant::now();
    let options = GroundOptions::switchable(domain, "ik_unfeasible");
    let mut planner = Planner::new(domain.clone(), problem, options)?;
    t.ground.push(ms(t0));
    let t0 = Instant::now();
    planner.drop_unreachable_goals(tabula_pddl::Budget::UNLIMITED)?;
    t.check.push(ms(t0));
    let t0 = Instant::now();
    let Ok(plan) = planner.plan(SearchMode::Optimal, Some(PLAN_LIMIT)) else {
        return Ok(());
    };
    t.optimal.push(ms(t0));
    t.total
        .push(t.ground.last().copied().unwrap_or(0.0) + t.optimal.last().copied().unwrap_or(0.0));
    t.solved += 1;
    t.optimal_length += plan.steps.len();
    t.expanded += plan.expanded;
    // The seed's loop: the first action turns out IK-infeasible; mark it, replan.
    let fact = infeasible(&plan.steps[0]);
    let t0 = Instant::now();
    planner.set_fact(&fact, true)?;
    let _ = planner.plan(SearchMode::Optimal, Some(PLAN_LIMIT));
    t.replan.push(ms(t0));
    planner.set_fact(&fact, false)?;
    let t0 = Instant::now();
    if let Ok(p) = planner.plan(SearchMode::Fast, Some(PLAN_LIMIT)) {
        t.fast.push(ms(t0));
        t.fast_length += p.steps.len();
    }
    // The seed's loop, ten decisions: plan optimally, execute the first action.
    let mut looping = planner.clone();
    let t0 = Instant::now();
    for _ in 0..10 {
        match looping.plan(SearchMode::Optimal, Some(PLAN_LIMIT)) {
            Ok(p) if !p.steps.is_empty() => looping.execute(&p.steps[0])?,
            _ => break,
        }
    }
    t.loop10.push(ms(t0));
    Ok(())
}
