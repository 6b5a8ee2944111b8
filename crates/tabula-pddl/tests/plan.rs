//! Planning on the seed's problems, classic domains and generated tables; every plan is
//! checked by the independent validator.

use std::time::Duration;
use tabula_pddl::generator::table_clearing_problem;
use tabula_pddl::*;

const DATA: &str = concat!(env!("CARGO_MANIFEST_DIR"), "/../../pddl/");

fn read(name: &str) -> String {
    std::fs::read_to_string(format!("{DATA}{name}")).unwrap()
}

fn seed_domain() -> Domain {
    parse_domain(&read("tablewclear-domain.pddl")).unwrap()
}

fn solve(domain: &Domain, problem: &Problem, mode: SearchMode) -> Result<Plan, NoPlan> {
    let planner = Planner::new(domain.clone(), problem.clone(), GroundOptions::default())?;
    let plan = planner.plan(mode, Some(Duration::from_secs(20)))?;
    let cost = validate(domain, problem, &plan.steps)
        .unwrap_or_else(|e| panic!("invalid plan: {e}\n{:?}", plan.steps));
    assert_eq!(cost, plan.cost);
    Ok(plan)
}

#[test]
fn seed_problems_have_their_optimal_lengths() {
    let d = seed_domain();
    for (name, length) in [
        ("thesis6-a", 9),
        ("thesis6-b", 10),
        ("thesis6-c", 11),
        ("thesis6-d-dropped", 9),
    ] {
        let p = parse_problem(&read(&format!("{name}.pddl")), &d).unwrap();
        let plan = solve(&d, &p, SearchMode::Optimal).unwrap_or_else(|e| panic!("{name}: {e}"));
        assert_eq!(plan.steps.len(), length, "{name}: {:?}", plan.steps);
        let fast = solve(&d, &p, SearchMode::Fast).unwrap();
        assert!(fast.steps.len() >= length);
    }
    let p = parse_problem(&read("thesis6-unsolvable.pddl"), &d).unwrap();
    assert_eq!(
        solve(&d, &p, SearchMode::Optimal).unwrap_err(),
        NoPlan::Unsolvable
    );
    assert_eq!(
        solve(&d, &p, SearchMode::Fast).unwrap_err(),
        NoPlan::Unsolvable
    );
}

#[test]
fn generated_tables_solve_optimally_and_validate() {
    let d = seed_domain();
    for (n, seed) in [(6, 1), (10, 2), (20, 3), (40, 4)] {
        let p = parse_problem(&table_clearing_problem(n, seed), &d).unwrap();
        let mut planner = Planner::for_table_clearing(d.clone(), p.clone()).unwrap();
        let dropped = planner.drop_unreachable_goals(None).unwrap();
        let pruned_problem = planner.problem().clone();
        let opt = planner
            .plan(SearchMode::Optimal, Some(Duration::from_secs(20)))
            .unwrap_or_else(|e| panic!("n={n}: {e}"));
        validate(&d, &pruned_problem, &opt.steps).unwrap();
        let fast = planner
            .plan(SearchMode::Fast, Some(Duration::from_secs(20)))
            .unwrap();
        validate(&d, &pruned_problem, &fast.steps).unwrap();
        assert!(fast.cost >= opt.cost, "n={n}");
        assert!(opt.steps.len() >= n - dropped.len());
    }
}
