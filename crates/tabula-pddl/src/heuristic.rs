//! Delete-relaxation heuristics: LM-cut (admissible, for A*) and h^FF with preferred
//! operators (for greedy search).
//!
//! Negative conditions are compiled into positive facts ¬f (true in a state where f is
//! false, added by whatever deletes f) instead of being dropped, so "nothing is on it"
//! and "not IK-infeasible" still need achievers in the relaxation. This is what Fast
//! Downward cannot do when it turns negated existentials into axioms. Effect conditions
//! are ignored (every conditional effect fires): a relaxation of the relaxation, so
//! LM-cut stays admissible.

use crate::ground::{GroundTask, Lit};
use std::cmp::Reverse;
use std::collections::BinaryHeap;

const INF: u64 = u64::MAX / 4;

/// The relaxed task over facts `f` (0..n), `¬f` (n..2n), an always-true start fact and
/// the goal fact.
#[derive(Debug, Clone)]
pub struct Relaxed {
    n: usize,
    start_fact: u32,
    goal_fact: u32,
    pre: Vec<Vec<u32>>,
    add: Vec<Vec<u32>>,
    cost: Vec<u64>,
    /// Actions with each fact as precondition.
    pre_of: Vec<Vec<u32>>,
    /// Actions adding each fact.
    adders: Vec<Vec<u32>>,
    /// Index of the artificial goal action (pre = goal, add = goal fact, cost 0).
    goal_action: usize,
    /// Per fact f: whether f (bit 0) and ¬f (bit 1) are needed by some precondition.
    needed: Vec<u8>,
}

fn relaxed_id(n: usize, l: Lit) -> u32 {
    if l.positive {
        l.fact
    } else {
        l.fact + n as u32
    }
}

impl Relaxed {
    pub fn new(task: &GroundTask) -> Self {
        let n = task.facts.len();
        let start_fact = 2 * n as u32;
        let goal_fact = start_fact + 1;
        let facts = 2 * n + 2;
        let mut pre = Vec::with_capacity(task.actions.len() + 1);
        let mut add = Vec::with_capacity(task.actions.len() + 1);
        let mut cost = Vec::with_capacity(task.actions.len() + 1);
        for a in &task.actions {
            let mut p: Vec<u32> = a.pre.iter().map(|&l| relaxed_id(n, l)).collect();
            p.sort_unstable();
            p.dedup();
            if p.is_empty() {
                p.push(start_fact);
            }
            let mut e: Vec<u32> = a
                .effects
                .iter()
                .map(|e| {
                    relaxed_id(
                        n,
                        Lit {
                            fact: e.fact,
                            positive: e.add,
                        },
                    )
                })
                .collect();
            e.sort_unstable();
            e.dedup();
            pre.push(p);
            add.push(e);
            cost.push(a.cost);
        }
        let mut g: Vec<u32> = task.goal.iter().map(|&l| relaxed_id(n, l)).collect();
        g.sort_unstable();
        g.dedup();
        if g.is_empty() {
            g.push(start_fact);
        }
        let goal_action = pre.len();
        pre.push(g);
        add.push(vec![goal_fact]);
        cost.push(0);
        // Only facts some precondition (or the goal) needs matter to any of these
        // heuristics: "block" facts themselves never are, only their negations.
        let mut needed = vec![false; facts];
        for p in &pre {
            for &f in p {
                needed[f as usize] = true;
            }
        }
        needed[goal_fact as usize] = true;
        for e in &mut add {
            e.retain(|&f| needed[f as usize]);
        }
        let mut pre_of = vec![Vec::new(); facts];
        let mut adders = vec![Vec::new(); facts];
        for (a, p) in pre.iter().enumerate() {
            for &f in p {
                pre_of[f as usize].push(a as u32);
            }
        }
        for (a, e) in add.iter().enumerate() {
            for &f in e {
                adders[f as usize].push(a as u32);
            }
        }
        let needed = (0..n)
            .map(|f| u8::from(needed[f]) | (u8::from(needed[f + n]) << 1))
            .collect();
        Self {
            n,
            start_fact,
            goal_fact,
            pre,
            add,
            cost,
            pre_of,
            adders,
            goal_action,
            needed,
        }
    }

    fn num_facts(&self) -> usize {
        2 * self.n + 2
    }

    /// Facts true in the relaxed initial state of `state`.
    fn start_facts(&self, state: &[u64], out: &mut Vec<u32>) {
        out.clear();
        for f in 0..self.n {
            let on = (state[f / 64] >> (f % 64)) & 1 == 1;
            let (id, bit) = if on { (f, 1) } else { (f + self.n, 2) };
            if self.needed[f] & bit != 0 {
                out.push(id as u32);
            }
        }
        out.push(self.start_fact);
    }
}

/// A priority queue for Dijkstra-like propagation where popped values never decrease:
/// small values (the usual unit and small action costs) live in buckets, O(1) a push
/// and pop; larger ones in a binary heap.
#[derive(Default)]
struct MonotoneQueue {
    buckets: Vec<Vec<u32>>,
    current: usize,
    in_buckets: usize,
    heap: BinaryHeap<Reverse<(u64, u32)>>,
}

