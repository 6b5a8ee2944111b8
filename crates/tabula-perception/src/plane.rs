//! RANSAC planes with a seed, adaptive iteration count, least-squares refinement and
//! optional normal agreement.

use crate::filters::{scatter, smallest_eigenvector};
use rand::{RngExt, SeedableRng};
use rand_chacha::ChaCha8Rng;
use tabula_geom::Vec3;
use tabula_geom::input::{Validate, check_count, check_in, check_positive};

/// A plane `normal · p + d = 0` with a unit normal.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Plane {
    pub normal: Vec3,
    pub d: f64,
}

impl Plane {
    pub fn distance(&self, p: Vec3) -> f64 {
        self.normal.dot(p) + self.d
    }

    /// Least-squares plane of points (smallest-eigenvalue direction of the scatter).
    pub fn fit(points: &[Vec3]) -> Option<Self> {
        Self::fit_iter(points.iter().copied())
    }

    /// As [`Plane::fit`], from any re-iterable sequence of points.
    pub fn fit_iter(points: impl Iterator<Item = Vec3>) -> Option<Self> {
        let (c, m) = scatter(points)?;
        let (normal, _) = smallest_eigenvector(m)?;
        Some(Plane {
            normal,
            d: -normal.dot(c),
        })
    }

    /// The same plane with its normal pointing the other way.
    pub fn flipped(&self) -> Self {
        Plane {
            normal: -self.normal,
            d: -self.d,
        }
    }
}

/// RANSAC parameters; defaults are seed 000's (SPEC §6: 1 cm threshold).
#[derive(Debug, Clone, serde::Deserialize, serde::Serialize)]
#[serde(default, deny_unknown_fields)]
pub struct RansacParams {
    /// Inlier distance (m), SPEC §6.
    pub threshold: f64,
    /// Probability of having drawn one all-inlier sample when stopping.
    pub confidence: f64,
    pub max_iterations: usize,
    /// Least-squares refits on the inliers.
    pub refinements: usize,
    /// With normals given: inliers' normals must be within this angle (rad) of the
    /// plane's (either direction).
    pub max_normal_angle: f64,
    pub seed: u64,
}

impl Default for RansacParams {
    fn default() -> Self {
        Self {
            threshold: 0.01,
            confidence: 0.999,
            max_iterations: 1000,
            refinements: 2,
            max_normal_angle: 0.35,
            seed: 0,
        }
    }
}

/// The best plane of the finite points (indices into `points`), or `None` when fewer
/// than three usable points exist. Hypotheses are scored on a fixed random subsample of
/// at most 4,000 points, so a hypothesis costs the same on any frame; the iteration count
/// adapts to the inlier ratio found so far (Fischler & Bolles).
pub fn ransac_plane(
    points: &[Vec3],
    candidates: &[usize],
    p: &RansacParams,
) -> Option<(Plane, Vec<usize>)> {
    ransac_plane_with_normals(points, None, candidates, p)
}

/// [`ransac_plane`] for round `round` of a sequential search that peels planes off
/// one after another: each round draws from its own seed.
pub fn ransac_round(
    points: &[Vec3],
    candidates: &[usize],
    p: &RansacParams,
    round: usize,
) -> Option<(Plane, Vec<usize>)> {
    let params = RansacParams {
        seed: p.seed.wrapping_add(round as u64),
        ..p.clone()
    };
    ransac_plane(points, candidates, &params)
}

/// [`ransac_plane`] where, if `normals` are given, a point only counts as an inlier
/// when its normal agrees with the plane's (points without a normal are judged by
/// distance alone) — so the rim of an object standing on a table is not table.
pub fn ransac_plane_with_normals(
    points: &[Vec3],
    normals: Option<&[Vec3]>,
    candidates: &[usize],
    p: &RansacParams,
) -> Option<(Plane, Vec<usize>)> {
    let usable: Vec<usize> = candidates
        .iter()
        .copied()
        .filter(|&i| points.get(i).is_some_and(|q| q.is_finite()))
        .collect();
    if usable.len() < 3 || p.threshold.is_nan() || p.threshold <= 0.0 {
        return None;
    }
    let cos_normal = p.max_normal_angle.cos();
    let agrees = |plane: &Plane, i: usize| {
        plane.distance(points[i]).abs() <= p.threshold
            && normals
                .and_then(|n| n.get(i))
                .is_none_or(|n| !n.is_finite() || n.dot(plane.normal).abs() >= cos_normal)
    };
    let mut rng = ChaCha8Rng::seed_from_u64(p.seed);
    let draw = |rng: &mut ChaCha8Rng, n: usize| -> Vec<usize> {
        if usable.len() > n {
            (0..n)
                .map(|_| usable[rng.random_range(0..usable.len())])
                .collect()
        } else {
            usable.clone()
        }
    };
    let sample = draw(&mut rng, 4000);
    // Without normals, score on a packed copy of the sample's points.
    let packed: Vec<Vec3> = sample.iter().map(|&i| points[i]).collect();
    let (mut best, mut best_count) = (None, 0usize);
    let mut needed = p.max_iterations.max(1);
    let mut it = 0;
    while it < needed {
        it += 1;
        let a = points[usable[rng.random_range(0..usable.len())]];
        let b = points[usable[rng.random_range(0..usable.len())]];
        let c = points[usable[rng.random_range(0..usable.len())]];
        let Some(normal) = (b - a).cross(c - a).try_normalize() else {
            continue;
        };
        let plane = Plane {
            normal,
            d: -normal.dot(a),
        };
        // Capel's bail-out: every 64 points, give up on a hypothesis whose inlier rate
        // so far is more than three standard deviations below the best one's (a
        // plane that wins is never dropped this way but with vanishing probability),
        // or that cannot reach the best count any more.
        let n = sample.len();
        let best_rate = best_count as f64 / n as f64;
        let hopeless = |count: usize, seen: usize| {
            count + (n - seen) <= best_count
                || (seen.is_multiple_of(64) && {
                    let expected = best_rate * seen as f64;
                    (count as f64) < expected - 3.0 * (expected * (1.0 - best_rate)).sqrt()
                })
        };
        let mut count = 0;
        for k in 0..n {
            let inlier = match normals {
                None => (normal.dot(packed[k]) + plane.d).abs() <= p.threshold,
                Some(_) => agrees(&plane, sample[k]),
            };
            count += usize::from(inlier);
            if !inlier && hopeless(count, k + 1) {
                break;
            }
        }
        if count > best_count {
            best_count = count;
            best = Some(plane);
            let w = count as f64 / sample.len() as f64;
            let denom = (1.0 - w * w * w).max(1e-12).ln();
            if denom < 0.0 {
                needed = needed.min(((1.0 - p.confidence).ln() / denom).ceil().max(1.0) as usize);
            }
        }
    }
    let mut plane = best?;
    // Least squares on a large random subset is as good as on all points and cheaper.
    let refine_on = draw(&mut rng, 20_000);
    for _ in 0..p.refinements {
        let inliers = refine_on
            .iter()
            .filter(|&&i| agrees(&plane, i))
            .map(|&i| points[i]);
        match Plane::fit_iter(inliers) {
            Some(f) => plane = f,
            None => break,
        }
    }
    let inliers = usable
        .iter()
        .copied()
        .filter(|&i| agrees(&plane, i))
        .collect();
    Some((plane, inliers))
}

