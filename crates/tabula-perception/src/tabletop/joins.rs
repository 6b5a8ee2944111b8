//! What the joins of pieces into objects share (an occluded object's pieces, a
//! container's inside and outside): each point's piece on the grid, and the merge.

/// Each point's region among `n` points (`u32::MAX`: none).
pub(super) fn labels(n: usize, regions: &[Vec<usize>]) -> Vec<u32> {
    let mut label = vec![u32::MAX; n];
    for (r, members) in regions.iter().enumerate() {
        for &i in members {
            label[i] = r as u32;
        }
    }
    label
}

/// `regions` with the two regions of every pair made one (and what those join,
/// transitively); each region's members sorted.
pub(super) fn merge(mut regions: Vec<Vec<usize>>, pairs: &[(usize, usize)]) -> Vec<Vec<usize>> {
    let mut parent: Vec<usize> = (0..regions.len()).collect();
    let root = |parent: &[usize], mut r: usize| {
        while parent[r] != r {
            r = parent[r];
        }
        r
    };
    for &(a, b) in pairs {
        let (ra, rb) = (root(&parent, a), root(&parent, b));
        if ra != rb {
            parent[ra.max(rb)] = ra.min(rb);
        }
    }
    for r in 0..regions.len() {
        let into = root(&parent, r);
        if into != r {
            let moved = std::mem::take(&mut regions[r]);
            regions[into].extend(moved);
        }
    }
    regions.retain(|r| !r.is_empty());
    for r in &mut regions {
        r.sort_unstable();
    }
    regions
}

#[cfg(test)]
mod tests {
    #[test]
    fn pairs_join_transitively() {
        let regions = vec![vec![5], vec![1, 0], vec![7], vec![3]];
        let merged = super::merge(regions, &[(3, 1), (1, 0)]);
        assert_eq!(merged, vec![vec![0, 1, 3, 5], vec![7]]);
    }
}
