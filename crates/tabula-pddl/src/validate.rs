//! An independent plan validator: it works on the lifted domain and problem (sets of
//! ground atoms, quantifiers evaluated over the objects), sharing no code with the
//! grounder or the search, so a bug there cannot hide itself here.

use crate::*;
use std::collections::HashSet;

/// Why a plan is not valid.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum PlanError {
    #[error("plan line {line}: cannot read `{text}`: expected `(action arg…)`")]
    Syntax { line: usize, text: String },
    #[error("step {step} `{text}`: no action `{name}` in the domain")]
    UnknownAction {
        step: usize,
        text: String,
        name: String,
    },
    #[error("step {step} `{text}`: {why}")]
    BadArguments {
        step: usize,
        text: String,
        why: String,
    },
    #[error("step {step} `{text}`: precondition does not hold")]
    PreconditionFalse { step: usize, text: String },
    #[error("the goal does not hold after the last step")]
    GoalNotReached,
    #[error("{0}")]
    Cost(String),
}

/// One step of a plan: action name and object names.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct PlanStep {
    pub action: String,
    pub args: Vec<String>,
}

impl std::fmt::Display for PlanStep {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        if self.args.is_empty() {
            write!(f, "({})", self.action)
        } else {
            write!(f, "({} {})", self.action, self.args.join(" "))
        }
    }
}

/// Reads a plan in Fast Downward's `sas_plan` format (`;` comments, one step a line).
pub fn parse_plan(text: &str) -> Result<Vec<PlanStep>, PlanError> {
    let mut steps = Vec::new();
    for (i, line) in text.lines().enumerate() {
        let line = line.split(';').next().unwrap_or("").trim();
        if line.is_empty() {
            continue;
        }
        let inner = line
            .strip_prefix('(')
            .and_then(|l| l.strip_suffix(')'))
            .filter(|l| !l.contains(['(', ')']))
            .ok_or_else(|| PlanError::Syntax {
                line: i + 1,
                text: line.to_string(),
            })?;
        let mut words = inner.split_whitespace().map(str::to_lowercase);
        let Some(action) = words.next() else {
            return Err(PlanError::Syntax {
                line: i + 1,
                text: line.to_string(),
            });
        };
        steps.push(PlanStep {
            action,
            args: words.collect(),
        });
    }
    Ok(steps)
}

struct World<'a> {
    domain: &'a Domain,
    problem: &'a Problem,
    state: HashSet<GroundAtom>,
}

type Binding = Vec<(String, String)>;

