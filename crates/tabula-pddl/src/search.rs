//! Search: A* with LM-cut and strong stubborn sets (optimal), greedy best-first with
//! h^FF and preferred operators (fast).
//!
//! Strong stubborn sets (Alkhazraji et al. 2012; Wehrle & Helmert 2014) expand only a
//! subset of the applicable actions that provably keeps an optimal plan: start from the
//! achievers of one unsatisfied goal literal; for every action in the set that is
//! applicable add every action that interferes with it, for every one that is not add
//! the achievers of one of its unsatisfied preconditions. Clearing separate clusters of
//! a table commutes, and without this A* expands every interleaving. Interference is
//! judged on what actions read (preconditions and effect conditions) and write
//! (every possible effect), which is conservative and so safe with conditional effects.

use crate::ground::{GroundTask, Lit};
use crate::heuristic::{Relaxed, Scratch};
use crate::task::State;
use std::cmp::Reverse;
use std::collections::{BinaryHeap, HashMap};
use std::time::{Duration, Instant};

/// When a search gives up. Expansions are counted, so a budget of them gives the same
/// answer on a loaded machine as on an idle one (a clearing run must not depend on
/// what else the cores do); the timeout is a wall-clock safety net on top.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct Budget {
    /// Wall time from the search's start.
    pub timeout: Option<Duration>,
    /// States expanded, at most.
    pub max_expanded: Option<usize>,
}

impl Budget {
    /// No limit: the search runs until it finds a plan or exhausts the space.
    pub const UNLIMITED: Budget = Budget {
        timeout: None,
        max_expanded: None,
    };

    /// Only a wall-clock limit.
    pub fn timeout(timeout: Option<Duration>) -> Self {
        Budget {
            timeout,
            max_expanded: None,
        }
    }

    /// The running search's clock, started now.
    fn start(self) -> Limit {
        Limit {
            deadline: self.timeout.and_then(|t| Instant::now().checked_add(t)),
            max_expanded: self.max_expanded,
        }
    }
}

/// A [`Budget`] whose clock has started.
#[derive(Debug, Clone, Copy)]
struct Limit {
    deadline: Option<Instant>,
    max_expanded: Option<usize>,
}

impl Limit {
    /// Whether the `expanded`th expansion is over the budget (the clock is read every
    /// 128): a search that needs `max_expanded` expansions still finds its plan.
    fn spent(&self, expanded: usize) -> bool {
        self.max_expanded.is_some_and(|m| expanded > m)
            || (expanded.is_multiple_of(128) && self.deadline.is_some_and(|d| Instant::now() >= d))
    }
}

/// How a search ended.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum SearchStatus {
    /// A plan (optimal for A*).
    Solved,
    /// The whole reachable space was searched (or the initial state is a relaxed dead
    /// end): no plan exists.
    Unsolvable,
    /// The budget (time or expansions) ran out first.
    Timeout,
}

/// The outcome of one search.
#[derive(Debug, Clone)]
pub struct SearchResult {
    pub status: SearchStatus,
    /// Action indices into the task.
    pub plan: Vec<usize>,
    pub cost: u64,
    pub expanded: usize,
    pub generated: usize,
    /// Heuristic value of the initial state (`None` = dead end).
    pub initial_h: Option<u64>,
}

impl SearchResult {
    /// Nothing found yet: the start of every search, and its answer if it exhausts.
    fn unsolvable() -> Self {
        SearchResult {
            status: SearchStatus::Unsolvable,
            plan: Vec::new(),
            cost: 0,
            expanded: 0,
            generated: 1,
            initial_h: None,
        }
    }
}

/// Precomputed relations for stubborn sets.
#[derive(Debug, Clone)]
pub struct Interference {
    /// Actions that make each literal true: index 2f (adds f) and 2f+1 (deletes f).
    achievers: Vec<Vec<u32>>,
    /// Per action: every action that may interfere with it.
    interferers: Vec<Vec<u32>>,
}

