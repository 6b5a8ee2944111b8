//! Grounding: the lifted domain and problem become a propositional task.
//!
//! Conditions are grounded into negation normal form with quantifiers expanded over
//! the typed objects, static predicates (in no effect) and equality evaluated on the
//! spot, and then put in DNF (one ground action per disjunct). A fixpoint of relaxed
//! reachability (positive conditions only) then finds which atoms can ever change;
//! every other atom is a constant and disappears from the task. Only the remaining
//! *fluent* atoms get ids; states are bit sets over them.

mod finish;
mod formula;
mod grounder;
mod init;

use crate::*;
use finish::finish;
use formula::*;
use grounder::*;
use init::*;
use rustc_hash::FxHashMap;
use std::collections::{HashMap, HashSet};

/// Why grounding failed.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum GroundError {
    #[error("grounding `{action}` needs {combinations} parameter combinations (limit {limit})")]
    TooLarge {
        action: String,
        combinations: u128,
        limit: u128,
    },
    #[error(
        "grounding visits more than {0} bindings (parameters and quantified variables); \
         the problem is too large to ground"
    )]
    TooMuchWork(u64),
    #[error("grounding ran past the time limit")]
    Timeout,
    #[error("a condition of `{0}` expands to more than 100000 disjuncts")]
    DnfTooLarge(String),
    #[error("action `{action}`: cost `({function})` has no value in the problem's :init")]
    MissingCost { action: String, function: String },
    #[error("action `{0}` would have a negative cost")]
    NegativeCost(String),
}

/// A literal over a fluent fact.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub struct Lit {
    pub fact: u32,
    pub positive: bool,
}

/// An effect on one fact, applied when every literal of `cond` holds before the action.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct CondEffect {
    pub cond: Vec<Lit>,
    pub fact: u32,
    pub add: bool,
}

/// A ground action.
#[derive(Debug, Clone, PartialEq)]
pub struct GroundAction {
    /// `(name arg…)`, as a plan prints it.
    pub name: String,
    pub pre: Vec<Lit>,
    pub effects: Vec<CondEffect>,
    pub cost: u64,
    /// Made up by the grounder (disjunctive goals); never printed in a plan.
    pub artificial: bool,
}

/// What grounding may keep variable beyond what the actions change.
#[derive(Debug, Clone, Default)]
pub struct GroundOptions {
    /// Predicates whose atoms stay in the task even if no action changes them, so that a
    /// replanning caller can switch them on and off (e.g. `ik_unfeasible_grasp`).
    pub mutable_predicates: Vec<String>,
    /// Grounding stops with [`GroundError::Timeout`] past this instant (a planner's
    /// time limit covers grounding too).
    pub deadline: Option<std::time::Instant>,
}

impl GroundOptions {
    /// Options keeping every predicate of `domain` whose name starts with `prefix`
    /// switchable (e.g. `ik_unfeasible` for a caller that backtracks by such facts
    /// without grounding again).
    pub fn switchable(domain: &Domain, prefix: &str) -> Self {
        Self {
            mutable_predicates: domain
                .predicates
                .iter()
                .filter(|p| p.name.starts_with(prefix))
                .map(|p| p.name.clone())
                .collect(),
            ..Self::default()
        }
    }
}

/// The propositional task.
#[derive(Debug, Clone)]
pub struct GroundTask {
    /// Fluent atoms; a state is one bit per entry.
    pub facts: Vec<GroundAtom>,
    pub fact_index: HashMap<GroundAtom, u32>,
    pub init: Vec<bool>,
    /// Conjunction of literals. `goal_unreachable` when no disjunct can ever hold.
    pub goal: Vec<Lit>,
    pub goal_unreachable: bool,
    pub actions: Vec<GroundAction>,
    /// Atoms that are true in every reachable state (not in `facts`).
    pub constant_true: HashSet<GroundAtom>,
}

/// A literal over a raw (not yet renumbered) atom id.
type RawLit = (u32, bool);

