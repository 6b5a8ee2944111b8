//! Neighbour search for unorganized clouds: kiddo's immutable kd-tree behind voxel
//! hashes.
//!
//! Sensor clouds are surfaces sampled at a locally even spacing, so a point's k nearest
//! neighbours nearly always lie in the 3×3×3 block of cells around it when the cell is
//! about the k-th neighbour distance. The hashes answer those queries exactly (a result
//! is only taken when its farthest neighbour is within one cell, which the block is
//! guaranteed to cover); the rest go to the tree.

use kiddo::{ImmutableKdTree, SquaredEuclidean};
use rustc_hash::FxHashMap;
use std::num::NonZero;

/// Single precision: neighbours of points a few metres apart need no more, and the
/// structures are half the memory and faster to search.
pub(crate) struct KdTree {
    tree: ImmutableKdTree<f32, 3>,
    points: Vec<[f32; 3]>,
    /// Voxel hashes, finest first, each cell twice the last: a depth frame's spacing
    /// grows with range, so far points are answered by a coarser level.
    levels: Vec<Level>,
}

/// Integer coordinates of a cell.
type CellKey = (i32, i32, i32);

struct Level {
    cell: f32,
    /// Cell → range in `order`.
    cells: FxHashMap<CellKey, (u32, u32)>,
    /// Point indices grouped by cell.
    order: Vec<u32>,
}

fn f32s(q: &[f64; 3]) -> [f32; 3] {
    q.map(|v| v as f32)
}

fn d2(a: &[f32; 3], b: &[f32; 3]) -> f32 {
    let (x, y, z) = (a[0] - b[0], a[1] - b[1], a[2] - b[2]);
    x * x + y * y + z * z
}

impl Level {
    /// Groups the points by cell with a counting sort (one hash lookup per point).
    fn new(points: &[[f32; 3]], cell: f32) -> Self {
        let mut level = Level {
            cell,
            cells: FxHashMap::default(),
            order: Vec::new(),
        };
        let mut slot_of: Vec<u32> = Vec::with_capacity(points.len());
        let mut counts: Vec<u32> = Vec::new();
        let mut ids: FxHashMap<CellKey, u32> = FxHashMap::default();
        for p in points {
            let next = counts.len() as u32;
            let id = *ids.entry(level.key(p)).or_insert(next);
            if id == next {
                counts.push(0);
            }
            counts[id as usize] += 1;
            slot_of.push(id);
        }
        let mut starts: Vec<u32> = Vec::with_capacity(counts.len());
        let mut total = 0u32;
        for &c in &counts {
            starts.push(total);
            total += c;
        }
        let mut fill = starts.clone();
        level.order = vec![0; points.len()];
        for (i, &id) in slot_of.iter().enumerate() {
            level.order[fill[id as usize] as usize] = i as u32;
            fill[id as usize] += 1;
        }
        level.cells = ids
            .into_iter()
            .map(|(key, id)| (key, (starts[id as usize], counts[id as usize])))
            .collect();
        level
    }

    fn key(&self, q: &[f32; 3]) -> CellKey {
        let k = |v: f32| (v / self.cell).floor() as i32;
        (k(q[0]), k(q[1]), k(q[2]))
    }

    /// Squared distances and indices of the points in the 3×3×3 cells around `q`.
    fn block(&self, points: &[[f32; 3]], q: &[f32; 3], out: &mut Vec<(f32, usize)>) {
        let (x, y, z) = self.key(q);
        for dx in -1..=1 {
            for dy in -1..=1 {
                for dz in -1..=1 {
                    if let Some(&(s, len)) = self.cells.get(&(x + dx, y + dy, z + dz)) {
                        for &i in &self.order[s as usize..(s + len) as usize] {
                            out.push((d2(q, &points[i as usize]), i as usize));
                        }
                    }
                }
            }
        }
    }
}

impl KdTree {
    /// The points `indices` of a cloud; results index into `indices`.
    pub(crate) fn over(points: &[tabula_geom::Vec3], indices: &[usize]) -> Option<Self> {
        let coords: Vec<[f64; 3]> = indices.iter().map(|&i| points[i].to_array()).collect();
        Self::build(&coords)
    }

