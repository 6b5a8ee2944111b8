//! Building a surface's occupancy map: the grid over its outline, the cells its points
//! show, the cells its objects cover, and every free cell's clearance.

use super::{Cell, FreeSpaceError, FreeSpaceMap, FreeSpaceParams};
use crate::surfaces::{Surface, plane_basis};
use tabula_geom::polygon::{convex_hull_2d, distance_to_boundary, inside_convex, polygon_area};
use tabula_geom::raster::distance_transform;
use tabula_geom::{Vec2, Vec3};

/// A cell's eight neighbours, as offsets.
const AROUND: [(isize, isize); 8] = [
    (-1, -1),
    (0, -1),
    (1, -1),
    (-1, 0),
    (1, 0),
    (-1, 1),
    (0, 1),
    (1, 1),
];

impl FreeSpaceMap {
    /// Builds the map of `surface` from the cloud it was found in and the objects on it
    /// (each as its points; their projections and convex footprints are occupied).
    pub fn build(
        surface: &Surface,
        points: &[Vec3],
        objects: &[Vec<Vec3>],
        p: &FreeSpaceParams,
    ) -> Result<Self, FreeSpaceError> {
        if !(p.resolution.is_finite() && p.resolution > 0.0) {
            return Err(FreeSpaceError::BadResolution);
        }
        let normal = surface.plane.normal;
        let (u, v) = plane_basis(normal);
        let to2 = |q: Vec3| Vec2::new(q.dot(u), q.dot(v));
        let mut hull: Vec<Vec2> = surface.hull.iter().map(|&q| to2(q)).collect();
        if hull.len() < 3 || polygon_area(&hull).abs() < 1e-9 {
            return Err(FreeSpaceError::EmptySurface);
        }
        if polygon_area(&hull) < 0.0 {
            hull.reverse();
        }
        let res = p.resolution;
        let (mut lo, mut hi) = (Vec2::splat(f64::INFINITY), Vec2::splat(f64::NEG_INFINITY));
        for q in &hull {
            lo = lo.min(*q);
            hi = hi.max(*q);
        }
        // One cell of border so the edge is always an obstacle.
        lo -= Vec2::splat(res);
        hi += Vec2::splat(res);
        let nx = ((hi.x - lo.x) / res).ceil() as usize;
        let ny = ((hi.y - lo.y) / res).ceil() as usize;
        if nx.saturating_mul(ny) > 16_000_000 {
            return Err(FreeSpaceError::TooLarge(nx, ny));
        }
        let mut map = Self {
            normal,
            u,
            v,
            offset: -surface.plane.d,
            resolution: res,
            lo,
            nx,
            ny,
            cells: Vec::new(),
            clearance: Vec::new(),
            yaw_samples: p.yaw_samples.max(1),
        };
        map.cells = (0..nx * ny)
            .map(|k| match inside_convex(&hull, map.cell_centre(k)) {
                true => Cell::Unknown,
                false => Cell::Outside,
            })
            .collect();
        let seen = map.seen(surface, points);
        for (cell, seen) in map.cells.iter_mut().zip(seen) {
            if *cell == Cell::Unknown && (seen || p.unknown_is_free) {
                *cell = Cell::Free;
            }
        }
        for object in objects {
            map.occupy(object, hi);
        }
        let blocked: Vec<bool> = map.cells.iter().map(|c| *c != Cell::Free).collect();
        map.clearance = distance_transform(&blocked, nx, ny)
            .into_iter()
            .map(|d2| d2.sqrt() * res)
            .collect();
        Ok(map)
    }

    /// The cell holding plane point `q`, if on the grid.
    fn cell_at(&self, q: Vec2) -> Option<usize> {
        let c = ((q - self.lo) / self.resolution).floor();
        (c.x >= 0.0 && c.y >= 0.0 && (c.x as usize) < self.nx && (c.y as usize) < self.ny)
            .then(|| c.y as usize * self.nx + c.x as usize)
    }

    /// Cell `c`'s eight neighbours (`None` off the grid).
    fn neighbours(&self, c: usize) -> impl Iterator<Item = Option<usize>> + '_ {
        let (nx, ny) = (self.nx, self.ny);
        let (i, j) = ((c % nx) as isize, (c / nx) as isize);
        AROUND.iter().map(move |(di, dj)| {
            let (a, b) = (i + di, j + dj);
            (a >= 0 && b >= 0 && (a as usize) < nx && (b as usize) < ny)
                .then(|| b as usize * nx + a as usize)
        })
    }

    /// The seen surface: the cells of the inliers, closed (grown by a cell, then shrunk
    /// by one): points are sparser than cells far from the camera, and the gaps between
    /// them fill in, but the surface's edge stays where its points end — growing alone
    /// moved every edge a cell outward, and spots near it over the edge.
    fn seen(&self, surface: &Surface, points: &[Vec3]) -> Vec<bool> {
        let cells = self.nx * self.ny;
        let mut seen = vec![false; cells];
        for &i in &surface.inliers {
            if let Some(q) = points.get(i)
                && let Some(c) = self.cell_at(self.to_plane(*q))
            {
                seen[c] = true;
            }
        }
        let mut dilated = seen.clone();
        for c in (0..cells).filter(|&c| seen[c]) {
            for k in self.neighbours(c).flatten() {
                dilated[k] = true;
            }
        }
        (0..cells)
            .map(|c| {
                seen[c] || (dilated[c] && self.neighbours(c).all(|k| k.is_some_and(|k| dilated[k])))
            })
            .collect()
    }

    /// Marks an object's cells occupied: its convex footprint, plus every projected
    /// point (`hi`: the grid's upper corner).
    fn occupy(&mut self, object: &[Vec3], hi: Vec2) {
        let (nx, res) = (self.nx, self.resolution);
        let flat: Vec<Vec2> = object
            .iter()
            .filter(|q| q.is_finite())
            .map(|&q| self.to_plane(q))
            .collect();
        let h: Vec<Vec2> = convex_hull_2d(&flat).into_iter().map(|k| flat[k]).collect();
        for q in &flat {
            if let Some(c) = self.cell_at(*q) {
                self.cells[c] = Cell::Occupied;
            }
        }
        if h.len() < 3 {
            return;
        }
        let (mut a, mut b) = (Vec2::splat(f64::INFINITY), Vec2::splat(f64::NEG_INFINITY));
        for q in &h {
            a = a.min(*q);
            b = b.max(*q);
        }
        let (Some(c0), Some(c1)) = (
            self.cell_at(a.max(self.lo)),
            self.cell_at(b.min(hi - Vec2::splat(1e-9))),
        ) else {
            return;
        };
        for j in c0 / nx..=c1 / nx {
            for i in c0 % nx..=c1 % nx {
                let k = j * nx + i;
                let centre = self.cell_centre(k);
                if inside_convex(&h, centre) || distance_to_boundary(&h, centre) < res * 0.5 {
                    self.cells[k] = Cell::Occupied;
                }
            }
        }
    }
}