struct Raw {
    name: String,
    pre: Vec<RawLit>,
    /// (condition, atom, add)
    effects: Vec<(Vec<RawLit>, u32, bool)>,
    cost: u64,
    artificial: bool,
}

/// Predicates in any effect, and those in an add effect.
fn predicates_in_effects(e: &Effect, any: &mut HashSet<String>, added: &mut HashSet<String>) {
    match e {
        Effect::And(items) => items
            .iter()
            .for_each(|i| predicates_in_effects(i, any, added)),
        Effect::Add(a) => {
            any.insert(a.predicate.clone());
            added.insert(a.predicate.clone());
        }
        Effect::Delete(a) => {
            any.insert(a.predicate.clone());
        }
        Effect::Forall(_, b) | Effect::When(_, b) => predicates_in_effects(b, any, added),
        Effect::IncreaseCost(_) => {}
    }
}

/// Largest number of parameter combinations one action schema may expand to.
pub const GROUNDING_LIMIT: u128 = 20_000_000;

/// Most bindings grounding visits in all, quantifiers included: counted where the
/// parameter limit alone misses `forall`/`exists` over many variables.
pub const WORK_LIMIT: u64 = 50_000_000;

impl GroundTask {
    /// Grounds `problem` of `domain`.
    pub fn new(
        domain: &Domain,
        problem: &Problem,
        options: &GroundOptions,
    ) -> Result<Self, GroundError> {
        let mutable: HashSet<&str> = options
            .mutable_predicates
            .iter()
            .map(String::as_str)
            .collect();
        let mut g = Grounder::start(domain, problem, &mutable, options.deadline);
        let unit_cost = !(domain.uses_action_costs() && problem.minimize_total_cost);
        let mut raw: Vec<Raw> = Vec::new();
        for action in &domain.actions {
            g.ground_schema(action, unit_cost, &mut raw)?;
        }
        let goal_formula = g.condition(&problem.goal, &mut Vec::new(), true);
        if let Some(e) = g.stopped.take() {
            return Err(e);
        }
        let goal_clauses =
            dnf(&goal_formula).ok_or_else(|| GroundError::DnfTooLarge("the goal".into()))?;
        let mutable_atoms: Vec<bool> = g
            .atoms
            .iter()
            .map(|a| mutable.contains(domain.predicates[a[0] as usize].name.as_str()))
            .collect();
        let init_atoms: Vec<bool> = g.atoms.iter().map(|a| g.init.contains(a)).collect();
        let atoms: Vec<GroundAtom> = g.atoms.iter().map(|a| g.ground_atom(a)).collect();
        Ok(finish(atoms, init_atoms, mutable_atoms, raw, goal_clauses))
    }

    /// Number of fluent facts.
    pub fn num_facts(&self) -> usize {
        self.facts.len()
    }

    /// The literal of a fluent atom, if the atom is in the task.
    pub fn fact(&self, atom: &GroundAtom) -> Option<u32> {
        self.fact_index.get(atom).copied()
    }
}

