//! A thin wrapper over kiddo's immutable kd-tree for the unorganized-cloud paths.

use kiddo::{ImmutableKdTree, SquaredEuclidean};
use std::num::NonZero;

pub(crate) struct KdTree {
    tree: ImmutableKdTree<f64, 3>,
}

impl KdTree {
    /// `None` when the points cannot be indexed (kiddo's item type holds 2³² points).
    pub(crate) fn build(points: &[[f64; 3]]) -> Option<Self> {
        ImmutableKdTree::new_from_slice(points)
            .ok()
            .map(|tree| Self { tree })
    }

    /// The `n` nearest points as (squared distance, index), nearest first.
    pub(crate) fn nearest(&self, q: &[f64; 3], n: usize) -> Vec<(f64, usize)> {
        let Some(n) = NonZero::new(n) else {
            return Vec::new();
        };
        self.tree
            .query(q)
            .nearest_n::<SquaredEuclidean<f64>>(n)
            .execute()
            .into_iter()
            .map(|m| (m.distance, m.item as usize))
            .collect()
    }

    /// Indices of the points within squared distance `r2`, in no particular order.
    pub(crate) fn within(&self, q: &[f64; 3], r2: f64) -> Vec<usize> {
        self.tree
            .query(q)
            .within::<SquaredEuclidean<f64>>(r2)
            .unsorted()
            .execute()
            .into_iter()
            .map(|m| m.item as usize)
            .collect()
    }
}
