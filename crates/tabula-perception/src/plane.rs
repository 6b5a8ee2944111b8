//! RANSAC planes with a seed, adaptive iteration count and least-squares refinement.

use nalgebra::{Matrix3, SymmetricEigen, Vector3};
use rand::{RngExt, SeedableRng};
use rand_chacha::ChaCha8Rng;
use tabula_geom::Vec3;

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
        if points.len() < 3 {
            return None;
        }
        let c = points.iter().copied().sum::<Vec3>() / points.len() as f64;
        let mut m = Matrix3::zeros();
        for p in points {
            let d = Vector3::new(p.x - c.x, p.y - c.y, p.z - c.z);
            m += d * d.transpose();
        }
        let eig = SymmetricEigen::new(m);
        let (i, _) = eig
            .eigenvalues
            .iter()
            .enumerate()
            .min_by(|a, b| a.1.total_cmp(b.1))?;
        let v = eig.eigenvectors.column(i);
        let normal = Vec3::new(v[0], v[1], v[2]).try_normalize()?;
        Some(Plane {
            normal,
            d: -normal.dot(c),
        })
    }
}

/// RANSAC parameters; defaults are seed 000's (SPEC §6: 1 cm threshold).
#[derive(Debug, Clone, serde::Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct RansacParams {
    /// Inlier distance (m), SPEC §6.
    pub threshold: f64,
    /// Probability of having drawn one all-inlier sample when stopping.
    pub confidence: f64,
    pub max_iterations: usize,
    /// Least-squares refits on the inliers.
    pub refinements: usize,
    pub seed: u64,
}

impl Default for RansacParams {
    fn default() -> Self {
        Self {
            threshold: 0.01,
            confidence: 0.999,
            max_iterations: 1000,
            refinements: 2,
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
    let usable: Vec<usize> = candidates
        .iter()
        .copied()
        .filter(|&i| points.get(i).is_some_and(|q| q.is_finite()))
        .collect();
    if usable.len() < 3 {
        return None;
    }
    let mut rng = ChaCha8Rng::seed_from_u64(p.seed);
    let sample: Vec<usize> = if usable.len() > 4000 {
        (0..4000)
            .map(|_| usable[rng.random_range(0..usable.len())])
            .collect()
    } else {
        usable.clone()
    };
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
        let count = sample
            .iter()
            .filter(|&&i| plane.distance(points[i]).abs() <= p.threshold)
            .count();
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
    let mut inliers: Vec<usize> = usable
        .iter()
        .copied()
        .filter(|&i| plane.distance(points[i]).abs() <= p.threshold)
        .collect();
    for _ in 0..p.refinements {
        let pts: Vec<Vec3> = inliers.iter().map(|&i| points[i]).collect();
        let Some(refined) = Plane::fit(&pts) else {
            break;
        };
        plane = refined;
        inliers = usable
            .iter()
            .copied()
            .filter(|&i| plane.distance(points[i]).abs() <= p.threshold)
            .collect();
    }
    Some((plane, inliers))
}
