//! `tabula plan …`: plan with PDDL files, validate plans, benchmark the planner.

use anyhow::{Context, Result, bail};
use clap::{Args, Subcommand};
use std::path::{Path, PathBuf};
use std::time::{Duration, Instant};
use tabula_geom::input::{Format, read_text};
use tabula_pddl::generator::table_clearing_problem;
use tabula_pddl::{
    Budget, Domain, GroundError, GroundOptions, NoPlan, Planner, Problem, SearchMode, parse_domain,
    parse_plan, parse_problem, validate,
};

#[derive(Args)]
#[command(args_conflicts_with_subcommands = true)]
pub struct PlanArgs {
    #[command(subcommand)]
    command: Option<PlanCommand>,
    /// DOMAIN PROBLEM to plan, or DOMAIN PROBLEM PLAN with --validate.
    files: Vec<PathBuf>,
    /// A cheapest plan: A* + LM-cut + strong stubborn sets (the default).
    #[arg(long, conflicts_with = "fast")]
    optimal: bool,
    /// A plan fast: greedy best-first with h^FF and preferred operators.
    #[arg(long)]
    fast: bool,
    /// Time limit in seconds, grounding included (an unsolvable problem too large to
    /// exhaust ends there, with exit status 2).
    #[arg(long, default_value_t = 600.0, value_parser = crate::args::seconds)]
    timeout: f64,
    /// Give up after expanding this many states: unlike `--timeout`, the same answer on
    /// any machine under any load.
    #[arg(long, value_parser = crate::args::count)]
    max_expanded: Option<usize>,
    /// Check PLAN against DOMAIN and PROBLEM instead of planning.
    #[arg(long)]
    validate: bool,
    /// Print one JSON object.
    #[arg(long)]
    json: bool,
}

#[derive(Subcommand)]
enum PlanCommand {
    /// Time the planner in process on generated table-clearing problems.
    Bench(BenchArgs),
    /// Print a generated table-clearing problem (seed 002's domain).
    Generate {
        #[arg(long, default_value_t = 10, value_parser = crate::args::objects)]
        objects: usize,
        #[arg(long, default_value_t = 1, value_parser = crate::args::seed)]
        seed: u64,
    },
}

#[derive(Args)]
struct BenchArgs {
    /// Object counts, comma separated.
    #[arg(long, value_delimiter = ',', default_value = "10,20,30,40,100", value_parser = crate::args::objects)]
    objects: Vec<usize>,
    /// Problems per object count (seeds 1..=N).
    #[arg(long, default_value_t = 5, value_parser = crate::args::count_u64)]
    problems: u64,
    #[arg(long)]
    json: bool,
    /// Write a report into this folder: planning time per table size.
    #[arg(long)]
    report: Option<std::path::PathBuf>,
}

fn read(path: &Path) -> Result<String> {
    Ok(read_text(path, Format::Pddl)?)
}

fn load(domain: &Path, problem: &Path) -> Result<(Domain, Problem)> {
    let d = parse_domain(&read(domain)?).map_err(|e| e.in_file(domain.display().to_string()))?;
    let p =
        parse_problem(&read(problem)?, &d).map_err(|e| e.in_file(problem.display().to_string()))?;
    Ok((d, p))
}