impl Interference {
    /// Two actions interfere when one can make a precondition of the other false, their
    /// effects contradict (one adds what the other deletes), or one writes a fact the
    /// other's conditional effects read (then the order changes the result). Enabling
    /// is not interference: clearing one object only helps the others.
    pub fn new(task: &GroundTask) -> Self {
        let n = task.facts.len();
        let mut achievers = vec![Vec::new(); 2 * n];
        let mut requirers = vec![Vec::new(); 2 * n];
        let mut cond_readers = vec![Vec::new(); n];
        for (i, a) in task.actions.iter().enumerate() {
            let i = i as u32;
            for e in &a.effects {
                let slot = &mut achievers[2 * e.fact as usize + usize::from(!e.add)];
                if slot.last() != Some(&i) {
                    slot.push(i);
                }
                for c in &e.cond {
                    let slot = &mut cond_readers[c.fact as usize];
                    if slot.last() != Some(&i) {
                        slot.push(i);
                    }
                }
            }
            for l in &a.pre {
                requirers[2 * l.fact as usize + usize::from(!l.positive)].push(i);
            }
        }
        let interferers = task
            .actions
            .iter()
            .map(|a| {
                let mut out: Vec<u32> = Vec::new();
                for e in &a.effects {
                    let f = 2 * e.fact as usize;
                    // Adding f disables requirers of ¬f and contradicts deleters of f; deleting
                    // f disables requirers of f and contradicts adders.
                    let (disabled, contradicted) = if e.add { (f + 1, f + 1) } else { (f, f) };
                    out.extend(&requirers[disabled]);
                    out.extend(&achievers[contradicted]);
                    out.extend(&cond_readers[e.fact as usize]);
                }
                for l in &a.pre {
                    // Who can falsify this precondition.
                    out.extend(&achievers[2 * l.fact as usize + usize::from(l.positive)]);
                }
                for c in a.effects.iter().flat_map(|e| &e.cond) {
                    out.extend(&achievers[2 * c.fact as usize]);
                    out.extend(&achievers[2 * c.fact as usize + 1]);
                }
                out.sort_unstable();
                out.dedup();
                out
            })
            .collect();
        Self {
            achievers,
            interferers,
        }
    }

    fn achievers_of(&self, l: Lit) -> &[u32] {
        &self.achievers[2 * l.fact as usize + usize::from(!l.positive)]
    }

    /// Applicable actions of a strong stubborn set of `state` (not a goal state).
    fn stubborn_applicable(
        &self,
        task: &GroundTask,
        state: &[u64],
        mark: &mut Vec<bool>,
        out: &mut Vec<usize>,
    ) {
        mark.clear();
        mark.resize(task.actions.len(), false);
        out.clear();
        let mut queue: Vec<u32> = Vec::new();
        let push = |a: u32, mark: &mut Vec<bool>, queue: &mut Vec<u32>| {
            if !mark[a as usize] {
                mark[a as usize] = true;
                queue.push(a);
            }
        };
        let pick = |lits: &[Lit]| {
            lits.iter()
                .filter(|&&l| !GroundTask::holds(state, l))
                .min_by_key(|&&l| self.achievers_of(l).len())
                .copied()
        };
        // Any unsatisfied goal literal is correct; a single applicable achiever that few
        // actions interfere with (an isolated object) usually gives the smallest set.
        let goal = task
            .goal
            .iter()
            .filter(|&&l| !GroundTask::holds(state, l))
            .min_by_key(|&&l| {
                let ach = self.achievers_of(l);
                let all_applicable = ach.iter().all(|&a| task.applicable(state, a as usize));
                (
                    !all_applicable,
                    ach.iter()
                        .map(|&a| self.interferers[a as usize].len())
                        .sum::<usize>(),
                )
            });
        if let Some(&g) = goal {
            for &a in self.achievers_of(g) {
                push(a, mark, &mut queue);
            }
        }
        while let Some(a) = queue.pop() {
            let au = a as usize;
            match pick(&task.actions[au].pre) {
                Some(p) => {
                    for &b in self.achievers_of(p) {
                        push(b, mark, &mut queue);
                    }
                }
                None => {
                    out.push(au);
                    for &b in &self.interferers[au] {
                        push(b, mark, &mut queue);
                    }
                }
            }
        }
        out.sort_unstable();
    }
}

