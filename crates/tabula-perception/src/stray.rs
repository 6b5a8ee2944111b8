//! Stray returns of a depth frame: single pixels whose range is nowhere near their
//! neighbours'.
//!
//! A depth camera's random returns (multipath, sunlight, a speckle misread) land
//! anywhere along their ray, so each is a lone point floating in front of or behind
//! the surface its neighbours see. Accumulated over a sweep they become voxels in the
//! air that block a base's path or a placement. A surface's points lie within the
//! range noise of their neighbours', which grows with the square of the range, so the
//! test is scaled with it — a fixed radius (PCL's `RadiusOutlierRemoval`) either keeps
//! the strays near the camera or eats a far wall.

use rayon::prelude::*;
use tabula_geom::input::{Validate, check_count, check_non_negative, check_positive};
use tabula_geom::{PointCloud, Vec3};

/// Parameters of [`stray_returns`].
#[derive(Debug, Clone, PartialEq, serde::Deserialize, serde::Serialize)]
#[serde(default, deny_unknown_fields)]
pub struct StrayParams {
    /// A neighbour this close always counts (m): the pixel spacing near the camera.
    pub radius: f64,
    /// The range noise's σ per square metre of range (1/m): a Kinect's 1.5 mm·z²
    /// (Khoshelham & Elberink 2012; SPEC's "Kinect-like noise").
    pub depth_noise: f64,
    /// A neighbour within `radius` plus this many σ of the range noise counts.
    pub sigmas: f64,
    /// A point with fewer such neighbours among its 8 pixels is a stray.
    pub min_neighbors: usize,
}

impl Default for StrayParams {
    fn default() -> Self {
        Self {
            radius: 0.01,
            depth_noise: 0.0015,
            sigmas: 4.0,
            min_neighbors: 1,
        }
    }
}

impl Validate for StrayParams {
    fn check(&self, at: &str) -> Result<(), String> {
        check_positive(at, "radius", self.radius)?;
        check_non_negative(at, "depth_noise", self.depth_noise)?;
        check_non_negative(at, "sigmas", self.sigmas)?;
        check_count(at, "min_neighbors", self.min_neighbors, 0)?;
        if self.min_neighbors > 8 {
            return Err(format!(
                "{at}min_neighbors: at most 8 (a pixel's neighbours)"
            ));
        }
        Ok(())
    }
}

/// Which points of an organized cloud (camera frame: the range is a point's distance
/// from the origin) are stray returns (`true`): fewer than `min_neighbors` of its 8
/// pixels see a point within reach (a lone valid pixel among holes is one, as a
/// flying pixel is). An unorganized cloud has no pixel neighbours to compare with:
/// none is marked.
pub fn stray_returns(cloud: &PointCloud, p: &StrayParams) -> Vec<bool> {
    let pts = &cloud.points;
    if !cloud.is_organized() || p.min_neighbors == 0 {
        return vec![false; pts.len()];
    }
    let (w, h) = (cloud.width, cloud.height);
    let mut stray = vec![false; pts.len()];
    stray.par_chunks_mut(w).enumerate().for_each(|(y, row)| {
        for (x, out) in row.iter_mut().enumerate() {
            let c = pts[y * w + x];
            if c.is_finite() {
                *out = !has_neighbours(pts, (w, h), (x, y), (reach(c, p), p.min_neighbors));
            }
        }
    });
    stray
}

/// How far a neighbour of `c` may be and still see the same surface (m).
fn reach(c: Vec3, p: &StrayParams) -> f64 {
    p.radius + p.sigmas * p.depth_noise * c.length_squared()
}

/// Whether at least `enough` of pixel `(x, y)`'s 8 neighbours lie within `r` of it
/// (stopping at the `enough`-th: most pixels of a surface end at the first).
fn has_neighbours(
    pts: &[Vec3],
    (w, h): (usize, usize),
    (x, y): (usize, usize),
    (r, enough): (f64, usize),
) -> bool {
    let c = pts[y * w + x];
    let r2 = r * r;
    let mut n = 0;
    for yy in y.saturating_sub(1)..(y + 2).min(h) {
        for xx in x.saturating_sub(1)..(x + 2).min(w) {
            if (xx, yy) != (x, y) {
                let q = pts[yy * w + xx];
                if q.is_finite() && q.distance_squared(c) <= r2 {
                    n += 1;
                    if n >= enough {
                        return true;
                    }
                }
            }
        }
    }
    false
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A wall `range` m before the camera, seen as a `w × h` depth image with pixel
    /// spacing `pitch` (m) and a deterministic ripple of `ripple` (m) in range.
    fn wall(w: usize, h: usize, range: f64, pitch: f64, ripple: f64) -> PointCloud {
        let points = (0..h)
            .flat_map(|y| (0..w).map(move |x| (x, y)))
            .map(|(x, y)| {
                let wobble = ripple * (((x * 7 + y * 13) % 5) as f64 / 2.0 - 1.0);
                Vec3::new(
                    (x as f64 - w as f64 / 2.0) * pitch,
                    (y as f64 - h as f64 / 2.0) * pitch,
                    range + wobble,
                )
            })
            .collect();
        PointCloud {
            width: w,
            height: h,
            points,
        }
    }

    #[test]
    fn a_lone_return_in_front_of_a_wall_is_stray_and_the_wall_is_not() {
        for (range, ripple) in [(0.8, 0.001), (3.0, 0.02)] {
            let mut cloud = wall(40, 30, range, 0.0015 * range, ripple);
            let at = 15 * 40 + 20;
            cloud.points[at] *= 0.6;
            let stray = stray_returns(&cloud, &StrayParams::default());
            assert!(stray[at], "the return 40 % short at {range} m");
            let others = stray
                .iter()
                .enumerate()
                .filter(|&(i, s)| *s && i != at)
                .count();
            assert_eq!(others, 0, "wall points marked at {range} m");
        }
    }

    #[test]
    fn thin_lines_holes_and_unorganized_clouds_keep_their_points() {
        // A one-pixel-wide rod before a far wall: each rod pixel has rod neighbours.
        let mut cloud = wall(20, 20, 2.5, 0.004, 0.0);
        for y in 0..20 {
            cloud.points[y * 20 + 10].z = 1.0;
        }
        // Holes around a pixel leave it without neighbours to judge: NaN ones count
        // for nothing, and the pixel's rod neighbours above and below still hold.
        cloud.points[5 * 20 + 9] = Vec3::NAN;
        let stray = stray_returns(&cloud, &StrayParams::default());
        assert!(stray.iter().all(|s| !s));
        // A pixel a metre before the wall is stray in the grid; the same points without
        // a grid have no neighbours to be judged by.
        cloud.points[3 * 20 + 3].z = 1.5;
        assert!(stray_returns(&cloud, &StrayParams::default())[3 * 20 + 3]);
        let unorganized = PointCloud {
            width: cloud.points.len(),
            height: 1,
            points: cloud.points.clone(),
        };
        let stray = stray_returns(&unorganized, &StrayParams::default());
        assert_eq!(stray.len(), unorganized.points.len());
        assert!(stray.iter().all(|s| !s));
    }
}
