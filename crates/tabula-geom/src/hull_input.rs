//! Points for a 3D convex hull, few enough for parry's quickhull: it goes quadratic on
//! many coplanar or cocircular points (a 100,000-corner polygon took minutes, a
//! 2-million-triangle sphere over a minute and 1.7 GB).

use crate::Vec3;

/// Most points handed to the hull of a stable-pose analysis: a cell of the thinning
/// grid is then at most a few thousandths of the object's size.
pub const MAX_HULL_INPUT: usize = 5_000;

/// `None` when there are at most `max` points; else the point farthest from the box's
/// centre in each cell of the finest grid (from 1/2000 of the diagonal, doubling) that
/// leaves at most `max` — the outermost points, so the hull shrinks by less than one
/// cell.
pub fn thin_for_hull(points: &[Vec3], max: usize) -> Option<Vec<Vec3>> {
    thinned_with_cell(points, max).map(|(kept, _)| kept)
}

/// [`thin_for_hull`] and the cell size (m) it took: the most the hull shrinks by.
pub fn thinned_with_cell(points: &[Vec3], max: usize) -> Option<(Vec<Vec3>, f64)> {
    if points.len() <= max {
        return None;
    }
    let (lo, hi) = crate::bounds(points);
    let centre = (lo + hi) / 2.0;
    let mut leaf = (hi - lo).length() / 2000.0;
    loop {
        let mut kept = outermost_per_cell(points, centre, leaf);
        if kept.len() <= max {
            sort_points(&mut kept);
            return Some((kept, leaf));
        }
        leaf *= 2.0;
    }
}

/// The point of `points` farthest from `centre` in each `cell`-sized voxel, in no
/// particular order: the hull of these loses less than a cell's diagonal.
pub fn outermost_per_cell<'a>(
    points: impl IntoIterator<Item = &'a Vec3>,
    centre: Vec3,
    cell: f64,
) -> Vec<Vec3> {
    let mut cells: std::collections::HashMap<[i64; 3], Vec3> = Default::default();
    for p in points {
        let kept = cells.entry(crate::voxel_key(*p, cell)).or_insert(*p);
        if p.distance_squared(centre) > kept.distance_squared(centre) {
            *kept = *p;
        }
    }
    cells.into_values().collect()
}

/// Points in lexicographic order (a hull does not depend on its input's order, but
/// its triangles' order does).
pub fn sort_points(points: &mut [Vec3]) {
    points.sort_by(|a, b| {
        a.to_array()
            .partial_cmp(&b.to_array())
            .unwrap_or(std::cmp::Ordering::Equal)
    });
}