pub fn run(a: PlanArgs) -> Result<()> {
    match a.command {
        Some(PlanCommand::Bench(b)) => return bench(b),
        Some(PlanCommand::Generate { objects, seed }) => {
            print!("{}", table_clearing_problem(objects, seed));
            return Ok(());
        }
        None => {}
    }
    if a.validate {
        let [domain, problem, plan] = a.files.as_slice() else {
            bail!("--validate needs DOMAIN PROBLEM PLAN");
        };
        let (d, p) = load(domain, problem)?;
        let steps = parse_plan(&read(plan)?)?;
        let cost = validate(&d, &p, &steps)
            .with_context(|| format!("{} is not a valid plan", plan.display()))?;
        println!("plan valid: {} steps, cost {cost}", steps.len());
        return Ok(());
    }
    let [domain, problem] = a.files.as_slice() else {
        bail!("usage: tabula plan DOMAIN PROBLEM [--optimal|--fast] [--timeout S] [--json]");
    };
    let (d, p) = load(domain, problem)?;
    let mode = if a.fast {
        SearchMode::Fast
    } else {
        SearchMode::Optimal
    };
    let t0 = Instant::now();
    let progress = crate::progress::spinner("grounding");
    let deadline = t0 + Duration::from_secs_f64(a.timeout);
    let options = GroundOptions {
        deadline: Some(deadline),
        ..GroundOptions::default()
    };
    let planner = match Planner::new(d, p, options) {
        Ok(planner) => planner,
        Err(GroundError::Timeout) => {
            progress.finish_and_clear();
            if a.json {
                println!(
                    "{}",
                    serde_json::json!({"status": "timeout", "message": "still grounding at the time limit"})
                );
            }
            eprintln!("no plan found within the time limit (still grounding)");
            std::process::exit(crate::exit::NO_SOLUTION);
        }
        Err(e) => return Err(e.into()),
    };
    let ground_ms = t0.elapsed().as_secs_f64() * 1e3;
    let t1 = Instant::now();
    progress.set_message("searching");
    let budget = Budget {
        timeout: Some(deadline.saturating_duration_since(t1)),
        max_expanded: a.max_expanded,
    };
    let result = planner.plan_within(mode, budget);
    let search_ms = t1.elapsed().as_secs_f64() * 1e3;
    progress.finish_and_clear();
    let unit = !(planner.domain().uses_action_costs() && planner.problem().minimize_total_cost);
    if a.json {
        let value = match &result {
            Ok(plan) => serde_json::json!({
                "status": "solved", "optimal": plan.optimal, "cost": plan.cost,
                "plan": plan.steps.iter().map(ToString::to_string).collect::<Vec<_>>(),
                "expanded": plan.expanded, "ground_ms": ground_ms, "search_ms": search_ms,
            }),
            Err(e) => serde_json::json!({
                "status": match e { NoPlan::Unsolvable => "unsolvable", NoPlan::Timeout => "timeout", NoPlan::Ground(_) => "error" },
                "message": e.to_string(), "ground_ms": ground_ms, "search_ms": search_ms,
            }),
        };
        println!("{}", serde_json::to_string_pretty(&value)?);
        return match result {
            Ok(_) => Ok(()),
            // Not an error of the input, but no plan either: scripts must be able to
            // tell (exit status 2, as `pick-place` uses for a task that failed).
            Err(NoPlan::Unsolvable | NoPlan::Timeout) => {
                std::process::exit(crate::exit::NO_SOLUTION)
            }
            Err(e) => Err(e.into()),
        };
    }
    match result {
        Ok(plan) => {
            for s in &plan.steps {
                println!("{s}");
            }
            println!(
                "; cost = {} ({})",
                plan.cost,
                if unit { "unit cost" } else { "general cost" }
            );
            eprintln!(
                "; {} plan, {} expanded, grounding {ground_ms:.2} ms, search {search_ms:.2} ms",
                if plan.optimal { "optimal" } else { "greedy" },
                plan.expanded
            );
            Ok(())
        }
        Err(NoPlan::Unsolvable) => {
            println!("; unsolvable: the search space was exhausted, no plan exists");
            std::process::exit(crate::exit::NO_SOLUTION)
        }
        Err(NoPlan::Timeout) => {
            println!("; no plan found within the time limit or --max-expanded");
            std::process::exit(crate::exit::NO_SOLUTION)
        }
        Err(e) => Err(e.into()),
    }
}

fn bench(b: BenchArgs) -> Result<()> {
    use tabula_bench::report::plan::{bench_page, header_lines, row_line};
    let domain = parse_domain(include_str!("../../../pddl/tablewclear-domain.pddl"))?;
    let mut rows = Vec::new();
    if !b.json {
        for line in header_lines(b.problems) {
            println!("{line}");
        }
    }
    let progress = crate::progress::steps(b.objects.len() as u64, "sizes");
    for &n in &b.objects {
        let _tick = crate::progress::Tick(&progress);
        progress.set_message(format!("{n} objects"));
        let r = tabula_bench::plan::size_row(&domain, n, b.problems)?;
        if !b.json {
            println!("{}", row_line(&r, b.problems));
        }
        rows.push(serde_json::to_value(&r)?);
    }
    progress.finish_and_clear();
    if let Some(dir) = &b.report {
        bench_page(dir, (&b.objects, b.problems), &rows)?;
    }
    if b.json {
        println!("{}", serde_json::to_string(&rows)?);
    }
    Ok(())
}
