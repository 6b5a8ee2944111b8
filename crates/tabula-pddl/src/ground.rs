//! Grounding: the lifted domain and problem become a propositional task.
//!
//! Conditions are grounded into negation normal form with quantifiers expanded over
//! the typed objects, static predicates (in no effect) and equality evaluated on the
//! spot, and then put in DNF (one ground action per disjunct). A fixpoint of relaxed
//! reachability (positive conditions only) then finds which atoms can ever change;
//! every other atom is a constant and disappears from the task. Only the remaining
//! *fluent* atoms get ids; states are bit sets over them.

use crate::*;
use rustc_hash::{FxHashMap, FxHashSet};
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

/// A grounded formula in negation normal form.
#[derive(Debug, Clone)]
enum Gf {
    True,
    False,
    Lit(u32, bool),
    And(Vec<Gf>),
    Or(Vec<Gf>),
}

fn and(items: Vec<Gf>) -> Gf {
    let mut out = Vec::with_capacity(items.len());
    for g in items {
        match g {
            Gf::True => {}
            Gf::False => return Gf::False,
            Gf::And(inner) => out.extend(inner),
            other => out.push(other),
        }
    }
    match out.len() {
        0 => Gf::True,
        1 => out.pop().unwrap_or(Gf::True),
        _ => Gf::And(out),
    }
}

fn or(items: Vec<Gf>) -> Gf {
    let mut out = Vec::with_capacity(items.len());
    for g in items {
        match g {
            Gf::False => {}
            Gf::True => return Gf::True,
            Gf::Or(inner) => out.extend(inner),
            other => out.push(other),
        }
    }
    match out.len() {
        0 => Gf::False,
        1 => out.pop().unwrap_or(Gf::False),
        _ => Gf::Or(out),
    }
}

const DNF_LIMIT: usize = 100_000;

/// Clauses of a DNF as sorted literal lists; contradictory clauses are dropped.
fn dnf(g: &Gf) -> Option<Vec<Vec<(u32, bool)>>> {
    Some(match g {
        Gf::True => vec![Vec::new()],
        Gf::False => Vec::new(),
        Gf::Lit(a, p) => vec![vec![(*a, *p)]],
        Gf::Or(items) => {
            let mut out = Vec::new();
            for i in items {
                out.extend(dnf(i)?);
                if out.len() > DNF_LIMIT {
                    return None;
                }
            }
            out
        }
        Gf::And(items) => {
            let mut acc: Vec<Vec<(u32, bool)>> = vec![Vec::new()];
            for i in items {
                let part = dnf(i)?;
                let mut next = Vec::with_capacity(acc.len() * part.len());
                for a in &acc {
                    for p in &part {
                        let mut c = a.clone();
                        c.extend_from_slice(p);
                        c.sort_unstable();
                        c.dedup();
                        if c.windows(2).all(|w| w[0].0 != w[1].0) {
                            next.push(c);
                        }
                    }
                }
                if next.len() > DNF_LIMIT {
                    return None;
                }
                acc = next;
            }
            acc
        }
    })
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

/// Membership in the initial state. Quantified effects ask it for every object
/// (`forall ?x (when (block_dir1 ?o ?x) …)`), so predicates of small arity get a dense
/// bit table indexed by object ids instead of a hash lookup.
struct InitIndex {
    objects: usize,
    dense: Vec<Option<Vec<u64>>>,
    sparse: FxHashSet<Vec<u32>>,
    /// Every initial atom, and for (predicate, argument position, object) the atoms
    /// that have that object there; position `u32::MAX` lists a predicate's atoms.
    keys: Vec<Vec<u32>>,
    by_arg: FxHashMap<(u32, u32, u32), Vec<u32>>,
}

impl InitIndex {
    const DENSE_LIMIT: usize = 1 << 22;

    fn new(domain: &Domain, objects: usize, keys: Vec<Vec<u32>>) -> Self {
        let mut dense: Vec<Option<Vec<u64>>> = domain
            .predicates
            .iter()
            .map(|p| {
                let cells = objects
                    .checked_pow(p.params.len() as u32)
                    .filter(|&c| c <= Self::DENSE_LIMIT)?;
                Some(vec![0u64; cells.div_ceil(64).max(1)])
            })
            .collect();
        let mut sparse = FxHashSet::default();
        let mut by_arg: FxHashMap<(u32, u32, u32), Vec<u32>> = FxHashMap::default();
        for (i, k) in keys.iter().enumerate() {
            by_arg
                .entry((k[0], u32::MAX, 0))
                .or_default()
                .push(i as u32);
            for (pos, &o) in k[1..].iter().enumerate() {
                by_arg
                    .entry((k[0], pos as u32, o))
                    .or_default()
                    .push(i as u32);
            }
        }
        let mut me = Self {
            objects,
            dense: Vec::new(),
            sparse: FxHashSet::default(),
            keys: Vec::new(),
            by_arg,
        };
        for k in keys.iter().cloned() {
            match me
                .cell(&k)
                .and_then(|c| dense.get_mut(k[0] as usize)?.as_mut().map(|bits| (c, bits)))
            {
                Some((c, bits)) => bits[c / 64] |= 1 << (c % 64),
                None => {
                    sparse.insert(k);
                }
            }
        }
        me.dense = dense;
        me.sparse = sparse;
        me.keys = keys;
        me
    }

    /// Position of an atom in its predicate's dense table.
    fn cell(&self, key: &[u32]) -> Option<usize> {
        let mut c = 0usize;
        for &o in &key[1..] {
            if o as usize >= self.objects {
                return None;
            }
            c = c * self.objects + o as usize;
        }
        Some(c)
    }

    fn contains(&self, key: &[u32]) -> bool {
        if let Some(Some(bits)) = self.dense.get(key[0] as usize)
            && let Some(c) = self.cell(key)
            && c / 64 < bits.len()
        {
            return (bits[c / 64] >> (c % 64)) & 1 == 1;
        }
        self.sparse.contains(key)
    }
}

/// A variable binding: variable name and object id.
type Binding<'a> = Vec<(&'a str, u32)>;