impl MonotoneQueue {
    const BUCKETS: usize = 1024;

    fn clear(&mut self) {
        if self.in_buckets > 0 {
            for b in &mut self.buckets {
                b.clear();
            }
        }
        if self.buckets.is_empty() {
            self.buckets = vec![Vec::new(); Self::BUCKETS];
        }
        self.current = 0;
        self.in_buckets = 0;
        self.heap.clear();
    }

    fn push(&mut self, value: u64, fact: u32) {
        if (value as usize) < Self::BUCKETS {
            self.buckets[value as usize].push(fact);
            self.in_buckets += 1;
        } else {
            self.heap.push(Reverse((value, fact)));
        }
    }

    fn pop(&mut self) -> Option<(u64, u32)> {
        while self.in_buckets > 0 {
            if let Some(f) = self.buckets[self.current].pop() {
                self.in_buckets -= 1;
                return Some((self.current as u64, f));
            }
            self.current += 1;
        }
        self.heap.pop().map(|Reverse(x)| x)
    }
}

/// Scratch memory reused across evaluations.
#[derive(Default)]
pub struct Scratch {
    value: Vec<u64>,
    unsat: Vec<u32>,
    pcf: Vec<u32>,
    cost: Vec<u64>,
    start: Vec<u32>,
    zone: Vec<bool>,
    seen: Vec<bool>,
    in_cut: Vec<bool>,
    stack: Vec<u32>,
    heap: MonotoneQueue,
}

impl Relaxed {
    /// h^max (sum = false) or h^add (sum = true) from the start facts with `cost`;
    /// fills `value` per fact, `pcf` (the precondition with the largest value, h^max)
    /// or the best supporter per fact (h^add, stored in `pcf` indexed by fact).
    fn propagate(&self, s: &mut Scratch, sum: bool) {
        let nf = self.num_facts();
        s.value.clear();
        s.value.resize(nf, INF);
        s.unsat.clear();
        s.unsat.extend(self.pre.iter().map(|p| p.len() as u32));
        s.pcf.clear();
        s.pcf
            .resize(if sum { nf } else { self.pre.len() }, u32::MAX);
        let mut acc = vec![0u64; if sum { self.pre.len() } else { 0 }];
        s.heap.clear();
        for &f in &s.start {
            s.value[f as usize] = 0;
            s.heap.push(0, f);
        }
        while let Some((v, f)) = s.heap.pop() {
            if v > s.value[f as usize] {
                continue;
            }
            for &a in &self.pre_of[f as usize] {
                let a = a as usize;
                if sum {
                    acc[a] = (acc[a] + v).min(INF);
                }
                s.unsat[a] -= 1;
                if s.unsat[a] == 0 {
                    let base = if sum { acc[a] } else { v };
                    if !sum {
                        s.pcf[a] = f;
                    }
                    let val = (base + s.cost[a]).min(INF);
                    for &e in &self.add[a] {
                        if val < s.value[e as usize] {
                            s.value[e as usize] = val;
                            if sum {
                                s.pcf[e as usize] = a as u32;
                            }
                            s.heap.push(val, e);
                        }
                    }
                }
            }
        }
    }

    /// After the costs of `changed` actions dropped, lowers h^max values (and the
    /// precondition choice) where that propagates, in increasing order of new value —
    /// instead of recomputing h^max from scratch in every LM-cut round.
    fn decrease(&self, s: &mut Scratch, changed: &[u32]) {
        s.heap.clear();
        for &a in changed {
            let a = a as usize;
            if s.unsat[a] != 0 {
                continue;
            }
            let v = s.value[s.pcf[a] as usize] + s.cost[a];
            for &e in &self.add[a] {
                if v < s.value[e as usize] {
                    s.value[e as usize] = v;
                    s.heap.push(v, e);
                }
            }
        }
        while let Some((v, f)) = s.heap.pop() {
            if v > s.value[f as usize] {
                continue;
            }
            for &b in &self.pre_of[f as usize] {
                let b = b as usize;
                if s.unsat[b] != 0 {
                    continue;
                }
                let (mut best, mut arg) = (0u64, self.pre[b][0]);
                for &p in &self.pre[b] {
                    if s.value[p as usize] > best {
                        best = s.value[p as usize];
                        arg = p;
                    }
                }
                s.pcf[b] = arg;
                let nv = best + s.cost[b];
                for &e in &self.add[b] {
                    if nv < s.value[e as usize] {
                        s.value[e as usize] = nv;
                        s.heap.push(nv, e);
                    }
                }
            }
        }
    }

