//! Paden–Kahan subproblems (as IK-Geo numbers them, Elias & Wen 2022): the closed-form
//! pieces the analytic solvers are built from. Axes are unit vectors through the
//! origin; points are relative to a point on the axis.

use tabula_geom::{Mat3, Vec3};

/// Geometry checks (parallel, intersecting) are relative to this (m or rad).
pub(crate) const TOL: f64 = 1e-9;

/// An angle kept as its cosine and sine: the subproblems produce these without a
/// trigonometric call, rotations are built from them directly, and the angle itself
/// (one `atan2`) is taken only for a verified answer.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct Turn {
    pub c: f64,
    pub s: f64,
}

impl Default for Turn {
    /// No turn.
    fn default() -> Self {
        Self { c: 1.0, s: 0.0 }
    }
}

impl Turn {
    #[inline]
    pub(crate) fn new(angle: f64) -> Self {
        let (s, c) = angle.sin_cos();
        Self { c, s }
    }

    #[inline]
    pub(crate) fn angle(self) -> f64 {
        atan2(self.s, self.c)
    }

    /// The angle negated.
    #[inline]
    pub(crate) fn inverse(self) -> Self {
        Self {
            c: self.c,
            s: -self.s,
        }
    }

    /// The difference of the two angles.
    #[inline]
    pub(crate) fn minus(self, other: Self) -> Self {
        Self {
            c: self.c * other.c + self.s * other.s,
            s: self.s * other.c - self.c * other.s,
        }
    }

    /// `rot(k, θ) v` (Rodrigues), `k` a unit vector.
    #[inline]
    pub(crate) fn rotate(self, k: Vec3, v: Vec3) -> Vec3 {
        v * self.c + k.cross(v) * self.s + k * (k.dot(v) * (1.0 - self.c))
    }

    /// `rot(k, θ)` as a matrix, `k` a unit vector.
    #[inline]
    pub(crate) fn about(self, k: Vec3) -> Mat3 {
        let (c, s, t) = (self.c, self.s, 1.0 - self.c);
        let (x, y, z) = (k.x, k.y, k.z);
        Mat3::from_cols(
            Vec3::new(t * x * x + c, t * x * y + s * z, t * x * z - s * y),
            Vec3::new(t * x * y - s * z, t * y * y + c, t * y * z + s * x),
            Vec3::new(t * x * z + s * y, t * y * z - s * x, t * z * z + c),
        )
    }
}

/// `atan2(y, x)` within a few ulps of libm's, in a third of its instructions: a
/// solve of a UR-type arm takes 30 of them and libm's (about 150 instructions each) were
/// a third of the solve. The ratio of the smaller to the larger magnitude is reduced
/// to within 1/16 of a multiple of 1/8, whose arctangent is tabled; the rest is the
/// arctangent's series to `u¹⁵` (truncation below 1e-20 at |u| ≤ 1/16). Zeros,
/// infinities and NaN go to libm for its conventions.
#[inline]
fn atan2(y: f64, x: f64) -> f64 {
    use std::f64::consts::{FRAC_PI_2, FRAC_PI_4, PI};
    /// `atan(i/8)`, i = 0…8, rounded to the nearest double.
    const ATAN_EIGHTHS: [f64; 9] = [
        0.0,
        0.124_354_994_546_761_44,
        0.244_978_663_126_864_14,
        0.358_770_670_270_572_25,
        0.463_647_609_000_806_1,
        0.558_599_315_343_562_4,
        0.643_501_108_793_284_4,
        0.718_829_999_621_624_5,
        FRAC_PI_4,
    ];
    let (ax, ay) = (x.abs(), y.abs());
    let steep = ay > ax;
    let (num, den) = if steep { (ax, ay) } else { (ay, ax) };
    if !(den > 0.0 && den < f64::INFINITY) {
        return y.atan2(x);
    }
    let t = num / den;
    let i = (t * 8.0 + 0.5) as usize;
    let c = i as f64 / 8.0;
    let u = (t - c) / (1.0 + t * c);
    let u2 = u * u;
    let odd = |n: f64| 1.0 / n;
    let series = u
        * (1.0
            - u2 * (odd(3.0)
                - u2 * (odd(5.0)
                    - u2 * (odd(7.0)
                        - u2 * (odd(9.0)
                            - u2 * (odd(11.0) - u2 * (odd(13.0) - u2 * odd(15.0))))))));
    let mut a = ATAN_EIGHTHS[i.min(8)] + series;
    if steep {
        a = FRAC_PI_2 - a;
    }
    if x.is_sign_negative() {
        a = PI - a;
    }
    if y.is_sign_negative() { -a } else { a }
}

/// θ with `rot(k, θ) p = q` (p and q at the same height along k), `None` when p or q
/// lies on the axis (any θ, or none).
#[inline]
pub(crate) fn subproblem1(p: Vec3, q: Vec3, k: Vec3) -> Option<Turn> {
    let pp = p - k * k.dot(p);
    let qp = q - k * k.dot(q);
    if pp.length_squared() < TOL * TOL || qp.length_squared() < TOL * TOL {
        return None;
    }
    let (c, s) = (pp.dot(qp), k.dot(pp.cross(qp)));
    // Lengths are of a robot's geometry: no overflow for `hypot` to guard (it costs as
    // much as the rest of the subproblem).
    let inv = 1.0 / (c * c + s * s).sqrt();
    Some(Turn {
        c: c * inv,
        s: s * inv,
    })
}

