//! Reachability and simplification to a fixpoint, then the fluent atoms renumbered.

use super::*;
use crate::*;
use std::collections::HashSet;

#[derive(Clone, Copy, PartialEq, Eq)]
pub(super) enum Truth {
    False,
    True,
    Fluent,
}

/// Whether literal `(f, p)` holds under `truth`: known, or `None` for a fluent.
fn holds(truth: &[Truth], (f, p): (u32, bool)) -> Option<bool> {
    match truth[f as usize] {
        Truth::True => Some(p),
        Truth::False => Some(!p),
        Truth::Fluent => None,
    }
}

/// Fixpoint of reachability and simplification, then renumbering of the fluent atoms.
pub(super) fn finish(
    atoms: Vec<GroundAtom>,
    init: Vec<bool>,
    mutable: Vec<bool>,
    raw: Vec<Raw>,
    goal_clauses: Vec<Vec<(u32, bool)>>,
) -> GroundTask {
    let (truth, raw) = fixpoint(&init, &mutable, raw);
    let n = atoms.len();
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
    let mut actions: Vec<GroundAction> = raw.into_iter().map(|a| ground_action(a, &id)).collect();
    let lit = |(f, p): (u32, bool)| Lit {
        fact: id[f as usize],
        positive: p,
    };
    let clauses: Vec<Vec<Lit>> = goal_clauses
        .into_iter()
        .filter(|c| c.iter().all(|&l| holds(&truth, l) != Some(false)))
        .map(|c| {
            c.into_iter()
                .filter(|&l| holds(&truth, l).is_none())
                .map(lit)
                .collect()
        })
        .collect();
    let mut init_bits: Vec<bool> = (0..n)
        .filter(|&f| truth[f] == Truth::Fluent)
        .map(|f| init[f])
        .collect();
    let (goal, goal_unreachable) = goal_of(clauses, (&mut facts, &mut init_bits), &mut actions);
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

/// Relaxed reachability and simplification until neither changes: each atom's truth
/// and the actions that remain, their known conditions and effects removed.
fn fixpoint(init: &[bool], mutable: &[bool], mut raw: Vec<Raw>) -> (Vec<Truth>, Vec<Raw>) {
    let n = init.len();
    let mut truth = vec![Truth::Fluent; n];
    loop {
        let (reached, usable) = reachable(init, mutable, &raw);
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
        raw = simplify(raw, &usable, &new_truth);
        let stable = new_truth == truth && raw.len() == before;
        truth = new_truth;
        if stable {
            return (truth, raw);
        }
    }
}

/// Relaxed reachability over positive conditions: the atoms reached and the actions
/// usable. Mutable atoms may be switched on by the caller: reachable by assumption.
fn reachable(init: &[bool], mutable: &[bool], raw: &[Raw]) -> (Vec<bool>, Vec<bool>) {
    let mut reached: Vec<bool> = init.iter().zip(mutable).map(|(i, m)| *i || *m).collect();
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
    (reached, usable)
}

/// The usable actions whose preconditions may hold, with the known literals and the
/// effects on non-fluent atoms removed.
fn simplify(raw: Vec<Raw>, usable: &[bool], truth: &[Truth]) -> Vec<Raw> {
    let mut next = Vec::with_capacity(raw.len());
    for (i, mut a) in raw.into_iter().enumerate() {
        if !usable[i] || a.pre.iter().any(|&l| holds(truth, l) == Some(false)) {
            continue;
        }
        a.pre.retain(|&l| holds(truth, l).is_none());
        a.effects.retain_mut(|(c, f, _)| {
            if c.iter().any(|&l| holds(truth, l) == Some(false)) {
                return false;
            }
            c.retain(|&l| holds(truth, l).is_none());
            truth[*f as usize] == Truth::Fluent
        });
        next.push(a);
    }
    next
}

/// An action over the renumbered facts (`id`), its effects sorted and deduplicated.
fn ground_action(a: Raw, id: &[u32]) -> GroundAction {
    let lit = |(f, p): (u32, bool)| Lit {
        fact: id[f as usize],
        positive: p,
    };
    let mut effects: Vec<CondEffect> = a
        .effects
        .into_iter()
        .map(|(c, f, add)| {
            let mut cond: Vec<Lit> = c.into_iter().map(lit).collect();
            // `(when f (not f))` is the plain `(not f)`.
            let itself = Lit {
                fact: id[f as usize],
                positive: true,
            };
            if !add && cond.len() == 1 && cond[0] == itself {
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
}

/// The goal: one clause is a conjunction; several get an artificial goal fact reached
/// by one zero-cost action per clause. Also whether no clause can hold.
fn goal_of(
    clauses: Vec<Vec<Lit>>,
    (facts, init_bits): (&mut Vec<GroundAtom>, &mut Vec<bool>),
    actions: &mut Vec<GroundAction>,
) -> (Vec<Lit>, bool) {
    match clauses.len() {
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
            let reached = Lit {
                fact: goal_fact,
                positive: true,
            };
            (vec![reached], false)
        }
    }
}
