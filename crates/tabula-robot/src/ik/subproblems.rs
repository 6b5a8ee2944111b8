//! Paden–Kahan subproblems (as IK-Geo numbers them, Elias & Wen 2022): the closed-form
//! pieces the analytic solvers are built from. Axes are unit vectors through the
//! origin; points are relative to a point on the axis.

use tabula_geom::Vec3;

/// Geometry checks (parallel, intersecting) are relative to this (m or rad).
pub(crate) const TOL: f64 = 1e-9;

/// θ with `rot(k, θ) p = q` (p and q at the same height along k), `None` when p or q
/// lies on the axis (any θ, or none).
pub(crate) fn subproblem1(p: Vec3, q: Vec3, k: Vec3) -> Option<f64> {
    let pp = p - k * k.dot(p);
    let qp = q - k * k.dot(q);
    if pp.length() < TOL || qp.length() < TOL {
        return None;
    }
    Some(k.dot(pp.cross(qp)).atan2(pp.dot(qp)))
}

/// Every θ with `hᵀ rot(k, θ) p = d` (none, one or two): `A cos θ + B sin θ = C`.
pub(crate) fn subproblem4(h: Vec3, p: Vec3, k: Vec3, d: f64) -> Roots {
    let along = k * k.dot(p);
    let a = h.dot(p - along);
    let b = h.dot(k.cross(p));
    let c = d - h.dot(along);
    let r = a.hypot(b);
    let scale = h.length() * p.length() + d.abs() + 1.0;
    if r < TOL * scale || c.abs() > r + 1e-12 * scale {
        return Roots::default();
    }
    let phi = b.atan2(a);
    let spread = (c / r).clamp(-1.0, 1.0).acos();
    if spread < 1e-12 {
        Roots {
            values: [phi, 0.0],
            len: 1,
        }
    } else {
        Roots {
            values: [phi + spread, phi - spread],
            len: 2,
        }
    }
}

/// Every θ with `|q − rot(k, θ) p| = d` (subproblem 3): through `qᵀ rot(k, θ) p`.
pub(crate) fn subproblem3(p: Vec3, q: Vec3, k: Vec3, d: f64) -> Roots {
    subproblem4(
        q,
        p,
        k,
        (q.length_squared() + p.length_squared() - d * d) / 2.0,
    )
}

/// Every (θ1, θ2) with `rot(k1, θ1) p1 = rot(k2, θ2) p2` (subproblem 2; k1, k2 not
/// parallel): the common image lies on both circles, found from its components along
/// k1, k2 and k1 × k2. None, one or two pairs.
pub(crate) fn subproblem2(p1: Vec3, k1: Vec3, p2: Vec3, k2: Vec3) -> Pairs {
    let mut out = Pairs::default();
    let n = k1.cross(k2);
    let nn = n.length_squared();
    if nn < TOL {
        return out;
    }
    let c = k1.dot(k2);
    let (a1, a2) = (k1.dot(p1), k2.dot(p2));
    let alpha = (a1 - c * a2) / (1.0 - c * c);
    let beta = (a2 - c * a1) / (1.0 - c * c);
    // The two points have the same length up to rounding: their mean.
    let r2 = (p1.length_squared() + p2.length_squared()) / 2.0;
    let g2 = (r2 - alpha * alpha - beta * beta - 2.0 * alpha * beta * c) / nn;
    let scale = r2 + 1e-12;
    if g2 < -1e-10 * scale {
        return out;
    }
    let gamma = g2.max(0.0).sqrt();
    let signs: &[f64] = if gamma < 1e-9 * scale.sqrt() {
        &[1.0]
    } else {
        &[1.0, -1.0]
    };
    for &s in signs {
        let v = k1 * alpha + k2 * beta + n * (s * gamma);
        if let (Some(t1), Some(t2)) = (subproblem1(p1, v, k1), subproblem1(p2, v, k2)) {
            out.values[out.len] = (t1, t2);
            out.len += 1;
        }
    }
    out
}

/// Up to two angle pairs, without allocating.
#[derive(Default)]
pub(crate) struct Pairs {
    values: [(f64, f64); 2],
    len: usize,
}

impl IntoIterator for Pairs {
    type Item = (f64, f64);
    type IntoIter = std::iter::Take<std::array::IntoIter<(f64, f64), 2>>;
    fn into_iter(self) -> Self::IntoIter {
        self.values.into_iter().take(self.len)
    }
}

/// Up to two angles, without allocating (the solver's inner loops run per solve).
#[derive(Default)]
pub(crate) struct Roots {
    values: [f64; 2],
    len: usize,
}

impl IntoIterator for Roots {
    type Item = f64;
    type IntoIter = std::iter::Take<std::array::IntoIter<f64, 2>>;
    fn into_iter(self) -> Self::IntoIter {
        self.values.into_iter().take(self.len)
    }
}

/// The point where the lines (a + s u) and (b + t v) meet, `None` if they do not.
pub(crate) fn intersection(a: Vec3, u: Vec3, b: Vec3, v: Vec3) -> Option<Vec3> {
    let n = u.cross(v);
    let nn = n.length_squared();
    if nn < TOL {
        return None;
    }
    let w = b - a;
    if (w.dot(n)).abs() / nn.sqrt() > 1e-7 {
        return None; // skew lines: a common normal of non-zero length
    }
    let s = w.cross(v).dot(n) / nn;
    Some(a + u * s)
}

pub(crate) fn any_perpendicular(k: Vec3) -> Vec3 {
    let t = if k.x.abs() < 0.9 { Vec3::X } else { Vec3::Y };
    k.cross(t).normalize()
}
