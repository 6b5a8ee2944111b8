//! The initial state indexed by predicate and arguments, for static tests.

use crate::*;
use rustc_hash::{FxHashMap, FxHashSet};

/// Membership in the initial state. Quantified effects ask it for every object
/// (`forall ?x (when (block_dir1 ?o ?x) …)`), so predicates of small arity get a dense
/// bit table indexed by object ids instead of a hash lookup.
pub(super) struct InitIndex {
    pub(super) objects: usize,
    pub(super) dense: Vec<Option<Vec<u64>>>,
    pub(super) sparse: FxHashSet<Vec<u32>>,
    /// Every initial atom, and for (predicate, argument position, object) the atoms
    /// that have that object there; position `u32::MAX` lists a predicate's atoms.
    pub(super) keys: Vec<Vec<u32>>,
    pub(super) by_arg: FxHashMap<(u32, u32, u32), Vec<u32>>,
}

impl InitIndex {
    const DENSE_LIMIT: usize = 1 << 22;

    pub(super) fn new(domain: &Domain, objects: usize, keys: Vec<Vec<u32>>) -> Self {
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
    pub(super) fn cell(&self, key: &[u32]) -> Option<usize> {
        let mut c = 0usize;
        for &o in &key[1..] {
            if o as usize >= self.objects {
                return None;
            }
            c = c * self.objects + o as usize;
        }
        Some(c)
    }

    pub(super) fn contains(&self, key: &[u32]) -> bool {
        if let Some(Some(bits)) = self.dense.get(key[0] as usize)
            && let Some(c) = self.cell(key)
            && c / 64 < bits.len()
        {
            return (bits[c / 64] >> (c % 64)) & 1 == 1;
        }
        self.sparse.contains(key)
    }
}