/// Grounding works on integer ids: an atom is `[predicate, arg…]`, looked up without
/// allocating, so quantifiers over every object stay cheap.
struct Grounder<'a> {
    domain: &'a Domain,
    problem: &'a Problem,
    object_names: Vec<&'a str>,
    object_index: FxHashMap<&'a str, u32>,
    predicate_index: FxHashMap<&'a str, u32>,
    init: InitIndex,
    /// Per predicate id: in no effect (and not mutable).
    static_pred: Vec<bool>,
    /// Per predicate id: in no add effect (and not mutable): atoms outside the initial
    /// state are false forever.
    never_added: Vec<bool>,
    atoms: Vec<Vec<u32>>,
    atom_index: FxHashMap<Vec<u32>, u32>,
    objects_by_type: FxHashMap<&'a str, std::rc::Rc<[u32]>>,
    /// Predicate id by the address of a predicate name in the (borrowed, immutable)
    /// domain: one integer hash per atom instead of hashing its name.
    predicate_of_name: FxHashMap<(usize, usize), u32>,
    key: Vec<u32>,
    /// Bindings visited so far (action parameters and quantified variables alike),
    /// against [`WORK_LIMIT`] and the deadline; once either is passed every loop
    /// returns at once and `stopped` says why.
    work: u64,
    deadline: Option<std::time::Instant>,
    stopped: Option<GroundError>,
}

impl<'a> Grounder<'a> {
    fn objects(&mut self, t: &'a str) -> std::rc::Rc<[u32]> {
        if let Some(v) = self.objects_by_type.get(t) {
            return v.clone();
        }
        let v: std::rc::Rc<[u32]> = self
            .domain
            .constants
            .iter()
            .chain(&self.problem.objects)
            .filter(|o| self.domain.is_subtype(&o.type_name, t))
            .map(|o| self.object_index[o.name.as_str()])
            .collect();
        self.objects_by_type.insert(t, v.clone());
        v
    }

    fn resolve(&self, term: &Term, binding: &Binding<'_>) -> u32 {
        match term {
            Term::Const(c) => self
                .object_index
                .get(c.as_str())
                .copied()
                .unwrap_or(u32::MAX),
            Term::Var(v) => binding
                .iter()
                .rev()
                .find(|(n, _)| n == v)
                .map_or(u32::MAX, |(_, o)| *o),
        }
    }

