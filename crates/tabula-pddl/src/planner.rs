//! The in-process planning API of the clearing loop (SPEC §3.5): ground once, then
//! change facts and the goal and replan without parsing or grounding again.

use crate::ground::{GroundError, GroundOptions, GroundTask, Lit};
use crate::search::{Budget, SearchResult, SearchStatus, astar, gbfs};
use crate::*;
use std::time::Duration;

/// Which search to run.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum SearchMode {
    /// A* + LM-cut + strong stubborn sets: a cheapest plan.
    Optimal,
    /// Greedy best-first with h^FF and preferred operators: a plan, fast.
    Fast,
}

/// A plan and how it was found.
#[derive(Debug, Clone)]
pub struct Plan {
    pub steps: Vec<PlanStep>,
    pub cost: u64,
    pub optimal: bool,
    pub expanded: usize,
    pub generated: usize,
}

/// Why there is no plan.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum NoPlan {
    #[error("unsolvable: no plan exists (search space exhausted)")]
    Unsolvable,
    #[error("no plan found within the search budget (time or expanded states)")]
    Timeout,
    #[error("{0}")]
    Ground(#[from] GroundError),
}

/// A grounded problem kept ready for repeated planning.
#[derive(Debug, Clone)]
pub struct Planner {
    domain: Domain,
    problem: Problem,
    options: GroundOptions,
    task: GroundTask,
}

impl Planner {
    /// Grounds `problem`. Predicates in `options.mutable_predicates` stay switchable.
    pub fn new(
        domain: Domain,
        problem: Problem,
        options: GroundOptions,
    ) -> Result<Self, GroundError> {
        let task = GroundTask::new(&domain, &problem, &options)?;
        Ok(Self {
            domain,
            problem,
            options,
            task,
        })
    }

    pub fn task(&self) -> &GroundTask {
        &self.task
    }

    pub fn problem(&self) -> &Problem {
        &self.problem
    }

    pub fn domain(&self) -> &Domain {
        &self.domain
    }

    /// Sets a fact of the initial state. A fluent (or switchable) atom only flips a bit;
    /// any other atom changes the problem and grounds it again.
    pub fn set_fact(&mut self, atom: &GroundAtom, value: bool) -> Result<(), GroundError> {
        if value {
            if !self.problem.init.contains(atom) {
                self.problem.init.push(atom.clone());
            }
        } else {
            self.problem.init.retain(|a| a != atom);
        }
        match self.task.fact(atom) {
            Some(f) => {
                self.task.init[f as usize] = value;
                Ok(())
            }
            None => self.reground(),
        }
    }

    /// Replaces the goal by a conjunction of atoms.
    pub fn set_goal(&mut self, atoms: &[GroundAtom]) -> Result<(), GroundError> {
        self.problem.goal = Condition::And(
            atoms
                .iter()
                .map(|a| {
                    Condition::Atom(Atom {
                        predicate: a.predicate.clone(),
                        args: a.args.iter().map(|o| Term::Const(o.clone())).collect(),
                    })
                })
                .collect(),
        );
        let mut lits = Vec::with_capacity(atoms.len());
        for a in atoms {
            if self.task.constant_true.contains(a) {
                continue;
            }
            match self.task.fact(a) {
                Some(fact) => lits.push(Lit {
                    fact,
                    positive: true,
                }),
                // Never true and not fluent: the goal cannot be reached.
                None => return self.reground(),
            }
        }
        self.task.goal = lits;
        self.task.goal_unreachable = false;
        Ok(())
    }

    /// The goal's atoms, when the goal is a conjunction of atoms.
    pub fn goal_atoms(&self) -> Option<Vec<GroundAtom>> {
        fn collect(c: &Condition, out: &mut Vec<GroundAtom>) -> bool {
            match c {
                Condition::And(items) => items.iter().all(|i| collect(i, out)),
                Condition::Atom(a) => {
                    let mut args = Vec::new();
                    for t in &a.args {
                        match t {
                            Term::Const(c) => args.push(c.clone()),
                            Term::Var(_) => return false,
                        }
                    }
                    out.push(GroundAtom {
                        predicate: a.predicate.clone(),
                        args,
                    });
                    true
                }
                Condition::True => true,
                _ => false,
            }
        }
        let mut out = Vec::new();
        collect(&self.problem.goal, &mut out).then_some(out)
    }

    fn reground(&mut self) -> Result<(), GroundError> {
        self.task = GroundTask::new(&self.domain, &self.problem, &self.options)?;
        Ok(())
    }

    /// Plans from the current initial state within a wall-clock limit.
    pub fn plan(&self, mode: SearchMode, timeout: Option<Duration>) -> Result<Plan, NoPlan> {
        self.plan_within(mode, Budget::timeout(timeout))
    }

