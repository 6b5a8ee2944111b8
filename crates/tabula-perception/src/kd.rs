//! A thin wrapper over kiddo's immutable kd-tree for the unorganized-cloud paths.

use kiddo::{ImmutableKdTree, SquaredEuclidean};
use std::num::NonZero;

/// Single precision: neighbours of points a few metres apart need no more, and the
/// tree is half the memory and faster to search.
pub(crate) struct KdTree {
    tree: ImmutableKdTree<f32, 3>,
}

fn f32s(q: &[f64; 3]) -> [f32; 3] {
    q.map(|v| v as f32)
}

impl KdTree {
    /// `None` when the points cannot be indexed (kiddo's item type holds 2³² points).
    pub(crate) fn build(points: &[[f64; 3]]) -> Option<Self> {
        let points: Vec<[f32; 3]> = points.iter().map(f32s).collect();
        ImmutableKdTree::new_from_slice(&points)
            .ok()
            .map(|tree| Self { tree })
    }

    /// The `n` nearest points as (squared distance, index), in no particular order.
    pub(crate) fn nearest(&self, q: &[f64; 3], n: usize) -> Vec<(f64, usize)> {
        let Some(n) = NonZero::new(n) else {
            return Vec::new();
        };
        self.tree
            .query(&f32s(q))
            .nearest_n::<SquaredEuclidean<f32>>(n)
            .unsorted()
            .execute()
            .into_iter()
            .map(|m| (m.distance as f64, m.item as usize))
            .collect()
    }

    /// Indices of the points within squared distance `r2`, in no particular order.
    pub(crate) fn within(&self, q: &[f64; 3], r2: f64) -> Vec<usize> {
        self.tree
            .query(&f32s(q))
            .within::<SquaredEuclidean<f32>>(r2 as f32)
            .unsorted()
            .execute()
            .into_iter()
            .map(|m| m.item as usize)
            .collect()
    }
}
