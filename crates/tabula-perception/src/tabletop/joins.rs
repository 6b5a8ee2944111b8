//! What the joins of pieces into objects share (an occluded object's pieces, a
//! container's inside and outside, a concave part and the piece around it): each
//! point's piece on the grid, whether two pieces touch there, and the merge.

/// Pieces touch on the grid: pixels at most this far apart.
const TOUCH_PIXELS: usize = 2;

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

/// Whether some pixel of `members` is within [`TOUCH_PIXELS`] of one labelled `other`
/// (`label` on a grid `width` wide).
pub(super) fn touches(label: &[u32], width: usize, members: &[usize], other: u32) -> bool {
    pixels_near(label, width, members, other).next().is_some()
}

/// The pixels labelled `other` within [`TOUCH_PIXELS`] of some pixel of `members`
/// (`label` on a grid `width` wide), once for each member they are near.
pub(super) fn pixels_near<'a>(
    label: &'a [u32],
    width: usize,
    members: &'a [usize],
    other: u32,
) -> impl Iterator<Item = usize> + 'a {
    let height = label.len() / width;
    let t = TOUCH_PIXELS as isize;
    members.iter().flat_map(move |&i| {
        let (x, y) = ((i % width) as isize, (i / width) as isize);
        (-t..=t).flat_map(move |dy| {
            (-t..=t).filter_map(move |dx| {
                let (xx, yy) = (x + dx, y + dy);
                let inside = xx >= 0 && yy >= 0 && (xx as usize) < width && (yy as usize) < height;
                let j = yy as usize * width + xx as usize;
                (inside && label[j] == other).then_some(j)
            })
        })
    })
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

    #[test]
    fn pieces_two_pixels_apart_touch_and_three_apart_do_not() {
        const N: u32 = u32::MAX;
        // A 6 × 2 grid: piece 0 at column 0, piece 1 at column 2 (two apart), piece 2
        // at column 5 (three from piece 1).
        let label = [0, N, 1, N, N, 2, N, N, N, N, N, N];
        let members_of_1 = [2];
        assert!(super::touches(&label, 6, &members_of_1, 0));
        assert!(!super::touches(&label, 6, &members_of_1, 2));
    }
}