impl World<'_> {
    fn objects(&self, t: &str) -> Vec<String> {
        self.domain
            .constants
            .iter()
            .chain(&self.problem.objects)
            .filter(|o| self.domain.is_subtype(&o.type_name, t))
            .map(|o| o.name.clone())
            .collect()
    }

    fn value(term: &Term, b: &Binding) -> String {
        match term {
            Term::Const(c) => c.clone(),
            Term::Var(v) => b
                .iter()
                .rev()
                .find(|(n, _)| n == v)
                .map(|(_, o)| o.clone())
                .unwrap_or_default(),
        }
    }

    fn atom(a: &Atom, b: &Binding) -> GroundAtom {
        GroundAtom {
            predicate: a.predicate.clone(),
            args: a.args.iter().map(|t| Self::value(t, b)).collect(),
        }
    }

    fn bindings(&self, vars: &[TypedName], b: &Binding) -> Vec<Binding> {
        let mut out = vec![b.clone()];
        for v in vars {
            let objs = self.objects(&v.type_name);
            out = out
                .into_iter()
                .flat_map(|b| {
                    objs.iter().map(move |o| {
                        let mut nb = b.clone();
                        nb.push((v.name.clone(), o.clone()));
                        nb
                    })
                })
                .collect();
        }
        out
    }

    fn holds(&self, c: &Condition, b: &Binding) -> bool {
        match c {
            Condition::True => true,
            Condition::Atom(a) => self.state.contains(&Self::atom(a, b)),
            Condition::Equal(x, y) => Self::value(x, b) == Self::value(y, b),
            Condition::Not(i) => !self.holds(i, b),
            Condition::And(items) => items.iter().all(|i| self.holds(i, b)),
            Condition::Or(items) => items.iter().any(|i| self.holds(i, b)),
            Condition::Imply(x, y) => !self.holds(x, b) || self.holds(y, b),
            Condition::Exists(vars, body) => {
                self.bindings(vars, b).iter().any(|nb| self.holds(body, nb))
            }
            Condition::Forall(vars, body) => {
                self.bindings(vars, b).iter().all(|nb| self.holds(body, nb))
            }
        }
    }

    /// Collects adds, deletes and cost of `e` evaluated in the current state.
    fn effects(
        &self,
        e: &Effect,
        b: &Binding,
        out: &mut (Vec<GroundAtom>, Vec<GroundAtom>, i64),
    ) -> Result<(), PlanError> {
        match e {
            Effect::And(items) => {
                for i in items {
                    self.effects(i, b, out)?;
                }
            }
            Effect::Add(a) => out.0.push(Self::atom(a, b)),
            Effect::Delete(a) => out.1.push(Self::atom(a, b)),
            Effect::Forall(vars, body) => {
                for nb in self.bindings(vars, b) {
                    self.effects(body, &nb, out)?;
                }
            }
            Effect::When(c, body) => {
                if self.holds(c, b) {
                    self.effects(body, b, out)?;
                }
            }
            Effect::IncreaseCost(CostExpr::Constant(v)) => out.2 += v,
            Effect::IncreaseCost(CostExpr::Function(f, args)) => {
                let g = GroundAtom {
                    predicate: f.clone(),
                    args: args.iter().map(|t| Self::value(t, b)).collect(),
                };
                let v = self
                    .problem
                    .init_numeric
                    .iter()
                    .find(|(a, _)| *a == g)
                    .map(|(_, v)| *v)
                    .ok_or_else(|| {
                        PlanError::Cost(format!("no value for ({} {})", f, g.args.join(" ")))
                    })?;
                out.2 += v;
            }
        }
        Ok(())
    }
}

/// Applies `plan` from the initial state, checking every precondition and the goal.
/// Returns the plan's cost (unit cost unless the problem minimises total-cost).
pub fn validate(domain: &Domain, problem: &Problem, plan: &[PlanStep]) -> Result<u64, PlanError> {
    let mut world = World {
        domain,
        problem,
        state: problem.init.iter().cloned().collect(),
    };
    let unit = !(domain.uses_action_costs() && problem.minimize_total_cost);
    let mut cost = 0u64;
    for (i, step) in plan.iter().enumerate() {
        let text = step.to_string();
        let Some(action) = domain.actions.iter().find(|a| a.name == step.action) else {
            return Err(PlanError::UnknownAction {
                step: i + 1,
                text,
                name: step.action.clone(),
            });
        };
        if action.params.len() != step.args.len() {
            return Err(PlanError::BadArguments {
                step: i + 1,
                text,
                why: format!("takes {} arguments", action.params.len()),
            });
        }
        let mut binding = Binding::new();
        for (p, o) in action.params.iter().zip(&step.args) {
            if !world.objects(&p.type_name).contains(o) {
                return Err(PlanError::BadArguments {
                    step: i + 1,
                    text,
                    why: format!("`{o}` is not an object of type `{}`", p.type_name),
                });
            }
            binding.push((p.name.clone(), o.clone()));
        }
        if !world.holds(&action.precondition, &binding) {
            return Err(PlanError::PreconditionFalse { step: i + 1, text });
        }
        let mut eff = (Vec::new(), Vec::new(), 0i64);
        world.effects(&action.effect, &binding, &mut eff)?;
        for d in &eff.1 {
            world.state.remove(d);
        }
        world.state.extend(eff.0);
        cost = cost.saturating_add(if unit { 1 } else { eff.2.max(0) as u64 });
    }
    if !world.holds(&problem.goal, &Binding::new()) {
        return Err(PlanError::GoalNotReached);
    }
    Ok(cost)
}