    /// `None` when the points cannot be indexed (kiddo's item type holds 2³² points).
    pub(crate) fn build(points: &[[f64; 3]]) -> Option<Self> {
        let points: Vec<[f32; 3]> = points.iter().map(f32s).collect();
        let tree = ImmutableKdTree::new_from_slice(&points).ok()?;
        let mut index = Self {
            tree,
            points,
            levels: Vec::new(),
        };
        // Finest cell: the median distance to the 32nd neighbour over a sample, so
        // that queries for up to about 30 neighbours mostly stay in the block.
        let n = index.points.len();
        if n > 64 {
            let mut r: Vec<f32> = (0..256)
                .map(|k| k * n / 256)
                .map(|i| {
                    let q = index.points[i];
                    index
                        .tree_nearest(&q, 33)
                        .iter()
                        .map(|m| m.0)
                        .fold(0.0f32, f32::max)
                        .sqrt()
                })
                .collect();
            let mid = r.len() / 2;
            let cell = *r.select_nth_unstable_by(mid, f32::total_cmp).1;
            if cell.is_finite() && cell > 0.0 {
                index.levels = (0..4)
                    .map(|l| Level::new(&index.points, cell * (1 << l) as f32))
                    .collect();
            }
        }
        Some(index)
    }

    fn tree_nearest(&self, q: &[f32; 3], n: usize) -> Vec<(f32, usize)> {
        let Some(n) = NonZero::new(n) else {
            return Vec::new();
        };
        self.tree
            .query(q)
            .nearest_n::<SquaredEuclidean<f32>>(n)
            .unsorted()
            .execute()
            .into_iter()
            .map(|m| (m.distance, m.item as usize))
            .collect()
    }

    /// The `n` nearest points of `q` from the voxel levels, if one answers exactly.
    fn hashed_nearest(&self, q: &[f32; 3], n: usize, skip: usize) -> Option<Vec<(f32, usize)>> {
        let mut found = Vec::with_capacity(8 * n);
        for level in self.levels.iter().skip(skip) {
            found.clear();
            level.block(&self.points, q, &mut found);
            if n > 0 && found.len() >= n {
                found.select_nth_unstable_by(n - 1, |a, b| a.0.total_cmp(&b.0));
                if found[n - 1].0 <= level.cell * level.cell {
                    found.truncate(n);
                    return Some(found);
                }
            }
        }
        None
    }

    /// The `n` nearest points as (squared distance, index), in no particular order.
    pub(crate) fn nearest(&self, q: &[f64; 3], n: usize) -> Vec<(f64, usize)> {
        let q = f32s(q);
        self.hashed_nearest(&q, n, 0)
            .unwrap_or_else(|| self.tree_nearest(&q, n))
            .into_iter()
            .map(|(d, i)| (d as f64, i))
            .collect()
    }

