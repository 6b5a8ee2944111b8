//! Free space on a surface (seed 000's biggest failure, SPEC §1.3: total area says
//! nothing about free space). A 2D occupancy grid in the surface's plane marks what is
//! seen free, what objects cover (their whole footprint, also the hidden part), what
//! nobody saw (shadows behind objects), and what is off the surface; a Euclidean
//! distance transform then answers "where does this footprint fit with this margin,
//! nearest to that point?" in one scan.

mod build;

use tabula_geom::input::{Validate, check_count, check_positive};
use tabula_geom::polygon::{convex_hull_2d, distance_to_boundary, inside_polygon};
pub use tabula_geom::raster::distance_transform;
use tabula_geom::{Pose, Quat, Vec2, Vec3};

/// Parameters.
#[derive(Debug, Clone, serde::Deserialize, serde::Serialize)]
#[serde(default, deny_unknown_fields)]
pub struct FreeSpaceParams {
    /// Cell size (m).
    pub resolution: f64,
    /// Orientations tried for a footprint over a full turn.
    pub yaw_samples: usize,
    /// Cells inside the surface's hull where the camera saw nothing (occluded) count
    /// as free. Off by default: an unseen patch may hold an unseen object.
    pub unknown_is_free: bool,
}

impl Default for FreeSpaceParams {
    fn default() -> Self {
        Self {
            resolution: 0.01,
            yaw_samples: 16,
            unknown_is_free: false,
        }
    }
}

/// One grid cell.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Cell {
    /// Not on the surface.
    Outside,
    /// On the surface, seen, nothing on it.
    Free,
    /// Under an object.
    Occupied,
    /// On the surface (inside its hull) but not seen.
    Unknown,
}

/// A place for a footprint.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Placement {
    /// Where the footprint's origin goes, on the surface (world frame).
    pub position: Vec3,
    /// Rotation of the footprint about the surface normal, relative to the map's `u`.
    pub yaw: f64,
    /// Pose of the footprint frame (x, y in the surface, z along its normal).
    pub world_from_footprint: Pose,
    /// Distance from the footprint's centre to the nearest obstacle or edge (m).
    pub clearance: f64,
}

/// Why a map cannot be built.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum FreeSpaceError {
    #[error("resolution must be positive and finite")]
    BadResolution,
    #[error("the surface has no area")]
    EmptySurface,
    #[error("a {0} × {1} grid is too large; use a coarser resolution")]
    TooLarge(usize, usize),
}

/// The occupancy map of one surface.
#[derive(Debug, Clone)]
pub struct FreeSpaceMap {
    pub normal: Vec3,
    /// In-plane axes: a cell (i, j) has its centre at `origin + u·(lo.x + (i + ½)·res) + …`.
    pub u: Vec3,
    pub v: Vec3,
    /// The plane's offset along the normal (`normal · p = offset` on the plane).
    pub offset: f64,
    pub resolution: f64,
    pub lo: Vec2,
    pub nx: usize,
    pub ny: usize,
    pub cells: Vec<Cell>,
    /// Distance (m) from each cell centre to the nearest cell that is not free.
    pub clearance: Vec<f64>,
    yaw_samples: usize,
}

impl FreeSpaceMap {
    /// The map of a tabletop result's table, with its objects on it.
    pub fn from_tabletop(
        tabletop: &crate::tabletop::Tabletop,
        points: &[Vec3],
        p: &FreeSpaceParams,
    ) -> Result<Self, FreeSpaceError> {
        let objects: Vec<Vec<Vec3>> = tabletop
            .objects
            .iter()
            .chain(&tabletop.partial)
            .map(|o| {
                o.indices
                    .iter()
                    .filter_map(|&i| points.get(i).copied())
                    .collect()
            })
            .collect();
        Self::build(&tabletop.table, points, &objects, p)
    }

    /// Centre of cell `k` in the plane's 2D frame.
    pub fn cell_centre(&self, k: usize) -> Vec2 {
        self.lo
            + Vec2::new(
                ((k % self.nx) as f64 + 0.5) * self.resolution,
                ((k / self.nx) as f64 + 0.5) * self.resolution,
            )
    }