struct Node {
    state: State,
    g: u64,
    parent: u32,
    action: u32,
}

struct Registry {
    nodes: Vec<Node>,
    index: HashMap<State, u32>,
}

impl Registry {
    fn new() -> Self {
        Self {
            nodes: Vec::new(),
            index: HashMap::new(),
        }
    }

    fn plan(&self, mut id: u32) -> Vec<usize> {
        let mut plan = Vec::new();
        while self.nodes[id as usize].parent != u32::MAX {
            plan.push(self.nodes[id as usize].action as usize);
            id = self.nodes[id as usize].parent;
        }
        plan.reverse();
        plan
    }
}

fn applicable_all(task: &GroundTask, state: &[u64], out: &mut Vec<usize>) {
    out.clear();
    out.extend((0..task.actions.len()).filter(|&a| task.applicable(state, a)));
}

/// A* with LM-cut; `stubborn` switches strong stubborn sets on. Ties on f go to the
/// lower h, then to the earlier generated node, so the result is deterministic.
pub fn astar(task: &GroundTask, stubborn: bool, budget: Budget) -> SearchResult {
    let limit = budget.start();
    let relaxed = Relaxed::new(task);
    let sss = stubborn.then(|| Interference::new(task));
    let mut scratch = Scratch::default();
    let mut reg = Registry::new();
    let init = task.initial_state();
    let mut result = SearchResult::unsolvable();
    if task.goal_unreachable {
        return result;
    }
    let h0 = relaxed.lmcut(&init, &mut scratch);
    result.initial_h = h0;
    let Some(h0) = h0 else { return result };
    let mut heuristic: Vec<u64> = vec![h0];
    reg.index.insert(init.clone(), 0);
    reg.nodes.push(Node {
        state: init,
        g: 0,
        parent: u32::MAX,
        action: 0,
    });
    let mut open = BinaryHeap::new();
    let mut counter = 0u64;
    open.push(Reverse((h0, h0, counter, 0u32, 0u64)));
    let mut closed_g: Vec<u64> = vec![u64::MAX];
    let (mut ops, mut mark) = (Vec::new(), Vec::new());
    while let Some(Reverse((_, _, _, id, g))) = open.pop() {
        let idu = id as usize;
        if g > reg.nodes[idu].g || closed_g[idu] <= g {
            continue;
        }
        closed_g[idu] = g;
        let state = reg.nodes[idu].state.clone();
        if task.is_goal(&state) {
            result.status = SearchStatus::Solved;
            result.plan = reg.plan(id);
            result.cost = g;
            return result;
        }
        result.expanded += 1;
        if limit.spent(result.expanded) {
            result.status = SearchStatus::Timeout;
            return result;
        }
        match &sss {
            Some(sss) => sss.stubborn_applicable(task, &state, &mut mark, &mut ops),
            None => applicable_all(task, &state, &mut ops),
        }
        for &a in &ops {
            let succ = task.apply(&state, a);
            let ng = g + task.actions[a].cost;
            result.generated += 1;
            let sid = match reg.index.get(&succ) {
                Some(&sid) => {
                    if ng >= reg.nodes[sid as usize].g {
                        continue;
                    }
                    let n = &mut reg.nodes[sid as usize];
                    n.g = ng;
                    n.parent = id;
                    n.action = a as u32;
                    sid
                }
                None => {
                    let Some(h) = relaxed.lmcut(&succ, &mut scratch) else {
                        continue;
                    };
                    let sid = reg.nodes.len() as u32;
                    reg.index.insert(succ.clone(), sid);
                    reg.nodes.push(Node {
                        state: succ,
                        g: ng,
                        parent: id,
                        action: a as u32,
                    });
                    heuristic.push(h);
                    closed_g.push(u64::MAX);
                    sid
                }
            };
            let h = heuristic[sid as usize];
            counter += 1;
            open.push(Reverse((ng + h, h, counter, sid, ng)));
        }
    }
    result
}