impl<'a> Grounder<'a> {
    /// A grounder over the domain's constants and the problem's objects, knowing which
    /// predicates are static or never added (`mutable` ones are neither) and the
    /// initial state's atoms.
    fn start(
        domain: &'a Domain,
        problem: &'a Problem,
        mutable: &HashSet<&str>,
        deadline: Option<std::time::Instant>,
    ) -> Self {
        let (mut changing, mut added) = (HashSet::new(), HashSet::new());
        for a in &domain.actions {
            predicates_in_effects(&a.effect, &mut changing, &mut added);
        }
        let object_names: Vec<&str> = domain
            .constants
            .iter()
            .chain(&problem.objects)
            .map(|o| o.name.as_str())
            .collect();
        let object_index: FxHashMap<&str, u32> = object_names
            .iter()
            .enumerate()
            .map(|(i, n)| (*n, i as u32))
            .collect();
        let predicate_index: FxHashMap<&str, u32> = domain
            .predicates
            .iter()
            .enumerate()
            .map(|(i, p)| (p.name.as_str(), i as u32))
            .collect();
        let is_mutable = |p: &Signature| mutable.contains(p.name.as_str());
        let static_pred = domain
            .predicates
            .iter()
            .map(|p| !changing.contains(&p.name) && !is_mutable(p))
            .collect();
        let never_added = domain
            .predicates
            .iter()
            .map(|p| !added.contains(&p.name) && !is_mutable(p))
            .collect();
        let key_of =
            |name: &str, index: &FxHashMap<&str, u32>| index.get(name).copied().unwrap_or(u32::MAX);
        let init_keys = problem
            .init
            .iter()
            .map(|a| {
                std::iter::once(key_of(&a.predicate, &predicate_index))
                    .chain(a.args.iter().map(|o| key_of(o, &object_index)))
                    .collect()
            })
            .collect();
        let init = InitIndex::new(domain, object_names.len(), init_keys);
        Grounder {
            domain,
            problem,
            object_names,
            object_index,
            predicate_index,
            init,
            static_pred,
            never_added,
            atoms: Vec::new(),
            atom_index: FxHashMap::default(),
            objects_by_type: FxHashMap::default(),
            predicate_of_name: FxHashMap::default(),
            key: Vec::new(),
            work: 0,
            deadline,
            stopped: None,
        }
    }

    /// Every ground action of schema `action` whose precondition can hold, one per
    /// disjunct of its precondition's DNF, into `raw`.
    fn ground_schema(
        &mut self,
        action: &'a Action,
        unit_cost: bool,
        raw: &mut Vec<Raw>,
    ) -> Result<(), GroundError> {
        let combinations: u128 = action
            .params
            .iter()
            .map(|p| self.objects(&p.type_name).len() as u128)
            .product();
        if combinations > GROUNDING_LIMIT {
            return Err(GroundError::TooLarge {
                action: action.name.clone(),
                combinations,
                limit: GROUNDING_LIMIT,
            });
        }
        let mut failure = None;
        let mut binding = Vec::new();
        self.for_each_binding(&action.params, 0, &mut binding, &mut |g, b| {
            if failure.is_some() {
                return;
            }
            match g.bound_action(action, b, unit_cost) {
                Ok(actions) => raw.extend(actions),
                Err(e) => failure = Some(e),
            }
        });
        match self.stopped.take().or(failure) {
            Some(e) => Err(e),
            None => Ok(()),
        }
    }

    /// The ground actions of `action` under binding `b`: none when its precondition
    /// cannot hold, else one per disjunct.
    fn bound_action(
        &mut self,
        action: &'a Action,
        b: &mut Binding<'a>,
        unit_cost: bool,
    ) -> Result<Vec<Raw>, GroundError> {
        let pre = self.condition(&action.precondition, b, true);
        let clauses = dnf(&pre).ok_or_else(|| GroundError::DnfTooLarge(action.name.clone()))?;
        if clauses.is_empty() {
            return Ok(Vec::new());
        }
        let cost = if unit_cost {
            1
        } else {
            match self.cost(action, b)? {
                c if c >= 0 => c as u64,
                _ => return Err(GroundError::NegativeCost(action.name.clone())),
            }
        };
        let mut effs = Vec::new();
        self.effect(&action.effect, b, &Gf::True, &mut effs);
        let mut effects = Vec::new();
        for (cond, atom, add) in effs {
            let cs = dnf(&cond).ok_or_else(|| GroundError::DnfTooLarge(action.name.clone()))?;
            effects.extend(cs.into_iter().map(|c| (c, atom, add)));
        }
        let args: Vec<&str> = b
            .iter()
            .take(action.params.len())
            .map(|(_, o)| self.object_names[*o as usize])
            .collect();
        let name = if args.is_empty() {
            format!("({})", action.name)
        } else {
            format!("({} {})", action.name, args.join(" "))
        };
        Ok(clauses
            .into_iter()
            .map(|clause| Raw {
                name: name.clone(),
                pre: clause,
                effects: effects.clone(),
                cost,
                artificial: false,
            })
            .collect())
    }
}