    /// A 2D plane point back in the world.
    pub fn to_world(&self, q: Vec2) -> Vec3 {
        self.u * q.x + self.v * q.y + self.normal * self.offset
    }

    /// A world point in the plane's 2D frame.
    pub fn to_plane(&self, p: Vec3) -> Vec2 {
        Vec2::new(p.dot(self.u), p.dot(self.v))
    }

    /// Area of free cells (m²).
    pub fn free_area(&self) -> f64 {
        self.cells.iter().filter(|c| **c == Cell::Free).count() as f64
            * self.resolution
            * self.resolution
    }

    /// The footprint's convex outline and, per sampled orientation, the cells it
    /// covers around its origin; `None` for a footprint that fits nowhere.
    fn footprint_masks(&self, footprint: &[Vec2], margin: f64) -> Option<FootprintMasks> {
        if footprint.len() < 3
            || !footprint.iter().all(|q| q.is_finite())
            || margin.is_nan()
            || margin < 0.0
        {
            return None;
        }
        let h: Vec<Vec2> = convex_hull_2d(footprint)
            .into_iter()
            .map(|k| footprint[k])
            .collect();
        if h.len() < 3 {
            return None;
        }
        let res = self.resolution;
        // Cell centres are up to half a diagonal from the true boundary of a cell.
        let slack = res * std::f64::consts::FRAC_1_SQRT_2;
        let reach = h.iter().map(|q| q.length()).fold(0.0, f64::max);
        // A footprint wider than the whole map fits nowhere (and would cost a huge mask).
        if reach > (self.nx.max(self.ny) as f64) * res {
            return None;
        }
        let r = (reach / res).ceil() as isize + 1;
        // Cells each orientation covers (centres inside the footprint or within a
        // half-diagonal of its outline).
        let shapes = (0..self.yaw_samples)
            .map(|k| {
                let yaw = std::f64::consts::TAU * k as f64 / self.yaw_samples as f64;
                let rot: Vec<Vec2> = h.iter().map(|q| Vec2::from_angle(yaw).rotate(*q)).collect();
                let mut cover: Vec<CoveredCell> = (-r..=r)
                    .flat_map(|dj| (-r..=r).map(move |di| (di, dj)))
                    .filter_map(|(di, dj)| {
                        let c = Vec2::new(di as f64 * res, dj as f64 * res);
                        (inside_polygon(&rot, c) || distance_to_boundary(&rot, c) <= slack)
                            .then_some((di, dj, c.length()))
                    })
                    .collect();
                // Outermost first: those are the cells that meet an obstacle first.
                cover.sort_by(|a, b| b.2.total_cmp(&a.2).then((a.0, a.1).cmp(&(b.0, b.1))));
                (yaw, cover)
            })
            .collect();
        Some(FootprintMasks {
            shapes,
            reach,
            need: margin + slack,
        })
    }

    /// The orientations (yaws) at which the footprint fits with its origin on cell `k`.
    fn yaws_at(&self, k: usize, m: &FootprintMasks) -> Vec<f64> {
        if self.cells[k] != Cell::Free || self.clearance[k] < m.need {
            return Vec::new();
        }
        let (i, j) = ((k % self.nx) as isize, (k / self.nx) as isize);
        // Far from everything: every orientation fits.
        if self.clearance[k] >= m.reach + m.need {
            return m.shapes.iter().map(|(yaw, _)| *yaw).collect();
        }
        // A cell nearer than this to the centre is clear enough by the triangle
        // inequality (the clearance is a Euclidean distance): only its bounds matter.
        let sure = self.clearance[k] - m.need - 1e-9;
        m.shapes
            .iter()
            .filter(|(_, cover)| {
                cover.iter().all(|&(di, dj, d)| {
                    let (a, b) = (i + di, j + dj);
                    a >= 0
                        && b >= 0
                        && (a as usize) < self.nx
                        && (b as usize) < self.ny
                        && (d < sure || self.clearance[b as usize * self.nx + a as usize] >= m.need)
                })
            })
            .map(|(yaw, _)| *yaw)
            .collect()
    }