/// Greedy best-first search with h^FF, preferred operators in a second queue that is
/// taken from first after progress (boosted, as in LAMA), stubborn-set pruning, eager
/// evaluation. Ties go to the newest node: on plateaus (equal h) that dives instead of
/// sweeping the plateau breadth-first, which on generated tables took 51,005
/// expansions for a 53-step plan (FIFO) against 53 (LIFO).
pub fn gbfs(task: &GroundTask, budget: Budget) -> SearchResult {
    let limit = budget.start();
    let relaxed = Relaxed::new(task);
    // Stubborn sets keep at least one plan (completeness), so they prune here too.
    let sss = Interference::new(task);
    let mut mark = Vec::new();
    let mut scratch = Scratch::default();
    let mut reg = Registry::new();
    let init = task.initial_state();
    let mut result = SearchResult::unsolvable();
    if task.goal_unreachable {
        return result;
    }
    let mut relaxed_plan = Vec::new();
    let h0 = relaxed.ff(&init, &mut scratch, &mut relaxed_plan);
    result.initial_h = h0;
    let Some(h0) = h0 else { return result };
    let mut preferred_of: Vec<Vec<u32>> = vec![relaxed_plan.clone()];
    reg.index.insert(init.clone(), 0);
    reg.nodes.push(Node {
        state: init,
        g: 0,
        parent: u32::MAX,
        action: 0,
    });
    let mut queues = [BinaryHeap::new(), BinaryHeap::new()];
    let mut counter = 0u64;
    queues[0].push(Reverse((h0, counter, 0u32)));
    let mut expanded = vec![false];
    let mut best_h = h0;
    let mut boost = 0u32;
    let mut turn = 0usize;
    let mut ops = Vec::new();
    loop {
        let q = if boost > 0 && !queues[1].is_empty() {
            boost -= 1;
            1
        } else {
            turn ^= 1;
            if queues[turn].is_empty() {
                turn ^ 1
            } else {
                turn
            }
        };
        let Some(Reverse((_, _, id))) = queues[q].pop() else {
            if queues[0].is_empty() && queues[1].is_empty() {
                return result;
            }
            continue;
        };
        let idu = id as usize;
        if expanded[idu] {
            continue;
        }
        expanded[idu] = true;
        let state = reg.nodes[idu].state.clone();
        if task.is_goal(&state) {
            result.status = SearchStatus::Solved;
            result.plan = reg.plan(id);
            result.cost = reg.nodes[idu].g;
            return result;
        }
        result.expanded += 1;
        if limit.spent(result.expanded) {
            result.status = SearchStatus::Timeout;
            return result;
        }
        sss.stubborn_applicable(task, &state, &mut mark, &mut ops);
        let preferred = std::mem::take(&mut preferred_of[idu]);
        for &a in &ops {
            let succ = task.apply(&state, a);
            result.generated += 1;
            if reg.index.contains_key(&succ) {
                continue;
            }
            let Some(h) = relaxed.ff(&succ, &mut scratch, &mut relaxed_plan) else {
                continue;
            };
            let sid = reg.nodes.len() as u32;
            reg.index.insert(succ.clone(), sid);
            let g = reg.nodes[idu].g + task.actions[a].cost;
            reg.nodes.push(Node {
                state: succ,
                g,
                parent: id,
                action: a as u32,
            });
            preferred_of.push(relaxed_plan.clone());
            expanded.push(false);
            counter += 1;
            queues[0].push(Reverse((h, u64::MAX - counter, sid)));
            if preferred.contains(&(a as u32)) {
                queues[1].push(Reverse((h, u64::MAX - counter, sid)));
            }
            if h < best_h {
                best_h = h;
                boost += 1000;
            }
        }
    }
}