    /// LM-cut of `state`; `None` when the relaxed goal is unreachable (a dead end).
    ///
    /// Before the cut rounds, an unreached goal fact with a single achiever makes that
    /// action a landmark on its own: its cost is counted and set to zero at once, which
    /// is the cut LM-cut would find anyway (seed 002's `(removed o)` goals are each
    /// achieved only by `grasp o`), without one h^max round per goal.
    pub fn lmcut(&self, state: &[u64], s: &mut Scratch) -> Option<u64> {
        let mut start = std::mem::take(&mut s.start);
        self.start_facts(state, &mut start);
        s.start = start;
        s.cost.clear();
        s.cost.extend_from_slice(&self.cost);
        let nf = self.num_facts();
        let na = self.pre.len();
        self.propagate(s, false);
        if s.value[self.goal_fact as usize] >= INF {
            return None;
        }
        let mut h = 0u64;
        let mut changed: Vec<u32> = Vec::new();
        for &g in &self.pre[self.goal_action] {
            if s.value[g as usize] > 0
                && let [a] = self.adders[g as usize][..]
                && s.cost[a as usize] > 0
            {
                h += s.cost[a as usize];
                s.cost[a as usize] = 0;
                changed.push(a);
            }
        }
        if !changed.is_empty() {
            self.decrease(s, &changed);
        }
        loop {
            if s.value[self.goal_fact as usize] == 0 {
                return Some(h);
            }
            // Goal zone: facts that reach the goal through zero-cost justification edges.
            s.zone.clear();
            s.zone.resize(nf, false);
            s.zone[self.goal_fact as usize] = true;
            s.stack.clear();
            s.stack.push(self.goal_fact);
            while let Some(f) = s.stack.pop() {
                for &a in &self.adders[f as usize] {
                    let a = a as usize;
                    if s.cost[a] == 0 && s.unsat[a] == 0 {
                        let p = s.pcf[a];
                        if !s.zone[p as usize] {
                            s.zone[p as usize] = true;
                            s.stack.push(p);
                        }
                    }
                }
            }
            // Forward from the start without entering the zone; the cut is every edge into it.
            s.seen.clear();
            s.seen.resize(nf, false);
            s.in_cut.clear();
            s.in_cut.resize(na, false);
            let mut cut: Vec<u32> = Vec::new();
            s.stack.clear();
            for i in 0..s.start.len() {
                let f = s.start[i];
                s.seen[f as usize] = true;
                s.stack.push(f);
            }
            while let Some(f) = s.stack.pop() {
                for &a in &self.pre_of[f as usize] {
                    let au = a as usize;
                    if s.unsat[au] != 0 || s.pcf[au] != f {
                        continue;
                    }
                    for &e in &self.add[au] {
                        if s.zone[e as usize] {
                            if !s.in_cut[au] {
                                s.in_cut[au] = true;
                                cut.push(a);
                            }
                        } else if !s.seen[e as usize] {
                            s.seen[e as usize] = true;
                            s.stack.push(e);
                        }
                    }
                }
            }
            let m = cut.iter().map(|&a| s.cost[a as usize]).min().unwrap_or(0);
            if m == 0 {
                // Cannot happen for a correct cut; stop rather than loop.
                return Some(h);
            }
            h += m;
            for &a in &cut {
                s.cost[a as usize] -= m;
            }
            self.decrease(s, &cut);
        }
    }

    /// Which facts (positive, by fact id) the delete relaxation reaches from `state`;
    /// only facts some precondition or the goal needs are tracked (others read false).
    pub fn reachable_facts(&self, state: &[u64]) -> Vec<bool> {
        let mut s = Scratch::default();
        self.start_facts(state, &mut s.start);
        s.cost.extend(self.cost.iter().map(|_| 0));
        self.propagate(&mut s, false);
        (0..self.n).map(|f| s.value[f] < INF).collect()
    }

    /// h^FF of `state` and the relaxed plan's actions (the preferred operators are those
    /// applicable in the state); `None` for a dead end.
    pub fn ff(&self, state: &[u64], s: &mut Scratch, plan: &mut Vec<u32>) -> Option<u64> {
        let mut start = std::mem::take(&mut s.start);
        self.start_facts(state, &mut start);
        s.start = start;
        s.cost.clear();
        // Unit costs plus the real cost make ties prefer cheap actions, as in LAMA.
        s.cost.extend(self.cost.iter().map(|c| c + 1));
        self.propagate(s, true);
        if s.value[self.goal_fact as usize] >= INF {
            return None;
        }
        plan.clear();
        s.seen.clear();
        s.seen.resize(self.num_facts(), false);
        s.in_cut.clear();
        s.in_cut.resize(self.pre.len(), false);
        for &f in &s.start {
            s.seen[f as usize] = true;
        }
        s.stack.clear();
        s.stack.push(self.goal_fact);
        let mut h = 0;
        while let Some(f) = s.stack.pop() {
            if s.seen[f as usize] {
                continue;
            }
            s.seen[f as usize] = true;
            let a = s.pcf[f as usize];
            if a == u32::MAX || s.in_cut[a as usize] {
                continue;
            }
            s.in_cut[a as usize] = true;
            if a as usize != self.goal_action {
                plan.push(a);
                h += self.cost[a as usize].max(1);
            }
            s.stack.extend(self.pre[a as usize].iter().copied());
        }
        Some(h)
    }
}