    fn placement(&self, k: usize, yaw: f64) -> Placement {
        let position = self.to_world(self.cell_centre(k));
        let x = self.u * yaw.cos() + self.v * yaw.sin();
        let y = self.normal.cross(x);
        let rotation = Quat::from_mat3(&tabula_geom::Mat3::from_cols(x, y, self.normal));
        Placement {
            position,
            yaw,
            world_from_footprint: Pose::from_parts(position, rotation),
            clearance: self.clearance[k],
        }
    }

    /// The place nearest to `near` (projected onto the surface) where `footprint` (a
    /// polygon in its own frame, metres, origin = the point that is placed) fits with
    /// at least `margin` to every object, unseen patch and edge; `None` if it fits
    /// nowhere. Orientations are tried in `yaw_samples` steps.
    pub fn find_place(&self, footprint: &[Vec2], margin: f64, near: Vec3) -> Option<Placement> {
        if !near.is_finite() {
            return None;
        }
        let masks = self.footprint_masks(footprint, margin)?;
        let target = self.to_plane(near);
        let mut order: Vec<(f64, usize)> = (0..self.cells.len())
            .filter(|&k| self.cells[k] == Cell::Free)
            .map(|k| (self.cell_centre(k).distance_squared(target), k))
            .collect();
        order.sort_by(|a, b| a.0.total_cmp(&b.0).then(a.1.cmp(&b.1)));
        order.into_iter().find_map(|(_, k)| {
            self.yaws_at(k, &masks)
                .first()
                .map(|&yaw| self.placement(k, yaw))
        })
    }

    /// Every place where `footprint` fits with `margin` (as [`Self::find_place`]),
    /// roomiest first, one per orientation that fits, on cells at least `spacing` apart
    /// (m), from at most `max_spots` cells: the candidates a placement chooses among by
    /// what the arm reaches.
    pub fn places(
        &self,
        footprint: &[Vec2],
        margin: f64,
        max_spots: usize,
        spacing: f64,
    ) -> Vec<Placement> {
        let Some(masks) = self.footprint_masks(footprint, margin) else {
            return Vec::new();
        };
        let mut order: Vec<usize> = (0..self.cells.len())
            .filter(|&k| self.cells[k] == Cell::Free && self.clearance[k] >= masks.need)
            .collect();
        order.sort_by(|&a, &b| {
            self.clearance[b]
                .total_cmp(&self.clearance[a])
                .then(a.cmp(&b))
        });
        // Cells within `spacing` of a spot already taken (cell centres lie on the grid,
        // so the disc of cells is exact).
        let mut near_taken = vec![false; self.cells.len()];
        let reach = (spacing / self.resolution).ceil() as isize;
        let mut taken = 0usize;
        let mut out = Vec::new();
        for k in order {
            if taken >= max_spots {
                break;
            }
            if near_taken[k] {
                continue;
            }
            let yaws = self.yaws_at(k, &masks);
            if yaws.is_empty() {
                continue;
            }
            taken += 1;
            let (i, j) = ((k % self.nx) as isize, (k / self.nx) as isize);
            for dj in -reach..=reach {
                for di in -reach..=reach {
                    let (a, b) = (i + di, j + dj);
                    let d = Vec2::new(di as f64, dj as f64) * self.resolution;
                    if a >= 0
                        && b >= 0
                        && (a as usize) < self.nx
                        && (b as usize) < self.ny
                        && d.length() < spacing
                    {
                        near_taken[b as usize * self.nx + a as usize] = true;
                    }
                }
            }
            out.extend(yaws.into_iter().map(|yaw| self.placement(k, yaw)));
        }
        out
    }
}

/// A cell a footprint covers: its offset from the centre cell (cells) and its distance
/// from the centre (m).
type CoveredCell = (isize, isize, f64);

/// A footprint prepared for fitting: per orientation, the cells it covers.
struct FootprintMasks {
    /// Per yaw, the cells it covers, farthest from the centre first.
    shapes: Vec<(f64, Vec<CoveredCell>)>,
    /// Farthest outline point from the origin (m).
    reach: f64,
    /// Clearance every covered cell needs (m).
    need: f64,
}