impl Validate for RansacParams {
    fn check(&self, at: &str) -> Result<(), String> {
        check_positive(at, "threshold", self.threshold)?;
        check_in(at, "confidence", self.confidence, 1e-6, 1.0 - 1e-12)?;
        check_count(at, "max_iterations", self.max_iterations, 1)?;
        check_in(
            at,
            "max_normal_angle",
            self.max_normal_angle,
            0.0,
            std::f64::consts::PI,
        )
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn finds_the_dominant_plane_among_outliers_deterministically() {
        let mut rng = ChaCha8Rng::seed_from_u64(3);
        let mut pts: Vec<Vec3> = (0..2000)
            .map(|_| {
                let (x, y) = (rng.random_range(-1.0..1.0), rng.random_range(-1.0..1.0));
                Vec3::new(x, y, 0.5 + 0.1 * x + rng.random_range(-0.003..0.003))
            })
            .collect();
        // 50 % outliers.
        pts.extend((0..2000).map(|_| {
            Vec3::new(
                rng.random_range(-1.0..1.0),
                rng.random_range(-1.0..1.0),
                rng.random_range(-1.0..2.0),
            )
        }));
        pts.push(Vec3::NAN);
        let all: Vec<usize> = (0..pts.len()).collect();
        let p = RansacParams::default();
        let (plane, inliers) = ransac_plane(&pts, &all, &p).unwrap();
        let truth = Vec3::new(-0.1, 0.0, 1.0).normalize();
        assert!(plane.normal.dot(truth).abs() > 0.9999, "{plane:?}");
        assert!(inliers.len() >= 2000 && inliers.len() < 2100);
        assert_eq!(ransac_plane(&pts, &all, &p).unwrap().1, inliers);
    }

    #[test]
    fn normal_agreement_rejects_points_whose_surface_crosses_the_plane() {
        // A floor and a wall meeting it: wall points within 1 cm of the floor are
        // distance-inliers but their normals are horizontal.
        let mut pts = Vec::new();
        let mut normals = Vec::new();
        for i in 0..50 {
            for j in 0..50 {
                pts.push(Vec3::new(i as f64 * 0.01, j as f64 * 0.01, 0.0));
                normals.push(Vec3::Z);
                pts.push(Vec3::new(0.6, i as f64 * 0.01, j as f64 * 0.004));
                normals.push(Vec3::X);
            }
        }
        let all: Vec<usize> = (0..pts.len()).collect();
        let p = RansacParams::default();
        let (_, plain) = ransac_plane(&pts, &all, &p).unwrap();
        let (_, agreeing) = ransac_plane_with_normals(&pts, Some(&normals), &all, &p).unwrap();
        assert!(plain.len() > agreeing.len());
        assert!(agreeing.iter().all(|&i| normals[i] == Vec3::Z));
    }

    #[test]
    fn degenerate_input_gives_none_or_a_plane_without_panicking() {
        let p = RansacParams::default();
        assert!(ransac_plane(&[], &[], &p).is_none());
        assert!(ransac_plane(&[Vec3::ONE], &[0], &p).is_none());
        assert!(ransac_plane(&[Vec3::NAN; 10], &(0..10).collect::<Vec<_>>(), &p).is_none());
        let line: Vec<Vec3> = (0..100).map(|i| Vec3::new(i as f64, 0.0, 0.0)).collect();
        assert!(ransac_plane(&line, &(0..100).collect::<Vec<_>>(), &p).is_none());
        // Out-of-range candidates are ignored.
        assert!(ransac_plane(&line, &[500, 600, 700], &p).is_none());
    }
}
