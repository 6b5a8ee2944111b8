//! Splitting the points on a plane into connected pieces on a grid of cells: which
//! cells hold points on the plane, which pieces they form, the pieces' areas, room
//! inside and outlines.

use super::{Surface, SurfaceParams, plane_basis};
use crate::plane::Plane;
use tabula_geom::polygon::{convex_hull_2d, polygon_area};
use tabula_geom::{Vec2, Vec3};

const EMPTY: u32 = u32::MAX;
const UNSET: u32 = u32::MAX - 1;

/// The eight directions a cell keeps its extreme points in.
const DIRS: [(f64, f64); 8] = [
    (1.0, 0.0),
    (-1.0, 0.0),
    (0.0, 1.0),
    (0.0, -1.0),
    (1.0, 1.0),
    (1.0, -1.0),
    (-1.0, 1.0),
    (-1.0, -1.0),
];

/// A grid of square cells on a plane, in its (u, v) basis.
struct PlaneGrid {
    u: Vec3,
    v: Vec3,
    lo: Vec2,
    cell: f64,
    nx: usize,
    ny: usize,
}

impl PlaneGrid {
    /// A dense grid over the inliers' extent (coarser if it would be huge), with a
    /// border of empty cells all round; `None` without finite inliers.
    fn over(points: &[Vec3], plane: &Plane, inliers: &[usize], cell: f64) -> Option<Self> {
        let (u, v) = plane_basis(plane.normal);
        let mut cell = cell.max(1e-4);
        let (mut lo, mut hi) = (Vec2::splat(f64::INFINITY), Vec2::splat(f64::NEG_INFINITY));
        for &i in inliers {
            let q = Vec2::new(points[i].dot(u), points[i].dot(v));
            lo = lo.min(q);
            hi = hi.max(q);
        }
        if lo.x.is_nan() || lo.x > hi.x {
            return None;
        }
        while ((hi - lo) / cell).element_product() > 4e6 {
            cell *= 2.0;
        }
        lo -= Vec2::splat(cell);
        hi += Vec2::splat(cell);
        let nx = ((hi.x - lo.x) / cell).floor() as usize + 1;
        let ny = ((hi.y - lo.y) / cell).floor() as usize + 1;
        Some(Self {
            u,
            v,
            lo,
            cell,
            nx,
            ny,
        })
    }

    fn to2(&self, q: Vec3) -> Vec2 {
        Vec2::new(q.dot(self.u), q.dot(self.v))
    }

    fn cell_of(&self, q: Vec2) -> Option<usize> {
        let inv = 1.0 / self.cell;
        // Truncation is floor for the non-negative values that pass the test.
        let (fx, fy) = ((q.x - self.lo.x) * inv, (q.y - self.lo.y) * inv);
        (fx >= 0.0 && fy >= 0.0 && (fx as usize) < self.nx && (fy as usize) < self.ny)
            .then(|| fy as usize * self.nx + fx as usize)
    }

    /// The cell at (x, y), if inside the grid.
    fn at(&self, x: isize, y: isize) -> Option<usize> {
        (x >= 0 && y >= 0 && (x as usize) < self.nx && (y as usize) < self.ny)
            .then(|| y as usize * self.nx + x as usize)
    }

    fn xy(&self, c: usize) -> (isize, isize) {
        ((c % self.nx) as isize, (c / self.nx) as isize)
    }
}

/// Every finite point on the plane with its cell; cells holding one marked `UNSET`
/// (others `EMPTY`); and per cell the points just below and just above the plane.
#[allow(clippy::type_complexity)]
fn mark(
    points: &[Vec3],
    plane: &Plane,
    grid: &PlaneGrid,
    threshold: f64,
) -> (Vec<u32>, Vec<(usize, usize)>, Vec<[u32; 2]>) {
    let cells = grid.nx * grid.ny;
    let mut comp = vec![EMPTY; cells];
    let mut on_plane: Vec<(usize, usize)> = Vec::new();
    let mut beside = vec![[0u32; 2]; cells];
    let (near, far) = (3.0 * threshold, 8.0 * threshold);
    for (i, q) in points.iter().enumerate() {
        let signed = plane.distance(*q);
        let off = signed.abs();
        let Some(c) = grid.cell_of(grid.to2(*q)) else {
            continue;
        };
        if off <= threshold {
            comp[c] = UNSET;
            on_plane.push((i, c));
        } else if off > near && off < far {
            beside[c][usize::from(signed > 0.0)] += 1;
        }
    }
    (comp, on_plane, beside)
}

