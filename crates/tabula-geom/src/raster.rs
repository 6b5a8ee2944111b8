//! Rasters: occupancy grids and the distances in them.

/// Squared Euclidean distance (in cells) from every cell to the nearest blocked cell
/// (Felzenszwalb & Huttenlocher's exact transform: two passes of 1D lower envelopes).
pub fn distance_transform(blocked: &[bool], nx: usize, ny: usize) -> Vec<f64> {
    let inf = 1e20;
    let mut d: Vec<f64> = blocked.iter().map(|&b| if b { 0.0 } else { inf }).collect();
    let mut f = vec![0.0; nx.max(ny)];
    let mut out = vec![0.0; nx.max(ny)];
    let mut vtx = vec![0usize; nx.max(ny)];
    let mut z = vec![0.0; nx.max(ny) + 1];
    let mut pass =
        |d: &mut Vec<f64>, n: usize, count: usize, at: &dyn Fn(usize, usize) -> usize| {
            for line in 0..count {
                for q in 0..n {
                    f[q] = d[at(line, q)];
                }
                envelope(&f[..n], &mut out[..n], &mut vtx, &mut z);
                for q in 0..n {
                    d[at(line, q)] = out[q];
                }
            }
        };
    pass(&mut d, nx, ny, &|row, q| row * nx + q);
    pass(&mut d, ny, nx, &|col, q| q * nx + col);
    d
}

/// 1D squared distance transform of sampled function `f` (lower envelope of parabolas).
fn envelope(f: &[f64], out: &mut [f64], v: &mut [usize], z: &mut [f64]) {
    let n = f.len();
    if n == 0 {
        return;
    }
    let mut k = 0usize;
    v[0] = 0;
    z[0] = f64::NEG_INFINITY;
    z[1] = f64::INFINITY;
    for q in 1..n {
        loop {
            let p = v[k];
            let s = ((f[q] + (q * q) as f64) - (f[p] + (p * p) as f64))
                / (2.0 * q as f64 - 2.0 * p as f64);
            // z[0] = −∞, so k never goes below 0.
            if s <= z[k] {
                k -= 1;
            } else {
                k += 1;
                v[k] = q;
                z[k] = s;
                z[k + 1] = f64::INFINITY;
                break;
            }
        }
    }
    k = 0;
    for (q, o) in out.iter_mut().enumerate() {
        while z[k + 1] < q as f64 {
            k += 1;
        }
        let p = v[k];
        *o = (q as f64 - p as f64).powi(2) + f[p];
    }
}
