//! The grounder: bindings of an action's parameters, its conditions and effects, its cost.

use super::*;
use crate::*;
use rustc_hash::FxHashMap;

/// A variable binding: variable name and object id.
pub(super) type Binding<'a> = Vec<(&'a str, u32)>;

/// Grounding works on integer ids: an atom is `[predicate, arg…]`, looked up without
/// allocating, so quantifiers over every object stay cheap.
pub(super) struct Grounder<'a> {
    pub(super) domain: &'a Domain,
    pub(super) problem: &'a Problem,
    pub(super) object_names: Vec<&'a str>,
    pub(super) object_index: FxHashMap<&'a str, u32>,
    pub(super) predicate_index: FxHashMap<&'a str, u32>,
    pub(super) init: InitIndex,
    /// Per predicate id: in no effect (and not mutable).
    pub(super) static_pred: Vec<bool>,
    /// Per predicate id: in no add effect (and not mutable): atoms outside the initial
    /// state are false forever.
    pub(super) never_added: Vec<bool>,
    pub(super) atoms: Vec<Vec<u32>>,
    pub(super) atom_index: FxHashMap<Vec<u32>, u32>,
    pub(super) objects_by_type: FxHashMap<&'a str, std::rc::Rc<[u32]>>,
    /// Predicate id by the address of a predicate name in the (borrowed, immutable)
    /// domain: one integer hash per atom instead of hashing its name.
    pub(super) predicate_of_name: FxHashMap<(usize, usize), u32>,
    pub(super) key: Vec<u32>,
    /// Bindings visited so far (action parameters and quantified variables alike),
    /// against [`WORK_LIMIT`] and the deadline; once either is passed every loop
    /// returns at once and `stopped` says why.
    pub(super) work: u64,
    pub(super) deadline: Option<std::time::Instant>,
    pub(super) stopped: Option<GroundError>,
}

impl<'a> Grounder<'a> {
    pub(super) fn objects(&mut self, t: &'a str) -> std::rc::Rc<[u32]> {
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

    pub(super) fn resolve(&self, term: &Term, binding: &Binding<'_>) -> u32 {
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
    pub(super) fn key_of(&mut self, a: &Atom, binding: &Binding<'_>) {
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

    pub(super) fn atom_id(&mut self) -> u32 {
        if let Some(&i) = self.atom_index.get(self.key.as_slice()) {
            return i;
        }
        let i = self.atoms.len() as u32;
        self.atom_index.insert(self.key.clone(), i);
        self.atoms.push(self.key.clone());
        i
    }

    pub(super) fn ground_atom(&self, key: &[u32]) -> GroundAtom {
        GroundAtom {
            predicate: self.domain.predicates[key[0] as usize].name.clone(),
            args: key[1..]
                .iter()
                .map(|&o| self.object_names[o as usize].to_string())
                .collect(),
        }
    }

    pub(super) fn condition(
        &mut self,
        c: &'a Condition,
        binding: &mut Binding<'a>,
        positive: bool,
    ) -> Gf {
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
    pub(super) fn guard_values(
        &self,
        a: &Atom,
        var: &str,
        binding: &Binding<'_>,
    ) -> Option<Vec<u32>> {
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
    pub(super) fn effect_candidates(
        &self,
        e: &Effect,
        var: &str,
        binding: &Binding<'_>,
    ) -> Option<Vec<u32>> {
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
    pub(super) fn for_each_value(
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

    pub(super) fn for_each_binding(
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
    pub(super) fn effect(
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

    pub(super) fn cost(&self, action: &Action, binding: &Binding<'_>) -> Result<i64, GroundError> {
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