/// Every θ with `hᵀ rot(k, θ) p = d` (none, one or two): `A cos θ + B sin θ = C`, so
/// θ = φ ± σ with `tan φ = B/A`, `cos σ = C/√(A²+B²)`.
#[inline]
pub(crate) fn subproblem4(h: Vec3, p: Vec3, k: Vec3, d: f64) -> Roots {
    let along = k * k.dot(p);
    let a = h.dot(p - along);
    let b = h.dot(k.cross(p));
    let c = d - h.dot(along);
    let r = (a * a + b * b).sqrt();
    let scale = h.length() * p.length() + d.abs() + 1.0;
    if r < TOL * scale || c.abs() > r + 1e-12 * scale {
        return Roots::default();
    }
    let inv = 1.0 / r;
    let phi = Turn {
        c: a * inv,
        s: b * inv,
    };
    let cos_spread = (c * inv).clamp(-1.0, 1.0);
    let sin_spread = (1.0 - cos_spread * cos_spread).max(0.0).sqrt();
    let spread = Turn {
        c: cos_spread,
        s: sin_spread,
    };
    if sin_spread < 1e-12 {
        Roots {
            values: [phi, phi],
            len: 1,
        }
    } else {
        Roots {
            values: [phi.minus(spread.inverse()), phi.minus(spread)],
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
    values: [(Turn, Turn); 2],
    len: usize,
}

impl IntoIterator for Pairs {
    type Item = (Turn, Turn);
    type IntoIter = std::iter::Take<std::array::IntoIter<(Turn, Turn), 2>>;
    fn into_iter(self) -> Self::IntoIter {
        self.values.into_iter().take(self.len)
    }
}

/// Up to two angles, without allocating (the solver's inner loops run per solve).
#[derive(Default)]
pub(crate) struct Roots {
    values: [Turn; 2],
    len: usize,
}

impl IntoIterator for Roots {
    type Item = Turn;
    type IntoIter = std::iter::Take<std::array::IntoIter<Turn, 2>>;
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

#[cfg(test)]
mod tests {
    use super::*;
    use rand::{RngExt, SeedableRng};

    /// Within 4 ulps of libm's `atan2` over every octant, at angles from 1e-300 to π,
    /// and libm's own answer for zeros, infinities and NaN.
    #[test]
    fn atan2_agrees_with_libm() {
        let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(7);
        let ulp = |v: f64| (v.abs().max(f64::MIN_POSITIVE)) * f64::EPSILON;
        let mut worst: f64 = 0.0;
        for n in 0..2_000_000 {
            let scale = 10f64.powi(rng.random_range(-12..12));
            let (mut y, mut x): (f64, f64) =
                (rng.random_range(-1.0..1.0), rng.random_range(-1.0..1.0));
            if n % 7 == 0 {
                y *= 10f64.powi(-rng.random_range(0..300)); // tiny angles
            }
            (y, x) = (y * scale, x * scale);
            let (ours, libm) = (atan2(y, x), y.atan2(x));
            worst = worst.max((ours - libm).abs() / ulp(libm));
        }
        assert!(worst <= 4.0, "{worst} ulps");
        for (y, x) in [
            (0.0, 0.0),
            (-0.0, -0.0),
            (0.0, -1.0),
            (-0.0, -1.0),
            (1.0, 0.0),
            (1.0, -0.0),
            (f64::INFINITY, 1.0),
            (1.0, f64::NEG_INFINITY),
            (f64::NAN, 1.0),
            (1.0, f64::NAN),
        ] {
            let (ours, libm) = (atan2(y, x), y.atan2(x));
            assert!(
                ours == libm || (ours.is_nan() && libm.is_nan()),
                "({y}, {x}): {ours} vs {libm}"
            );
        }
    }

    /// Turns compose as angles do and rotate as `Mat3::from_axis_angle`.
    #[test]
    fn turns_match_angles_and_rotations() {
        let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(8);
        for _ in 0..1000 {
            let (a, b) = (rng.random_range(-7.0..7.0), rng.random_range(-7.0..7.0));
            let k = Vec3::new(
                rng.random_range(-1.0..1.0),
                rng.random_range(-1.0..1.0),
                rng.random_range(-1.0..1.0),
            )
            .normalize();
            let v = Vec3::new(
                rng.random_range(-1.0..1.0),
                rng.random_range(-1.0..1.0),
                rng.random_range(-1.0..1.0),
            );
            let (ta, tb) = (Turn::new(a), Turn::new(b));
            let d = ta.minus(tb);
            assert!((d.c - (a - b).cos()).abs() < 1e-14 && (d.s - (a - b).sin()).abs() < 1e-14);
            let m = Mat3::from_axis_angle(k, a);
            assert!((ta.about(k) * v - m * v).length() < 1e-14);
            assert!((ta.rotate(k, v) - m * v).length() < 1e-14);
            assert!((tabula_geom::wrap_angle(ta.angle() - a)).abs() < 1e-14);
        }
    }
}
