//! Open containers (bowls, mugs, pots) in one piece. Seen from above, a container's
//! inside is cut from its outside twice: the front rim hides the inside's lower part
//! (a depth jump on the grid) and the inside is concave against the outside (a crease).
//! The outside's rim is a circle on the table's plane; what lies inside that circle,
//! touches the outside on the grid and rises no higher than its rim is the inside.

use super::joins;
use crate::plane::Plane;
use crate::surfaces::plane_basis;
use tabula_geom::{Vec2, Vec3};

/// The rim: an outside's points within this distance (m) of its highest.
const RIM_BAND: f64 = 0.015;
/// Containers this wide (rim radius, m) …
const RADIUS: [f64; 2] = [0.02, 0.2];
/// … whose rim points lie on their circle within this RMS (m).
const MAX_RIM_RESIDUAL: f64 = 0.004;
/// An inside's points lie within the rim's radius plus this (m) …
const SLACK: f64 = 0.006;
/// … all but this share of them.
const OUTSIDE_SHARE: f64 = 0.03;
/// … and rise no higher than the rim by more than this (m).
const ABOVE_RIM: f64 = 0.01;

/// A piece whose rim is a circle on the table: centre and radius (table plane
/// coordinates), rim height.
struct Rim {
    centre: Vec2,
    radius: f64,
    height: f64,
}

/// `regions` with every container's inside joined to its outside (organized frames:
/// `width` is the grid's).
pub(super) fn join_insides(
    pts: &[Vec3],
    width: usize,
    table: &Plane,
    regions: Vec<Vec<usize>>,
) -> Vec<Vec<usize>> {
    if width == 0 || regions.len() < 2 || regions.len() > 512 {
        return regions;
    }
    let (u, v) = plane_basis(table.normal);
    let flat = |i: usize| Vec2::new(pts[i].dot(u), pts[i].dot(v));
    let rims: Vec<Option<Rim>> = regions.iter().map(|m| rim(pts, table, m, &flat)).collect();
    let label = joins::labels(pts.len(), &regions);
    let mut pairs = Vec::new();
    for (a, inside) in regions.iter().enumerate() {
        let best = rims
            .iter()
            .enumerate()
            .filter(|&(b, _)| b != a)
            .filter_map(|(b, r)| r.as_ref().map(|r| (b, r)))
            .filter(|&(b, r)| {
                within(pts, table, inside, r, &flat)
                    && joins::touches(&label, width, inside, b as u32)
            })
            .max_by(|x, y| x.1.radius.total_cmp(&y.1.radius));
        if let Some((b, _)) = best {
            pairs.push((a, b));
        }
    }
    joins::merge(regions, &pairs)
}

/// The circle through a piece's highest band, when it is one.
fn rim(
    pts: &[Vec3],
    table: &Plane,
    members: &[usize],
    flat: &dyn Fn(usize) -> Vec2,
) -> Option<Rim> {
    let height = members
        .iter()
        .map(|&i| table.distance(pts[i]))
        .fold(f64::NEG_INFINITY, f64::max);
    let band: Vec<Vec2> = members
        .iter()
        .filter(|&&i| table.distance(pts[i]) >= height - RIM_BAND)
        .map(|&i| flat(i))
        .collect();
    let (centre, radius) = fit_circle(&band)?;
    let rms = (band
        .iter()
        .map(|q| (q.distance(centre) - radius).powi(2))
        .sum::<f64>()
        / band.len() as f64)
        .sqrt();
    ((RADIUS[0]..=RADIUS[1]).contains(&radius) && rms <= MAX_RIM_RESIDUAL).then_some(Rim {
        centre,
        radius,
        height,
    })
}

/// Kåsa's algebraic circle fit (least squares on x² + y² + Dx + Ey + F = 0), about
/// the points' mean so the normal equations stay well conditioned.
fn fit_circle(points: &[Vec2]) -> Option<(Vec2, f64)> {
    if points.len() < 10 {
        return None;
    }
    let mean = points.iter().copied().sum::<Vec2>() / points.len() as f64;
    let (mut sxx, mut sxy, mut syy, mut sxz, mut syz) = (0.0, 0.0, 0.0, 0.0, 0.0);
    let mut sz = 0.0;
    for p in points {
        let d = *p - mean;
        let z = d.length_squared();
        sxx += d.x * d.x;
        sxy += d.x * d.y;
        syy += d.y * d.y;
        sxz += d.x * z;
        syz += d.y * z;
        sz += z;
    }
    let det = sxx * syy - sxy * sxy;
    if det.abs() < 1e-18 {
        return None;
    }
    // Centre c solves [sxx sxy; sxy syy] c = ½ [sxz; syz].
    let cx = 0.5 * (sxz * syy - syz * sxy) / det;
    let cy = 0.5 * (syz * sxx - sxz * sxy) / det;
    let c = Vec2::new(cx, cy);
    let radius = (c.length_squared() + sz / points.len() as f64).sqrt();
    radius.is_finite().then_some((mean + c, radius))
}

fn within(
    pts: &[Vec3],
    table: &Plane,
    inside: &[usize],
    rim: &Rim,
    flat: &dyn Fn(usize) -> Vec2,
) -> bool {
    let outside = inside
        .iter()
        .filter(|&&i| {
            flat(i).distance(rim.centre) > rim.radius + SLACK
                || table.distance(pts[i]) > rim.height + ABOVE_RIM
        })
        .count();
    (outside as f64) <= OUTSIDE_SHARE * inside.len() as f64
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_half_circle_of_points_gives_its_circle() {
        let points: Vec<Vec2> = (0..50)
            .map(|k| {
                let a = std::f64::consts::PI * k as f64 / 49.0;
                Vec2::new(0.3 + 0.05 * a.cos(), -0.2 + 0.05 * a.sin())
            })
            .collect();
        let (c, r) = fit_circle(&points).unwrap();
        assert!(c.distance(Vec2::new(0.3, -0.2)) < 1e-9 && (r - 0.05).abs() < 1e-9);
        assert!(fit_circle(&points[..5]).is_none());
    }
}
