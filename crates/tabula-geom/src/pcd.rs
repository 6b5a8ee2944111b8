//! Reading PCD files (ascii, binary, binary_compressed) into a [`PointCloud`].
//!
//! Only the x, y, z fields are kept; any other fields (rgb, normals, labels) are skipped
//! by their declared size. Every malformed header or short body is a [`PcdError`].

use crate::{PointCloud, Vec3};

/// Why a PCD file cannot be read.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[error("PCD: {0}")]
pub struct PcdError(pub String);

fn err<T>(m: impl Into<String>) -> Result<T, PcdError> {
    Err(PcdError(m.into()))
}

#[derive(Debug)]
struct Field {
    name: String,
    size: usize,
    kind: u8,
    count: usize,
}

/// LZF decompression (the codec of PCD's binary_compressed).
fn lzf_decompress(input: &[u8], out_len: usize) -> Result<Vec<u8>, PcdError> {
    let mut out = Vec::with_capacity(out_len);
    let mut i = 0;
    while i < input.len() {
        let ctrl = input[i] as usize;
        i += 1;
        if ctrl < 32 {
            let n = ctrl + 1;
            if i + n > input.len() || out.len() + n > out_len {
                return err("compressed data overruns");
            }
            out.extend_from_slice(&input[i..i + n]);
            i += n;
        } else {
            let mut len = ctrl >> 5;
            if len == 7 {
                let Some(&b) = input.get(i) else {
                    return err("compressed data truncated");
                };
                len += b as usize;
                i += 1;
            }
            len += 2;
            let Some(&b) = input.get(i) else {
                return err("compressed data truncated");
            };
            i += 1;
            let back = ((ctrl & 0x1f) << 8) + b as usize + 1;
            if back > out.len() || out.len() + len > out_len {
                return err("compressed back-reference out of range");
            }
            let start = out.len() - back;
            for k in 0..len {
                let byte = out[start + k];
                out.push(byte);
            }
        }
    }
    if out.len() != out_len {
        return err(format!(
            "decompressed {} bytes, expected {out_len}",
            out.len()
        ));
    }
    Ok(out)
}

fn read_value(bytes: &[u8], f: &Field) -> f64 {
    match (f.kind, f.size) {
        (b'F', 4) => f32::from_le_bytes([bytes[0], bytes[1], bytes[2], bytes[3]]) as f64,
        (b'F', 8) => f64::from_le_bytes(bytes[..8].try_into().unwrap_or([0; 8])),
        (b'I', 1) => bytes[0] as i8 as f64,
        (b'I', 2) => i16::from_le_bytes([bytes[0], bytes[1]]) as f64,
        (b'I', 4) => i32::from_le_bytes([bytes[0], bytes[1], bytes[2], bytes[3]]) as f64,
        (b'U', 1) => bytes[0] as f64,
        (b'U', 2) => u16::from_le_bytes([bytes[0], bytes[1]]) as f64,
        (b'U', 4) => u32::from_le_bytes([bytes[0], bytes[1], bytes[2], bytes[3]]) as f64,
        _ => f64::NAN,
    }
}