/// Numbers the pieces of `UNSET` cells; how many there are. Connectivity comes from
/// every point on the plane, at full resolution (a far floor's rows are centimetres
/// apart, more so on a downsampled grid); two cells' reach bridges the rows a grazing
/// view leaves between its points.
fn label_pieces(comp: &mut [u32], grid: &PlaneGrid) -> u32 {
    let mut n_comp = 0u32;
    for start in 0..comp.len() {
        if comp[start] != UNSET {
            continue;
        }
        comp[start] = n_comp;
        let mut stack = vec![start];
        while let Some(c) = stack.pop() {
            let (cx, cy) = grid.xy(c);
            for dy in -2..=2 {
                for dx in -2..=2 {
                    if let Some(n) = grid.at(cx + dx, cy + dy)
                        && comp[n] == UNSET
                    {
                        comp[n] = n_comp;
                        stack.push(n);
                    }
                }
            }
        }
        n_comp += 1;
    }
    n_comp
}

/// Cells on a piece's border (only they can hold hull points), numbered in order; the
/// others `EMPTY`.
fn border_cells(comp: &[u32], grid: &PlaneGrid) -> (Vec<u32>, usize) {
    let mut n = 0usize;
    let index = (0..comp.len())
        .map(|c| {
            let (cx, cy) = grid.xy(c);
            let border = comp[c] < UNSET
                && (-1..=1).any(|dy| {
                    (-1..=1).any(|dx| grid.at(cx + dx, cy + dy).is_none_or(|n| comp[n] >= UNSET))
                });
            if border {
                n += 1;
                (n - 1) as u32
            } else {
                EMPTY
            }
        })
        .collect();
    (index, n)
}

/// Each piece's points, the cells holding points by piece, and each border cell's
/// extreme points in the eight directions (by the cell's border number: a grid over
/// a far, grazing plane has millions of cells and few on a border).
struct Gathered {
    members: Vec<Vec<usize>>,
    filled: Vec<u32>,
    border: Vec<u32>,
    extremes: Vec<[(f64, Vec2); 8]>,
}

fn gather(
    points: &[Vec3],
    grid: &PlaneGrid,
    (comp, n_comp): (&[u32], u32),
    on_plane: &[(usize, usize)],
) -> Gathered {
    let (border, n_border) = border_cells(comp, grid);
    let mut g = Gathered {
        members: vec![Vec::new(); n_comp as usize],
        filled: vec![EMPTY; comp.len()],
        border,
        extremes: vec![[(f64::NEG_INFINITY, Vec2::ZERO); 8]; n_border],
    };
    for &(i, c) in on_plane {
        let owner = comp[c];
        g.members[owner as usize].push(i);
        g.filled[c] = owner;
        let b = g.border[c];
        if b == EMPTY {
            continue;
        }
        let q2 = grid.to2(points[i]);
        let extremes = &mut g.extremes[b as usize];
        for (k, d) in DIRS.iter().enumerate() {
            let s = q2.x * d.0 + q2.y * d.1;
            if s > extremes[k].0 {
                extremes[k] = (s, q2);
            }
        }
    }
    g
}

/// A far surface seen at a grazing angle has rows of points more than a cell apart:
/// an empty cell between two cells of one piece (across, along or diagonally) is that
/// piece's, so its area and its room inside are not those of a comb.
fn bridge_rows(filled: &[u32], grid: &PlaneGrid) -> Vec<u32> {
    (0..filled.len())
        .map(|c| {
            if filled[c] < UNSET {
                return filled[c];
            }
            let (cx, cy) = grid.xy(c);
            let at = |x: isize, y: isize| grid.at(x, y).map_or(EMPTY, |n| filled[n]);
            [(1, 0), (0, 1), (1, 1), (1, -1)]
                .iter()
                .map(|&(dx, dy)| (at(cx - dx, cy - dy), at(cx + dx, cy + dy)))
                .find(|&(a, b)| a == b && a < UNSET)
                .map_or(EMPTY, |(a, _)| a)
        })
        .collect()
}