    /// For every indexed point, the mean distance to its `n` nearest other points.
    /// Queries are answered cell by cell, so the 27 cells around a cell are gathered
    /// once for all of the points in it.
    pub(crate) fn mean_neighbour_distances(&self, n: usize) -> Vec<f64> {
        use rayon::prelude::*;
        let total = self.points.len();
        let mut out = vec![f64::INFINITY; total];
        if n == 0 || total < 2 {
            return out;
        }
        let want = n.min(total - 1) + 1;
        let slow = |i: usize| -> f64 {
            let nn = self.tree_nearest(&self.points[i], want);
            nn.iter().map(|m| (m.0 as f64).sqrt()).sum::<f64>() / (nn.len().max(2) - 1) as f64
        };
        if self.levels.is_empty() {
            out.par_iter_mut()
                .enumerate()
                .for_each(|(i, o)| *o = slow(i));
            return out;
        }
        // Level by level: the points a level cannot answer try the next one, grouped
        // by their cell there; the last few go to the tree.
        let mut pending: Vec<u32> = Vec::new();
        for (l, level) in self.levels.iter().enumerate() {
            let limit = level.cell * level.cell;
            // Every point is pending at the first level, already grouped by its cells.
            let by_cell: Vec<(CellKey, u32)> = if l == 0 {
                level
                    .order
                    .iter()
                    .map(|&i| (level.key(&self.points[i as usize]), i))
                    .collect()
            } else {
                let mut v: Vec<(CellKey, u32)> = pending
                    .iter()
                    .map(|&i| (level.key(&self.points[i as usize]), i))
                    .collect();
                v.sort_unstable();
                v
            };
            let groups: Vec<&[(CellKey, u32)]> = by_cell.chunk_by(|a, b| a.0 == b.0).collect();
            let results: Vec<(u32, Option<f64>)> = groups
                .par_iter()
                .flat_map_iter(|group| {
                    let first = self.points[group[0].1 as usize];
                    let mut found = Vec::new();
                    level.block(&self.points, &first, &mut found);
                    let block: Vec<[f32; 3]> = found.iter().map(|&(_, j)| self.points[j]).collect();
                    let mut d = vec![0.0f32; block.len()];
                    group.iter().map(move |&(_, i)| {
                        let q = self.points[i as usize];
                        if block.len() < want {
                            return (i, None);
                        }
                        for (dj, p) in d.iter_mut().zip(&block) {
                            *dj = d2(&q, p);
                        }
                        d.select_nth_unstable_by(want - 1, f32::total_cmp);
                        // The point itself is among them at distance 0.
                        let mean = (d[want - 1] <= limit).then(|| {
                            d[..want].iter().map(|v| (*v as f64).sqrt()).sum::<f64>()
                                / (want - 1) as f64
                        });
                        (i, mean)
                    })
                })
                .collect();
            pending.clear();
            for (i, m) in results {
                match m {
                    Some(m) => out[i as usize] = m,
                    None => pending.push(i),
                }
            }
            if pending.is_empty() {
                break;
            }
        }
        let rest: Vec<(u32, f64)> = pending.par_iter().map(|&i| (i, slow(i as usize))).collect();
        for (i, m) in rest {
            out[i as usize] = m;
        }
        out
    }

    /// Indices of the points within squared distance `r2`, in no particular order.
    pub(crate) fn within(&self, q: &[f64; 3], r2: f64) -> Vec<usize> {
        let q = f32s(q);
        let r2 = r2 as f32;
        if let Some(level) = self.levels.iter().find(|l| r2 <= l.cell * l.cell) {
            let mut found = Vec::new();
            level.block(&self.points, &q, &mut found);
            return found
                .into_iter()
                .filter(|(d, _)| *d <= r2)
                .map(|(_, i)| i)
                .collect();
        }
        self.tree
            .query(&q)
            .within::<SquaredEuclidean<f32>>(r2)
            .unsorted()
            .execute()
            .into_iter()
            .map(|m| m.item as usize)
            .collect()
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use rand::{RngExt, SeedableRng};

    #[test]
    fn hash_answers_match_brute_force() {
        let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(1);
        // A noisy surface plus scattered points, like a depth frame.
        let mut pts: Vec<[f64; 3]> = (0..3000)
            .map(|_| {
                let (x, y) = (rng.random_range(0.0..1.0), rng.random_range(0.0..1.0));
                [x, y, 0.1 * x + rng.random_range(-0.002..0.002)]
            })
            .collect();
        pts.extend((0..100).map(|_| {
            [
                rng.random_range(-1.0..2.0),
                rng.random_range(-1.0..2.0),
                rng.random_range(-1.0..2.0),
            ]
        }));
        let index = KdTree::build(&pts).unwrap();
        assert!(!index.levels.is_empty());
        let dist = |a: &[f64; 3], b: &[f64; 3]| (0..3).map(|k| (a[k] - b[k]).powi(2)).sum::<f64>();
        for qi in (0..pts.len()).step_by(37) {
            let q = pts[qi];
            let mut truth: Vec<f64> = pts.iter().map(|p| dist(&q, p)).collect();
            truth.sort_by(f64::total_cmp);
            for n in [1, 5, 21, 60] {
                let mut got: Vec<f64> = index.nearest(&q, n).iter().map(|m| m.0).collect();
                got.sort_by(f64::total_cmp);
                assert_eq!(got.len(), n);
                assert!(
                    (got[n - 1] - truth[n - 1]).abs() < 1e-5,
                    "query {qi}, n {n}"
                );
            }
            for r in [0.01, 0.05, 0.5] {
                let got = index.within(&q, r * r).len();
                let want = truth.iter().filter(|d| **d <= r * r).count();
                assert!(
                    got.abs_diff(want) <= 1,
                    "query {qi}, r {r}: {got} vs {want}"
                );
            }
        }
    }
}