    /// Fills `self.key` with the atom's ids.
    fn key_of(&mut self, a: &Atom, binding: &Binding<'_>) {
        let mut key = std::mem::take(&mut self.key);
        key.clear();
        let addr = (a.predicate.as_ptr() as usize, a.predicate.len());
        let pid = match self.predicate_of_name.get(&addr) {
            Some(&p) => p,
            None => {
                let p = self
                    .predicate_index
                    .get(a.predicate.as_str())
                    .copied()
                    .unwrap_or(u32::MAX);
                self.predicate_of_name.insert(addr, p);
                p
            }
        };
        key.push(pid);
        key.extend(a.args.iter().map(|t| self.resolve(t, binding)));
        self.key = key;
    }

    fn atom_id(&mut self) -> u32 {
        if let Some(&i) = self.atom_index.get(self.key.as_slice()) {
            return i;
        }
        let i = self.atoms.len() as u32;
        self.atom_index.insert(self.key.clone(), i);
        self.atoms.push(self.key.clone());
        i
    }

    fn ground_atom(&self, key: &[u32]) -> GroundAtom {
        GroundAtom {
            predicate: self.domain.predicates[key[0] as usize].name.clone(),
            args: key[1..]
                .iter()
                .map(|&o| self.object_names[o as usize].to_string())
                .collect(),
        }
    }