/// Parses PCD bytes.
pub fn read_pcd(bytes: &[u8]) -> Result<PointCloud, PcdError> {
    let mut fields: Vec<Field> = Vec::new();
    let (mut width, mut height, mut points) = (None, None, None);
    let mut pos = 0;
    let mut data = None;
    while pos < bytes.len() {
        let end = bytes[pos..]
            .iter()
            .position(|&b| b == b'\n')
            .map_or(bytes.len(), |e| pos + e);
        let line = String::from_utf8_lossy(&bytes[pos..end]).trim().to_string();
        pos = (end + 1).min(bytes.len());
        if line.is_empty() || line.starts_with('#') {
            continue;
        }
        let mut words = line.split_whitespace();
        let key = words.next().unwrap_or("").to_ascii_uppercase();
        let rest: Vec<&str> = words.collect();
        let num = |s: &str| {
            s.parse::<usize>()
                .map_err(|_| PcdError(format!("`{s}` in `{line}` is not a count")))
        };
        match key.as_str() {
            "VERSION" | "VIEWPOINT" => {}
            "FIELDS" => {
                fields = rest
                    .iter()
                    .map(|n| Field {
                        name: n.to_string(),
                        size: 4,
                        kind: b'F',
                        count: 1,
                    })
                    .collect();
            }
            "SIZE" | "TYPE" | "COUNT" => {
                if rest.len() != fields.len() {
                    return err(format!(
                        "{key} has {} entries for {} fields",
                        rest.len(),
                        fields.len()
                    ));
                }
                for (f, v) in fields.iter_mut().zip(&rest) {
                    match key.as_str() {
                        "SIZE" => f.size = num(v)?,
                        "TYPE" => f.kind = v.bytes().next().unwrap_or(b'?').to_ascii_uppercase(),
                        _ => f.count = num(v)?,
                    }
                }
            }
            "WIDTH" => width = Some(num(rest.first().copied().unwrap_or(""))?),
            "HEIGHT" => height = Some(num(rest.first().copied().unwrap_or(""))?),
            "POINTS" => points = Some(num(rest.first().copied().unwrap_or(""))?),
            "DATA" => {
                data = Some(rest.first().copied().unwrap_or("").to_ascii_lowercase());
                break;
            }
            other => return err(format!("unknown header line `{other}`")),
        }
    }
    let Some(data) = data else {
        return err("no DATA line");
    };
    let (w, h) = (width.unwrap_or(0), height.unwrap_or(1));
    let n = points.unwrap_or(w.saturating_mul(h));
    if w.checked_mul(h) != Some(n) {
        return err(format!("WIDTH {w} × HEIGHT {h} is not POINTS {n}"));
    }
    if n > 100_000_000 {
        return err(format!("{n} points is more than this reader accepts"));
    }
    for f in &fields {
        if !matches!((f.kind, f.size), (b'F', 4 | 8) | (b'I' | b'U', 1 | 2 | 4))
            || f.count == 0
            || f.count > 1 << 16
        {
            return err(format!(
                "field `{}` has an unsupported type {}{} × {}",
                f.name, f.kind as char, f.size, f.count
            ));
        }
    }
    let index = |name: &str| fields.iter().position(|f| f.name == name);
    let (Some(ix), Some(iy), Some(iz)) = (index("x"), index("y"), index("z")) else {
        return err("the fields must include x, y and z");
    };
    let body = &bytes[pos..];
    let mut out = Vec::with_capacity(n);
    match data.as_str() {
        "ascii" => {
            let text = String::from_utf8_lossy(body);
            let stride: usize = fields.iter().map(|f| f.count).sum();
            let offsets: Vec<usize> = fields
                .iter()
                .scan(0, |o, f| {
                    let here = *o;
                    *o += f.count;
                    Some(here)
                })
                .collect();
            for (k, line) in text.lines().filter(|l| !l.trim().is_empty()).enumerate() {
                if k >= n {
                    break;
                }
                let vals: Vec<&str> = line.split_whitespace().collect();
                if vals.len() < stride {
                    return err(format!(
                        "data line {} has {} values, expected {stride}",
                        k + 1,
                        vals.len()
                    ));
                }
                let v = |i: usize| vals[offsets[i]].parse::<f64>().unwrap_or(f64::NAN);
                out.push(Vec3::new(v(ix), v(iy), v(iz)));
            }
        }
        "binary" => {
            let stride: usize = fields.iter().map(|f| f.size * f.count).sum();
            if body.len() < n * stride {
                return err(format!(
                    "binary data has {} bytes, expected {}",
                    body.len(),
                    n * stride
                ));
            }
            let offs: Vec<usize> = fields
                .iter()
                .scan(0, |o, f| {
                    let here = *o;
                    *o += f.size * f.count;
                    Some(here)
                })
                .collect();
            for k in 0..n {
                let p = &body[k * stride..];
                out.push(Vec3::new(
                    read_value(&p[offs[ix]..], &fields[ix]),
                    read_value(&p[offs[iy]..], &fields[iy]),
                    read_value(&p[offs[iz]..], &fields[iz]),
                ));
            }
        }
        "binary_compressed" => {
            if body.len() < 8 {
                return err("compressed header truncated");
            }
            let csize = u32::from_le_bytes([body[0], body[1], body[2], body[3]]) as usize;
            let usize_ = u32::from_le_bytes([body[4], body[5], body[6], body[7]]) as usize;
            if body.len() < 8 + csize {
                return err("compressed data truncated");
            }
            let raw = lzf_decompress(&body[8..8 + csize], usize_)?;
            // Field-major layout: all x, then all y, …
            let mut offset = 0;
            let mut starts = Vec::new();
            for f in &fields {
                starts.push(offset);
                offset += f.size * f.count * n;
            }
            if raw.len() < offset {
                return err("decompressed data too short");
            }
            for k in 0..n {
                let at = |i: usize| {
                    read_value(
                        &raw[starts[i] + k * fields[i].size * fields[i].count..],
                        &fields[i],
                    )
                };
                out.push(Vec3::new(at(ix), at(iy), at(iz)));
            }
        }
        other => return err(format!("unknown DATA encoding `{other}`")),
    }
    if out.len() != n {
        return err(format!("{} points read, header says {n}", out.len()));
    }
    Ok(PointCloud {
        width: w,
        height: h,
        points: out,
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::PcdEncoding;

    #[test]
    fn round_trips_with_the_writer_and_rejects_junk() {
        let cloud = PointCloud::organized(
            2,
            2,
            vec![
                Vec3::new(1.0, 2.0, 3.0),
                Vec3::NAN,
                Vec3::new(-1.0, 0.5, 2.0),
                Vec3::new(0.0, 0.0, 1.0),
            ],
        )
        .unwrap();
        for enc in [PcdEncoding::Ascii, PcdEncoding::Binary] {
            let mut bytes = Vec::new();
            cloud.write_pcd(&mut bytes, enc).unwrap();
            let back = read_pcd(&bytes).unwrap();
            assert_eq!((back.width, back.height), (2, 2));
            assert_eq!(back.points[0], Vec3::new(1.0, 2.0, 3.0));
            assert!(back.points[1].x.is_nan());
        }
        for junk in [
            &b""[..],
            b"VERSION 0.7\n",
            b"FIELDS x y z\nWIDTH 2\nHEIGHT 1\nPOINTS 3\nDATA ascii\n",
            b"FIELDS a b\nWIDTH 1\nPOINTS 1\nDATA ascii\n1 2\n",
            b"FIELDS x y z\nWIDTH 1\nPOINTS 1\nDATA binary\n\x00",
        ] {
            assert!(
                read_pcd(junk).is_err(),
                "{:?}",
                String::from_utf8_lossy(junk)
            );
        }
    }

    #[test]
    fn lzf_literal_and_back_reference() {
        // "abcabcabc": 3 literals, then copy 6 bytes from 3 back.
        // Literal run "abc", then a back-reference: length (4 + 2), distance (2 + 1).
        let compressed = [2u8, b'a', b'b', b'c', 4 << 5, 2];
        assert_eq!(lzf_decompress(&compressed, 9).unwrap(), b"abcabcabc");
        assert!(lzf_decompress(&[1 << 5, 9], 3).is_err());
    }

    #[test]
    fn mutated_files_never_panic() {
        let cloud = PointCloud::organized(3, 1, vec![Vec3::ONE; 3]).unwrap();
        let mut base = Vec::new();
        cloud.write_pcd(&mut base, PcdEncoding::Binary).unwrap();
        let mut seed = 88172645463325252u64;
        for _ in 0..5000 {
            let mut b = base.clone();
            for _ in 0..1 + seed % 4 {
                seed ^= seed << 13;
                seed ^= seed >> 7;
                seed ^= seed << 17;
                let i = (seed as usize) % b.len();
                b[i] = (seed >> 32) as u8;
            }
            let _ = read_pcd(&b);
        }
    }
}