impl Validate for FreeSpaceParams {
    fn check(&self, at: &str) -> Result<(), String> {
        check_positive(at, "resolution", self.resolution)?;
        check_count(at, "yaw_samples", self.yaw_samples, 1)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::plane::Plane;
    use crate::surfaces::{Surface, plane_basis};
    use proptest::prelude::*;

    fn square_table(size: f64) -> (Surface, Vec<Vec3>) {
        let n = (size / 0.005) as usize;
        let points: Vec<Vec3> = (0..n * n)
            .map(|k| Vec3::new((k % n) as f64 * 0.005, (k / n) as f64 * 0.005, 0.7))
            .collect();
        let hull = vec![
            Vec3::new(0.0, 0.0, 0.7),
            Vec3::new(size, 0.0, 0.7),
            Vec3::new(size, size, 0.7),
            Vec3::new(0.0, size, 0.7),
        ];
        let surface = Surface {
            plane: Plane {
                normal: Vec3::Z,
                d: -0.7,
            },
            inliers: (0..points.len()).collect(),
            hull,
            area: size * size,
            hull_area: size * size,
            centroid: Vec3::new(size / 2.0, size / 2.0, 0.7),
            threshold: 0.01,
        };
        (surface, points)
    }

    fn rect(w: f64, h: f64) -> Vec<Vec2> {
        vec![
            Vec2::new(-w / 2.0, -h / 2.0),
            Vec2::new(w / 2.0, -h / 2.0),
            Vec2::new(w / 2.0, h / 2.0),
            Vec2::new(-w / 2.0, h / 2.0),
        ]
    }

    #[test]
    fn brute_force_distance_transform_agrees() {
        let (nx, ny) = (13, 9);
        let blocked: Vec<bool> = (0..nx * ny).map(|k| (k * 7) % 11 == 0).collect();
        let d = distance_transform(&blocked, nx, ny);
        for (k, dk) in d.iter().enumerate() {
            let (x, y) = ((k % nx) as f64, (k / nx) as f64);
            let best = (0..nx * ny)
                .filter(|&b| blocked[b])
                .map(|b| ((b % nx) as f64 - x).powi(2) + ((b / nx) as f64 - y).powi(2))
                .fold(f64::INFINITY, f64::min);
            assert_eq!(*dk, best, "cell {k}");
        }
    }

    #[test]
    fn places_agree_with_checking_every_covered_cell_and_every_spot_taken() {
        let (surface, points) = square_table(0.6);
        let blob = |x0: f64, y0: f64, n: usize| -> Vec<Vec3> {
            (0..n * n)
                .map(|k| Vec3::new(x0 + (k % n) as f64 * 0.01, y0 + (k / n) as f64 * 0.01, 0.75))
                .collect()
        };
        let objects = vec![blob(0.1, 0.1, 8), blob(0.35, 0.2, 5), blob(0.2, 0.42, 12)];
        let map =
            FreeSpaceMap::build(&surface, &points, &objects, &FreeSpaceParams::default()).unwrap();
        let footprint = rect(0.09, 0.05);
        let (margin, spacing) = (0.015, 0.04);
        let m = map.footprint_masks(&footprint, margin).unwrap();
        // Every covered cell looked up, no shortcut; spots spaced by a list of those taken.
        let fits = |k: usize, cover: &[CoveredCell]| {
            let (i, j) = ((k % map.nx) as isize, (k / map.nx) as isize);
            cover.iter().all(|&(di, dj, _)| {
                let (a, b) = (i + di, j + dj);
                a >= 0
                    && b >= 0
                    && (a as usize) < map.nx
                    && (b as usize) < map.ny
                    && map.clearance[b as usize * map.nx + a as usize] >= m.need
            })
        };
        let mut order: Vec<usize> = (0..map.cells.len())
            .filter(|&k| map.cells[k] == Cell::Free && map.clearance[k] >= m.need)
            .collect();
        order.sort_by(|&a, &b| {
            map.clearance[b]
                .total_cmp(&map.clearance[a])
                .then(a.cmp(&b))
        });
        let mut taken: Vec<usize> = Vec::new();
        let mut want = Vec::new();
        for k in order {
            let (i, j) = ((k % map.nx) as f64, (k / map.nx) as f64);
            let near = taken.iter().any(|&t| {
                let d = Vec2::new((t % map.nx) as f64 - i, (t / map.nx) as f64 - j);
                (d * map.resolution).length() < spacing
            });
            let yaws: Vec<f64> = m
                .shapes
                .iter()
                .filter(|(_, cover)| fits(k, cover))
                .map(|(yaw, _)| *yaw)
                .collect();
            if near || yaws.is_empty() || taken.len() >= 400 {
                continue;
            }
            taken.push(k);
            want.extend(yaws.into_iter().map(|yaw| (k, yaw)));
        }
        let got: Vec<(Vec3, f64)> = map
            .places(&footprint, margin, 400, spacing)
            .into_iter()
            .map(|p| (p.position, p.yaw))
            .collect();
        assert!(want.len() > 20, "{}", want.len());
        assert_eq!(got.len(), want.len());
        for ((position, yaw), (k, want_yaw)) in got.iter().zip(&want) {
            assert!(position.distance(map.to_world(map.cell_centre(*k))) < 1e-12);
            assert_eq!(yaw, want_yaw);
        }
    }

    #[test]
    fn sparse_points_fill_in_but_the_seen_edge_stays_where_they_end() {
        // Points every 2.5 cm (sparser than the 1 cm cells) over x ≤ 0.4 of a 0.6 m
        // hull: the gaps between them are free, nothing beyond x = 0.4 + a cell is.
        let (mut surface, _) = square_table(0.6);
        let points: Vec<Vec3> = (0..=16)
            .flat_map(|i| (0..=24).map(move |j| Vec3::new(i as f64 * 0.025, j as f64 * 0.025, 0.7)))
            .collect();
        surface.inliers = (0..points.len()).collect();
        let p = FreeSpaceParams {
            resolution: 0.01,
            ..FreeSpaceParams::default()
        };
        let map = FreeSpaceMap::build(&surface, &points, &[], &p).unwrap();
        let (u, v) = plane_basis(Vec3::Z);
        let at = |x: f64, y: f64| {
            let q = Vec2::new(Vec3::new(x, y, 0.7).dot(u), Vec3::new(x, y, 0.7).dot(v));
            let c = ((q - map.lo) / map.resolution).floor();
            map.cells[c.y as usize * map.nx + c.x as usize]
        };
        for x in [0.012, 0.2, 0.312, 0.388] {
            for y in [0.012, 0.3, 0.562] {
                assert_eq!(at(x, y), Cell::Free, "({x}, {y}) between seen points");
            }
        }
        for x in [0.415, 0.45, 0.55] {
            assert_eq!(at(x, 0.3), Cell::Unknown, "x = {x} is past the seen edge");
        }
    }

    #[test]
    fn a_box_goes_next_to_the_clutter_not_on_it() {
        let (surface, points) = square_table(0.6);
        // An object covering the middle of the table.
        let object: Vec<Vec3> = (0..400)
            .map(|k| {
                Vec3::new(
                    0.2 + (k % 20) as f64 * 0.01,
                    0.2 + (k / 20) as f64 * 0.01,
                    0.75,
                )
            })
            .collect();
        let map =
            FreeSpaceMap::build(&surface, &points, &[object], &FreeSpaceParams::default()).unwrap();
        assert!(map.free_area() < 0.36 - 0.03 && map.free_area() > 0.25);
        let fp = rect(0.1, 0.06);
        let place = map.find_place(&fp, 0.02, Vec3::new(0.3, 0.3, 0.7)).unwrap();
        let q = place.position;
        // Outside the object's square grown by the footprint's half size and margin.
        let gap = (q.x - 0.295).abs().max((q.y - 0.295).abs());
        assert!(gap >= 0.095 + 0.03 + 0.02 - 0.015, "{place:?}");
        // Inside the table by at least half the short side and the margin.
        assert!(
            q.x >= 0.05 && q.x <= 0.55 && q.y >= 0.05 && q.y <= 0.55,
            "{place:?}"
        );
        assert!((q.z - 0.7).abs() < 1e-9);
        // Nothing fits when the margin is as large as the table, or the box is larger.
        assert!(
            map.find_place(&rect(50.0, 50.0), 0.0, Vec3::new(0.3, 0.3, 0.7))
                .is_none()
        );
        assert!(map.find_place(&fp, 0.3, Vec3::new(0.3, 0.3, 0.7)).is_none());
        // Bad footprints are no answer, not a panic.
        assert!(map.find_place(&[], 0.0, Vec3::ZERO).is_none());
        assert!(
            map.find_place(&rect(0.1, f64::NAN), 0.0, Vec3::ZERO)
                .is_none()
        );
    }

    #[test]
    fn long_footprints_turn_to_fit_a_corridor() {
        let (surface, points) = square_table(0.6);
        // Two walls of objects leaving a corridor 8 cm wide along y at x = 0.3.
        let wall = |x0: f64| -> Vec<Vec3> {
            (0..60 * 25)
                .map(|k| Vec3::new(x0 + (k % 25) as f64 * 0.01, (k / 25) as f64 * 0.01, 0.72))
                .collect()
        };
        let objects = vec![wall(0.0), wall(0.35)];
        let map =
            FreeSpaceMap::build(&surface, &points, &objects, &FreeSpaceParams::default()).unwrap();
        // 20 cm long, 4 cm wide: fits only along the corridor (yaw ≈ ±90°).
        let place = map
            .find_place(&rect(0.2, 0.04), 0.0, Vec3::new(0.3, 0.3, 0.7))
            .unwrap();
        let axis = map.u * place.yaw.cos() + map.v * place.yaw.sin();
        assert!(axis.y.abs() > 0.9, "{place:?}");
    }

    proptest! {
        #![proptest_config(ProptestConfig::with_cases(48))]

        /// Wherever a footprint is placed, no object point is closer to it than the
        /// margin (less the grid's half-diagonal), and it lies on the table.
        #[test]
        fn placements_keep_their_margin(
            blobs in prop::collection::vec((0.05..0.55f64, 0.05..0.55f64, 0.01..0.06f64), 0..8),
            size in (0.02..0.2f64, 0.02..0.12f64),
            margin in 0.0..0.04f64,
            near in (0.0..0.6f64, 0.0..0.6f64),
        ) {
            let (surface, points) = square_table(0.6);
            let objects: Vec<Vec<Vec3>> = blobs
                .iter()
                .map(|&(x, y, r)| {
                    (0..64)
                        .map(|k| {
                            let a = k as f64 * 0.7;
                            let d = r * ((k % 8) as f64 / 7.0);
                            Vec3::new(x + d * a.cos(), y + d * a.sin(), 0.75)
                        })
                        .collect()
                })
                .collect();
            let map = FreeSpaceMap::build(&surface, &points, &objects, &FreeSpaceParams::default()).unwrap();
            let fp = rect(size.0, size.1);
            if let Some(place) = map.find_place(&fp, margin, Vec3::new(near.0, near.1, 0.7)) {
                let corners: Vec<Vec2> = fp
                    .iter()
                    .map(|c| {
                        let w = place.world_from_footprint * Vec3::new(c.x, c.y, 0.0);
                        Vec2::new(w.x, w.y)
                    })
                    .collect();
                let slack = map.resolution * std::f64::consts::SQRT_2;
                for o in objects.iter().flatten() {
                    let q = Vec2::new(o.x, o.y);
                    let d = if inside_polygon(&corners, q) { 0.0 } else { distance_to_boundary(&corners, q) };
                    prop_assert!(d >= margin - slack, "object point {q:?} {d} from the footprint");
                }
                for c in &corners {
                    prop_assert!(c.x >= -slack && c.y >= -slack && c.x <= 0.6 + slack && c.y <= 0.6 + slack, "{c:?} off the table");
                }
            }
        }
    }
}