    fn condition(&mut self, c: &'a Condition, binding: &mut Binding<'a>, positive: bool) -> Gf {
        match c {
            Condition::True => {
                if positive {
                    Gf::True
                } else {
                    Gf::False
                }
            }
            Condition::Atom(a) => {
                self.key_of(a, binding);
                let pred = self.key[0] as usize;
                let in_init = self.init.contains(self.key.as_slice());
                if self.static_pred[pred] || (self.never_added[pred] && !in_init) {
                    if in_init == positive {
                        Gf::True
                    } else {
                        Gf::False
                    }
                } else {
                    Gf::Lit(self.atom_id(), positive)
                }
            }
            Condition::Equal(x, y) => {
                if (self.resolve(x, binding) == self.resolve(y, binding)) == positive {
                    Gf::True
                } else {
                    Gf::False
                }
            }
            Condition::Not(inner) => self.condition(inner, binding, !positive),
            Condition::And(items) | Condition::Or(items) => {
                let parts = items
                    .iter()
                    .map(|i| self.condition(i, binding, positive))
                    .collect();
                if matches!(c, Condition::And(_)) == positive {
                    and(parts)
                } else {
                    or(parts)
                }
            }
            Condition::Imply(a, b) => {
                // a → b  ≡  ¬a ∨ b
                let parts = vec![
                    self.condition(a, binding, !positive),
                    self.condition(b, binding, positive),
                ];
                if positive { or(parts) } else { and(parts) }
            }
            Condition::Exists(vars, body) | Condition::Forall(vars, body) => {
                // A conjunction (forall, or negated exists) or a disjunction over the
                // objects; neutral parts are dropped as they come and an absorbing one
                // ends the expansion, so "nothing is on it" over 100 objects stays small.
                let conjunction = matches!(c, Condition::Forall(..)) == positive;
                let mut parts = Vec::new();
                let mut absorbed = false;
                let mut visit = |g: &mut Self, b: &mut Binding<'a>| {
                    if absorbed {
                        return;
                    }
                    match (g.condition(body, b, positive), conjunction) {
                        (Gf::True, true) | (Gf::False, false) => {}
                        (Gf::False, true) | (Gf::True, false) => absorbed = true,
                        (part, _) => parts.push(part),
                    }
                };
                // One variable over a literal of an atom no action adds: every object
                // outside the matching initial atoms gives the same value, so only the
                // matching ones are visited (and the rest decided at once).
                let mut negations = 0;
                let mut literal = body.as_ref();
                while let Condition::Not(inner) = literal {
                    negations += 1;
                    literal = inner;
                }
                let guarded = match (vars.as_slice(), literal) {
                    ([v], Condition::Atom(a)) => {
                        self.guard_values(a, &v.name, binding).map(|vals| (v, vals))
                    }
                    _ => None,
                };
                match guarded {
                    Some((v, values)) => {
                        // An atom outside the initial state is false; through the
                        // negations and the polarity that is the others' common value.
                        let others = (negations % 2 == 1) == positive;
                        let neutral = others == conjunction;
                        let typed = self.objects(&v.type_name);
                        if !neutral && typed.iter().any(|o| values.binary_search(o).is_err()) {
                            absorbed = true;
                        } else {
                            self.for_each_value(v, &values, binding, &mut visit);
                        }
                    }
                    None => self.for_each_binding(vars, 0, binding, &mut visit),
                }
                match (absorbed, conjunction) {
                    (true, true) => Gf::False,
                    (true, false) => Gf::True,
                    (false, true) => and(parts),
                    (false, false) => or(parts),
                }
            }
        }
    }

    /// Objects `var` can take for atom `a` (of a predicate no action adds) to be true:
    /// those of the matching initial atoms. `None` when `a` is not such an atom or does
    /// not mention `var`.
    fn guard_values(&self, a: &Atom, var: &str, binding: &Binding<'_>) -> Option<Vec<u32>> {
        let pid = *self.predicate_index.get(a.predicate.as_str())?;
        if !self.never_added[pid as usize] {
            return None;
        }
        let var_pos: Vec<usize> = (0..a.args.len())
            .filter(|&i| a.args[i] == Term::Var(var.to_string()))
            .collect();
        if var_pos.is_empty() {
            return None;
        }
        let bound: Vec<(usize, u32)> = (0..a.args.len())
            .filter(|i| !var_pos.contains(i))
            .map(|i| (i, self.resolve(&a.args[i], binding)))
            .collect();
        let list_key = bound
            .first()
            .map_or((pid, u32::MAX, 0), |&(i, o)| (pid, i as u32, o));
        let mut out = Vec::new();
        for &k in self
            .init
            .by_arg
            .get(&list_key)
            .map(Vec::as_slice)
            .unwrap_or(&[])
        {
            let key = &self.init.keys[k as usize];
            let value = key[var_pos[0] + 1];
            if bound.iter().all(|&(i, o)| key[i + 1] == o)
                && var_pos.iter().all(|&i| key[i + 1] == value)
            {
                out.push(value);
            }
        }
        out.sort_unstable();
        out.dedup();
        Some(out)
    }

    /// For a one-variable `forall` effect whose every leaf is a delete of, or guarded by,
    /// an atom no action adds: the only values of the variable that can do anything.
    fn effect_candidates(&self, e: &Effect, var: &str, binding: &Binding<'_>) -> Option<Vec<u32>> {
        match e {
            Effect::And(items) => {
                let mut all = Vec::new();
                for i in items {
                    all.extend(self.effect_candidates(i, var, binding)?);
                }
                all.sort_unstable();
                all.dedup();
                Some(all)
            }
            Effect::Delete(a) => self.guard_values(a, var, binding),
            Effect::When(c, _) => match c {
                Condition::Atom(a) => self.guard_values(a, var, binding),
                Condition::And(items) => items.iter().find_map(|i| match i {
                    Condition::Atom(a) => self.guard_values(a, var, binding),
                    _ => None,
                }),
                _ => None,
            },
            _ => None,
        }
    }

    /// Binds one variable to each of `values` that has its type.
    fn for_each_value(
        &mut self,
        var: &'a TypedName,
        values: &[u32],
        binding: &mut Binding<'a>,
        f: &mut dyn FnMut(&mut Self, &mut Binding<'a>),
    ) {
        let typed = self.objects(&var.type_name);
        for &o in values {
            if typed.binary_search(&o).is_ok() {
                binding.push((var.name.as_str(), o));
                f(self, binding);
                binding.pop();
            }
        }
    }

    fn for_each_binding(
        &mut self,
        vars: &'a [TypedName],
        i: usize,
        binding: &mut Binding<'a>,
        f: &mut dyn FnMut(&mut Self, &mut Binding<'a>),
    ) {
        if self.stopped.is_some() {
            return;
        }
        if i == vars.len() {
            self.work += 1;
            if self.work > WORK_LIMIT {
                self.stopped = Some(GroundError::TooMuchWork(WORK_LIMIT));
                return;
            }
            if self.work.is_multiple_of(4096)
                && self.deadline.is_some_and(|d| std::time::Instant::now() > d)
            {
                self.stopped = Some(GroundError::Timeout);
                return;
            }
            f(self, binding);
            return;
        }
        let objects = self.objects(&vars[i].type_name);
        for &o in objects.iter() {
            if self.stopped.is_some() {
                return;
            }
            binding.push((vars[i].name.as_str(), o));
            self.for_each_binding(vars, i + 1, binding, f);
            binding.pop();
        }
    }

    /// (condition, atom, add) triples, condition still a formula.
    fn effect(
        &mut self,
        e: &'a Effect,
        binding: &mut Binding<'a>,
        cond: &Gf,
        out: &mut Vec<(Gf, u32, bool)>,
    ) {
        match e {
            Effect::And(items) => {
                for i in items {
                    self.effect(i, binding, cond, out);
                }
            }
            Effect::Add(a) | Effect::Delete(a) => {
                self.key_of(a, binding);
                let add = matches!(e, Effect::Add(_));
                // Deleting an atom that can never be true does nothing.
                if !add
                    && self.never_added[self.key[0] as usize]
                    && !self.init.contains(self.key.as_slice())
                {
                    return;
                }
                let id = self.atom_id();
                out.push((cond.clone(), id, add));
            }
            Effect::Forall(vars, body) => {
                let candidates = match vars.as_slice() {
                    [v] => self.effect_candidates(body, &v.name, binding),
                    _ => None,
                };
                match candidates {
                    Some(values) => self.for_each_value(&vars[0], &values, binding, &mut |g, b| {
                        g.effect(body, b, cond, out)
                    }),
                    None => self.for_each_binding(vars, 0, binding, &mut |g, b| {
                        g.effect(body, b, cond, out)
                    }),
                }
            }
            Effect::When(c, body) => {
                // Most conditions are false (an atom outside the initial state that no
                // action adds): decide that before building anything.
                let c = match (cond, self.condition(c, binding, true)) {
                    (_, Gf::False) => return,
                    (Gf::True, c) => c,
                    (outer, Gf::True) => outer.clone(),
                    (outer, c) => and(vec![outer.clone(), c]),
                };
                self.effect(body, binding, &c, out);
            }
            Effect::IncreaseCost(_) => {}
        }
    }

    fn cost(&self, action: &Action, binding: &Binding<'_>) -> Result<i64, GroundError> {
        fn collect<'e>(e: &'e Effect, out: &mut Vec<&'e CostExpr>) {
            match e {
                Effect::And(items) => items.iter().for_each(|i| collect(i, out)),
                Effect::IncreaseCost(c) => out.push(c),
                _ => {}
            }
        }
        let mut exprs = Vec::new();
        collect(&action.effect, &mut exprs);
        let mut total = 0i64;
        for e in exprs {
            total += match e {
                CostExpr::Constant(v) => *v,
                CostExpr::Function(f, args) => {
                    let g = GroundAtom {
                        predicate: f.clone(),
                        args: args
                            .iter()
                            .map(|t| {
                                self.object_names
                                    .get(self.resolve(t, binding) as usize)
                                    .copied()
                                    .unwrap_or("")
                                    .to_string()
                            })
                            .collect(),
                    };
                    self.problem
                        .init_numeric
                        .iter()
                        .find(|(a, _)| *a == g)
                        .map(|(_, v)| *v)
                        .ok_or_else(|| GroundError::MissingCost {
                            action: action.name.clone(),
                            function: std::iter::once(f.clone())
                                .chain(g.args.clone())
                                .collect::<Vec<_>>()
                                .join(" "),
                        })?
                }
            };
        }
        Ok(total)
    }
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
        let (mut changing, mut added) = (HashSet::new(), HashSet::new());
        for a in &domain.actions {
            predicates_in_effects(&a.effect, &mut changing, &mut added);
        }
        let mutable: HashSet<&str> = options
            .mutable_predicates
            .iter()
            .map(String::as_str)
            .collect();
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
        let init_keys = problem
            .init
            .iter()
            .map(|a| {
                std::iter::once(
                    predicate_index
                        .get(a.predicate.as_str())
                        .copied()
                        .unwrap_or(u32::MAX),
                )
                .chain(
                    a.args
                        .iter()
                        .map(|o| object_index.get(o.as_str()).copied().unwrap_or(u32::MAX)),
                )
                .collect()
            })
            .collect();
        let init = InitIndex::new(domain, object_names.len(), init_keys);
        let mut g = Grounder {
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
            deadline: options.deadline,
            stopped: None,
        };
        let unit_cost = !(domain.uses_action_costs() && problem.minimize_total_cost);
        let mut raw: Vec<Raw> = Vec::new();
        for action in &domain.actions {
            let combinations: u128 = action
                .params
                .iter()
                .map(|p| g.objects(&p.type_name).len() as u128)
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
            g.for_each_binding(&action.params, 0, &mut binding, &mut |g, b| {
                if failure.is_some() {
                    return;
                }
                let pre = g.condition(&action.precondition, b, true);
                let Some(clauses) = dnf(&pre) else {
                    failure = Some(GroundError::DnfTooLarge(action.name.clone()));
                    return;
                };
                if clauses.is_empty() {
                    return;
                }
                let cost = if unit_cost {
                    1
                } else {
                    match g.cost(action, b) {
                        Ok(c) if c >= 0 => c as u64,
                        Ok(_) => {
                            failure = Some(GroundError::NegativeCost(action.name.clone()));
                            return;
                        }
                        Err(e) => {
                            failure = Some(e);
                            return;
                        }
                    }
                };
                let mut effs = Vec::new();
                g.effect(&action.effect, b, &Gf::True, &mut effs);
                let mut effects = Vec::new();
                for (cond, atom, add) in effs {
                    let Some(cs) = dnf(&cond) else {
                        failure = Some(GroundError::DnfTooLarge(action.name.clone()));
                        return;
                    };
                    for c in cs {
                        effects.push((c, atom, add));
                    }
                }
                let args: Vec<&str> = b
                    .iter()
                    .take(action.params.len())
                    .map(|(_, o)| g.object_names[*o as usize])
                    .collect();
                let name = if args.is_empty() {
                    format!("({})", action.name)
                } else {
                    format!("({} {})", action.name, args.join(" "))
                };
                for clause in clauses {
                    raw.push(Raw {
                        name: name.clone(),
                        pre: clause,
                        effects: effects.clone(),
                        cost,
                        artificial: false,
                    });
                }
            });
            if let Some(e) = g.stopped.take().or(failure) {
                return Err(e);
            }
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
            .map(|a| is_mutable(&domain.predicates[a[0] as usize]))
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

#[derive(Clone, Copy, PartialEq, Eq)]
enum Truth {
    False,
    True,
    Fluent,
}

/// Fixpoint of reachability and simplification, then renumbering of the fluent atoms.
fn finish(
    atoms: Vec<GroundAtom>,
    init: Vec<bool>,
    mutable: Vec<bool>,
    mut raw: Vec<Raw>,
    goal_clauses: Vec<Vec<(u32, bool)>>,
) -> GroundTask {
    let n = atoms.len();
    let mut truth = vec![Truth::Fluent; n];
    loop {
        // Relaxed reachability over positive conditions.
        // Mutable atoms may be switched on by the caller: reachable by assumption.
        let mut reached: Vec<bool> = init.iter().zip(&mutable).map(|(i, m)| *i || *m).collect();
        let mut usable = vec![false; raw.len()];
        let mut changed = true;
        while changed {
            changed = false;
            for (i, a) in raw.iter().enumerate() {
                if !usable[i] && a.pre.iter().all(|&(f, p)| !p || reached[f as usize]) {
                    usable[i] = true;
                    changed = true;
                }
                if usable[i] {
                    for (c, f, add) in &a.effects {
                        if *add
                            && !reached[*f as usize]
                            && c.iter().all(|&(f, p)| !p || reached[f as usize])
                        {
                            reached[*f as usize] = true;
                            changed = true;
                        }
                    }
                }
            }
        }
        let mut deleted = vec![false; n];
        for (i, a) in raw.iter().enumerate() {
            if usable[i] {
                for (c, f, add) in &a.effects {
                    if !*add && c.iter().all(|&(f, p)| !p || reached[f as usize]) {
                        deleted[*f as usize] = true;
                    }
                }
            }
        }
        let new_truth: Vec<Truth> = (0..n)
            .map(|f| {
                if mutable[f] {
                    Truth::Fluent
                } else if !reached[f] {
                    Truth::False
                } else if init[f] && !deleted[f] {
                    Truth::True
                } else {
                    Truth::Fluent
                }
            })
            .collect();
        let before = raw.len();
        let holds = |t: &[Truth], (f, p): (u32, bool)| match t[f as usize] {
            Truth::True => Some(p),
            Truth::False => Some(!p),
            Truth::Fluent => None,
        };
        let mut next = Vec::with_capacity(raw.len());
        for (i, mut a) in raw.into_iter().enumerate() {
            if !usable[i] || a.pre.iter().any(|&l| holds(&new_truth, l) == Some(false)) {
                continue;
            }
            a.pre.retain(|&l| holds(&new_truth, l).is_none());
            a.effects.retain_mut(|(c, f, _)| {
                if c.iter().any(|&l| holds(&new_truth, l) == Some(false)) {
                    return false;
                }
                c.retain(|&l| holds(&new_truth, l).is_none());
                new_truth[*f as usize] == Truth::Fluent
            });
            next.push(a);
        }
        raw = next;
        let stable = new_truth == truth && raw.len() == before;
        truth = new_truth;
        if stable {
            break;
        }
    }
    // Renumber fluent atoms.
    let mut id = vec![u32::MAX; n];
    let mut facts = Vec::new();
    let mut constant_true = HashSet::new();
    for f in 0..n {
        match truth[f] {
            Truth::Fluent => {
                id[f] = facts.len() as u32;
                facts.push(atoms[f].clone());
            }
            Truth::True => {
                constant_true.insert(atoms[f].clone());
            }
            Truth::False => {}
        }
    }
    let lit = |(f, p): (u32, bool)| Lit {
        fact: id[f as usize],
        positive: p,
    };
    let mut actions: Vec<GroundAction> = raw
        .into_iter()
        .map(|a| {
            let mut effects: Vec<CondEffect> = a
                .effects
                .into_iter()
                .map(|(c, f, add)| {
                    let mut cond: Vec<Lit> = c.into_iter().map(lit).collect();
                    // `(when f (not f))` is the plain `(not f)`.
                    if !add
                        && cond.len() == 1
                        && cond[0]
                            == (Lit {
                                fact: id[f as usize],
                                positive: true,
                            })
                    {
                        cond.clear();
                    }
                    CondEffect {
                        cond,
                        fact: id[f as usize],
                        add,
                    }
                })
                .collect();
            effects.sort_by_key(|e| (e.cond.is_empty(), e.fact, e.add));
            effects.dedup();
            GroundAction {
                name: a.name,
                pre: a.pre.into_iter().map(lit).collect(),
                effects,
                cost: a.cost,
                artificial: a.artificial,
            }
        })
        .collect();
    // Goal: one clause is a conjunction; several get an artificial goal fact.
    let holds = |(f, p): (u32, bool)| match truth[f as usize] {
        Truth::True => Some(p),
        Truth::False => Some(!p),
        Truth::Fluent => None,
    };
    let clauses: Vec<Vec<Lit>> = goal_clauses
        .into_iter()
        .filter(|c| c.iter().all(|&l| holds(l) != Some(false)))
        .map(|c| {
            c.into_iter()
                .filter(|&l| holds(l).is_none())
                .map(lit)
                .collect()
        })
        .collect();
    let mut init_bits: Vec<bool> = (0..n)
        .filter(|&f| truth[f] == Truth::Fluent)
        .map(|f| init[f])
        .collect();
    let (goal, goal_unreachable) = match clauses.len() {
        0 => (Vec::new(), true),
        1 => (clauses.into_iter().next().unwrap_or_default(), false),
        _ if clauses.iter().any(Vec::is_empty) => (Vec::new(), false),
        _ => {
            let goal_fact = facts.len() as u32;
            facts.push(GroundAtom {
                predicate: "__goal-reached".into(),
                args: Vec::new(),
            });
            init_bits.push(false);
            for (i, c) in clauses.into_iter().enumerate() {
                actions.push(GroundAction {
                    name: format!("(__reach-goal-{i})"),
                    pre: c,
                    effects: vec![CondEffect {
                        cond: Vec::new(),
                        fact: goal_fact,
                        add: true,
                    }],
                    cost: 0,
                    artificial: true,
                });
            }
            (
                vec![Lit {
                    fact: goal_fact,
                    positive: true,
                }],
                false,
            )
        }
    };
    let fact_index = facts
        .iter()
        .enumerate()
        .map(|(i, a)| (a.clone(), i as u32))
        .collect();
    GroundTask {
        facts,
        fact_index,
        init: init_bits,
        goal,
        goal_unreachable,
        actions,
        constant_true,
    }
}