    /// Plans from the current initial state within a budget: with `max_expanded` set the
    /// answer does not depend on the machine's speed or load.
    pub fn plan_within(&self, mode: SearchMode, budget: Budget) -> Result<Plan, NoPlan> {
        let r = match mode {
            SearchMode::Optimal => astar(&self.task, true, budget),
            SearchMode::Fast => gbfs(&self.task, budget),
        };
        self.to_plan(r, mode == SearchMode::Optimal)
    }

    fn to_plan(&self, r: SearchResult, optimal: bool) -> Result<Plan, NoPlan> {
        match r.status {
            SearchStatus::Unsolvable => Err(NoPlan::Unsolvable),
            SearchStatus::Timeout => Err(NoPlan::Timeout),
            SearchStatus::Solved => Ok(Plan {
                steps: r
                    .plan
                    .iter()
                    .map(|&a| &self.task.actions[a])
                    .filter(|a| !a.artificial)
                    .map(|a| {
                        let inner = a.name.trim_start_matches('(').trim_end_matches(')');
                        let mut words = inner.split_whitespace().map(String::from);
                        PlanStep {
                            action: words.next().unwrap_or_default(),
                            args: words.collect(),
                        }
                    })
                    .collect(),
                cost: r.cost,
                optimal,
                expanded: r.expanded,
                generated: r.generated,
            }),
        }
    }

    /// Applies one step to the initial state (the robot executed it), so the next
    /// [`Self::plan`] starts after it — the seed's loop without re-perceiving.
    pub fn execute(&mut self, step: &PlanStep) -> Result<(), PlanError> {
        let name = step.to_string();
        let state = self.task.initial_state();
        let Some(a) = self
            .task
            .actions
            .iter()
            .position(|a| a.name == name && !a.artificial)
        else {
            return Err(PlanError::UnknownAction {
                step: 1,
                text: name,
                name: step.action.clone(),
            });
        };
        if !self.task.applicable(&state, a) {
            return Err(PlanError::PreconditionFalse {
                step: 1,
                text: name,
            });
        }
        let next = self.task.apply(&state, a);
        for (f, atom) in self.task.facts.iter().enumerate() {
            let now = GroundTask::holds(
                &next,
                Lit {
                    fact: f as u32,
                    positive: true,
                },
            );
            self.task.init[f] = now;
            let was = self.problem.init.iter().position(|x| x == atom);
            match (now, was) {
                (true, None) => self.problem.init.push(atom.clone()),
                (false, Some(i)) => {
                    self.problem.init.swap_remove(i);
                }
                _ => {}
            }
        }
        Ok(())
    }

    /// Goal atoms that no plan can ever reach from the current state, each checked on
    /// its own (a relaxed test first, then a complete greedy search). In the clearing
    /// domain this is every object that can never be removed — those whose every action
    /// is IK-infeasible (the seed's rule) and also, e.g., two objects blocking each
    /// other's grasp with every push blocked, which the seed's rule misses.
    /// Each search runs within `budget_each`; one that runs out keeps its atom.
    pub fn unreachable_goal_atoms(&self, budget_each: Budget) -> Vec<GroundAtom> {
        let Some(atoms) = self.goal_atoms() else {
            return Vec::new();
        };
        // The whole goal reachable: nothing to drop.
        if gbfs(&self.task, budget_each).status == SearchStatus::Solved {
            return Vec::new();
        }
        let relaxed_reachable =
            crate::heuristic::Relaxed::new(&self.task).reachable_facts(&self.task.initial_state());
        let mut out = Vec::new();
        for a in atoms {
            if self.task.constant_true.contains(&a) {
                continue;
            }
            let Some(fact) = self.task.fact(&a) else {
                out.push(a);
                continue;
            };
            // Not even reachable in the delete relaxation: certainly unreachable.
            if !relaxed_reachable[fact as usize] {
                out.push(a);
                continue;
            }
            let mut single = self.task.clone();
            single.goal = vec![Lit {
                fact,
                positive: true,
            }];
            single.goal_unreachable = false;
            if gbfs(&single, budget_each).status == SearchStatus::Unsolvable {
                out.push(a);
            }
        }
        out
    }

    /// Drops every unreachable goal atom (see [`Self::unreachable_goal_atoms`]) and
    /// returns them.
    pub fn drop_unreachable_goals(
        &mut self,
        budget_each: Budget,
    ) -> Result<Vec<GroundAtom>, GroundError> {
        let dropped = self.unreachable_goal_atoms(budget_each);
        if let Some(atoms) = self.goal_atoms()
            && !dropped.is_empty()
        {
            let keep: Vec<GroundAtom> =
                atoms.into_iter().filter(|a| !dropped.contains(a)).collect();
            self.set_goal(&keep)?;
        }
        Ok(dropped)
    }
}
