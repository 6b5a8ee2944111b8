//! States of a ground task and the successor function.

use crate::ground::{GroundTask, Lit};

/// A state: one bit per fluent fact.
pub type State = Box<[u64]>;

impl GroundTask {
    /// Words per state.
    pub fn words(&self) -> usize {
        self.facts.len().div_ceil(64).max(1)
    }

    /// The initial state.
    pub fn initial_state(&self) -> State {
        let mut s = vec![0u64; self.words()].into_boxed_slice();
        for (f, &v) in self.init.iter().enumerate() {
            if v {
                s[f / 64] |= 1 << (f % 64);
            }
        }
        s
    }

    /// True when `lit` holds in `state`.
    #[inline]
    pub fn holds(state: &[u64], lit: Lit) -> bool {
        let f = lit.fact as usize;
        ((state[f / 64] >> (f % 64)) & 1 == 1) == lit.positive
    }

    pub fn is_goal(&self, state: &[u64]) -> bool {
        !self.goal_unreachable && self.goal.iter().all(|&l| Self::holds(state, l))
    }

    pub fn applicable(&self, state: &[u64], action: usize) -> bool {
        self.actions[action]
            .pre
            .iter()
            .all(|&l| Self::holds(state, l))
    }

    /// The successor of `state` by an applicable action: conditions are read in the old
    /// state, deletes apply before adds (so an add wins, as PDDL says).
    pub fn apply(&self, state: &[u64], action: usize) -> State {
        let mut next: State = state.into();
        let a = &self.actions[action];
        let fires = |e: &crate::ground::CondEffect| e.cond.iter().all(|&l| Self::holds(state, l));
        for e in a.effects.iter().filter(|e| !e.add && fires(e)) {
            let f = e.fact as usize;
            next[f / 64] &= !(1 << (f % 64));
        }
        for e in a.effects.iter().filter(|e| e.add && fires(e)) {
            let f = e.fact as usize;
            next[f / 64] |= 1 << (f % 64);
        }
        next
    }
}