/// Splits the points on a plane into connected pieces (grid cells) and keeps those
/// with enough area. The (possibly downsampled) inliers only bound the grid;
/// connectivity, membership and outline come from every finite point on the plane.
/// Each cell remembers its extreme points in eight directions, so hulls come from a
/// few points per cell.
pub(crate) fn split(
    points: &[Vec3],
    plane: &Plane,
    inliers: &[usize],
    p: &SurfaceParams,
) -> Vec<Surface> {
    let Some(grid) = PlaneGrid::over(points, plane, inliers, p.cell) else {
        return Vec::new();
    };
    let (mut comp, on_plane, beside) = mark(points, plane, &grid, p.ransac.threshold);
    let n_comp = label_pieces(&mut comp, &grid);
    let gathered = gather(points, &grid, (&comp, n_comp), &on_plane);
    let filled = bridge_rows(&gathered.filled, &grid);
    // How far each cell is from the nearest empty one: thin pieces (the slice of a
    // drum's side within the threshold of a table's plane) have no room inside.
    let room = (p.min_inscribed_radius > 0.0).then(|| {
        let empty: Vec<bool> = filled.iter().map(|&c| c >= UNSET).collect();
        tabula_geom::raster::distance_transform(&empty, grid.nx, grid.ny)
    });
    let mut cells_of: Vec<Vec<usize>> = vec![Vec::new(); n_comp as usize];
    for (c, &k) in filled.iter().enumerate() {
        if k < UNSET {
            cells_of[k as usize].push(c);
        }
    }
    let cell = grid.cell;
    let mut out = Vec::new();
    for (cells, idx) in cells_of.into_iter().zip(gathered.members) {
        let area = cells.len() as f64 * cell * cell;
        let core = room.as_ref().map_or(f64::INFINITY, |room| {
            cells.iter().map(|&c| room[c]).fold(0.0, f64::max).sqrt() * cell
        });
        // Only cells with points on both sides: what stands on a surface is above it.
        let sliced: u32 = cells
            .iter()
            .map(|&c| 2 * beside[c][0].min(beside[c][1]))
            .sum();
        if area < p.min_area
            || idx.len() < 3
            || core < p.min_inscribed_radius
            || sliced as f64 > p.max_slice_ratio * idx.len() as f64
        {
            continue;
        }
        let candidates: Vec<Vec2> = cells
            .iter()
            .filter(|&&c| gathered.border[c] != EMPTY)
            .flat_map(|&c| gathered.extremes[gathered.border[c] as usize].iter())
            .filter(|e| e.0.is_finite())
            .map(|e| e.1)
            .collect();
        out.push(surface(points, plane, &grid, (candidates, idx, area), p));
    }
    out.sort_by_key(|s| std::cmp::Reverse(s.inliers.len()));
    out
}

/// A kept piece as a surface: its hull from its cells' extreme points, its centroid.
fn surface(
    points: &[Vec3],
    plane: &Plane,
    grid: &PlaneGrid,
    (candidates, idx, area): (Vec<Vec2>, Vec<usize>, f64),
    p: &SurfaceParams,
) -> Surface {
    let hull2: Vec<Vec2> = convex_hull_2d(&candidates)
        .into_iter()
        .map(|i| candidates[i])
        .collect();
    let centroid = idx.iter().map(|&i| points[i]).sum::<Vec3>() / idx.len() as f64;
    let lift = |q: Vec2| grid.u * q.x + grid.v * q.y - plane.normal * plane.d;
    Surface {
        plane: *plane,
        hull_area: polygon_area(&hull2),
        hull: hull2.iter().map(|&q| lift(q)).collect(),
        inliers: idx,
        area,
        centroid,
        threshold: p.ransac.threshold,
    }
}
