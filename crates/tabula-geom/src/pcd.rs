//! Reading PCD files (ascii, binary, binary_compressed) into a [`PointCloud`].
//!
//! The x, y, z fields become points; a packed `rgb` or `rgba` field (PCL's layout:
//! 0x00RRGGBB in a float's or an unsigned int's bits) becomes colours; a `label` field
//! (PCL's segmentation labels, any integer type) becomes labels; `VIEWPOINT` becomes the
//! sensor pose in the cloud's frame. Other fields (normals, curvature) are skipped by
//! their declared size. Every size from the header is checked arithmetic
//! and checked against the body before anything is allocated; every malformed header,
//! short body or non-numeric value is a [`PcdError`].

use crate::{CloudFile, PointCloud, Pose, Quat, Vec3};

/// Why a PCD file cannot be read.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[error("PCD: {0}")]
pub struct PcdError(pub String);

fn err<T>(m: impl Into<String>) -> Result<T, PcdError> {
    Err(PcdError(m.into()))
}

/// Most points a file may claim (a 640 × 480 frame is 0.3 M; a dense lidar map tens of M).
pub const MAX_PCD_POINTS: usize = 100_000_000;

/// Header words are quoted back in errors at most this long, so a hostile line is not
/// echoed whole.
fn clip(s: &str) -> String {
    crate::input::clip(s, 60)
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
    // A three-byte back-reference makes at most 264 bytes: a block that claims more than
    // 88 times its size is a lie, refused before its claim is reserved.
    if out_len / 88 > input.len() {
        return err(format!(
            "{} compressed bytes cannot unpack to {out_len}",
            input.len()
        ));
    }
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

/// PCL packs colour as 0x00RRGGBB (`rgb`) or 0xAARRGGBB (`rgba`) in four bytes, read
/// as a float or an unsigned int: the bits are the colour either way.
fn unpack_rgb(bits: u32) -> [u8; 3] {
    [(bits >> 16) as u8, (bits >> 8) as u8, bits as u8]
}

/// One ascii value of a field: a number (`nan` and `inf` included); anything else is
/// an error, not a silent NaN.
fn parse_ascii(tok: &str, line: usize) -> Result<f64, PcdError> {
    tok.parse::<f64>()
        .map_err(|_| PcdError(format!("data line {line}: `{}` is not a number", clip(tok))))
}

/// Colour bits of an ascii value. Integers are the bits (some writers print a float
/// `rgb` field as its bits: a packed colour read as a float is below 1e-30, so an
/// integer ≥ 1 can only be bits); other floats are reinterpreted.
fn ascii_rgb_bits(tok: &str, f: &Field, line: usize) -> Result<u32, PcdError> {
    if let Ok(bits) = tok.parse::<u32>() {
        return Ok(bits);
    }
    match tok.parse::<f32>() {
        Ok(v) if f.kind == b'F' => Ok(v.to_bits()),
        _ => err(format!("data line {line}: `{}` is not a colour", clip(tok))),
    }
}

/// Points, and their colours and labels when the file has them.
struct Decoded {
    points: Vec<Vec3>,
    colors: Option<Vec<[u8; 3]>>,
    labels: Option<Vec<u32>>,
}

/// A `label` value as PCL's unsigned label: any integer type, or a float holding a whole
/// number; anything else (negative, fractional, NaN) is an error, not a silent 0.
fn label_of(v: f64, k: usize) -> Result<u32, PcdError> {
    if v >= 0.0 && v <= f64::from(u32::MAX) && v.fract() == 0.0 {
        Ok(v as u32)
    } else {
        err(format!(
            "point {}: label {v} is not a non-negative integer",
            k + 1
        ))
    }
}

/// Points (fields `xyz`) and colours (field `colour`) of `n` binary points, from the
/// bytes of field `i` of point `k` whatever the layout (point-major binary, field-major
/// compressed).
fn decode<'a>(
    n: usize,
    fields: &[Field],
    c: &Columns,
    at: &dyn Fn(usize, usize) -> &'a [u8],
) -> Result<Decoded, PcdError> {
    let points = (0..n)
        .map(|k| {
            let [x, y, z] = c.xyz.map(|i| read_value(at(i, k), &fields[i]));
            Vec3::new(x, y, z)
        })
        .collect();
    let colors = c.colour.map(|i| {
        (0..n)
            .map(|k| {
                let b = at(i, k);
                unpack_rgb(u32::from_le_bytes([b[0], b[1], b[2], b[3]]))
            })
            .collect()
    });
    let labels = match c.label {
        Some(i) => Some(
            (0..n)
                .map(|k| label_of(read_value(at(i, k), &fields[i]), k))
                .collect::<Result<_, _>>()?,
        ),
        None => None,
    };
    Ok(Decoded {
        points,
        colors,
        labels,
    })
}

/// Parses PCD bytes into a cloud (points only; see [`read_pcd_file`] for colours and
/// the sensor pose).
pub fn read_pcd(bytes: &[u8]) -> Result<PointCloud, PcdError> {
    read_pcd_file(bytes).map(|f| f.cloud)
}

/// What a PCD header says, up to its `DATA` line.
struct PcdHeader {
    fields: Vec<Field>,
    width: Option<usize>,
    height: Option<usize>,
    points: Option<usize>,
    viewpoint: Pose,
    /// The `DATA` encoding, lower case; where the body starts.
    data: String,
    body_start: usize,
}

/// The header's lines, up to and including `DATA`.
fn parse_pcd_header(bytes: &[u8]) -> Result<PcdHeader, PcdError> {
    let mut h = PcdHeader {
        fields: Vec::new(),
        width: None,
        height: None,
        points: None,
        viewpoint: Pose::IDENTITY,
        data: String::new(),
        body_start: bytes.len(),
    };
    let mut pos = 0;
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
        if key == "DATA" {
            h.data = rest.first().copied().unwrap_or("").to_ascii_lowercase();
            h.body_start = pos;
            return Ok(h);
        }
        h.line(&key, &rest)?;
    }
    err("no DATA line")
}

impl PcdHeader {
    /// One header line other than `DATA`.
    fn line(&mut self, key: &str, rest: &[&str]) -> Result<(), PcdError> {
        let num = |s: &str| {
            s.parse::<usize>()
                .map_err(|_| PcdError(format!("`{}` in {key} is not a count", clip(s))))
        };
        let first = || rest.first().copied().unwrap_or("");
        match key {
            "VERSION" => {}
            "VIEWPOINT" => self.viewpoint = viewpoint(rest)?,
            "FIELDS" => {
                self.fields = rest
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
                if rest.len() != self.fields.len() {
                    return err(format!(
                        "{key} has {} entries for {} fields",
                        rest.len(),
                        self.fields.len()
                    ));
                }
                for (f, v) in self.fields.iter_mut().zip(rest) {
                    match key {
                        "SIZE" => f.size = num(v)?,
                        "TYPE" => f.kind = v.bytes().next().unwrap_or(b'?').to_ascii_uppercase(),
                        _ => f.count = num(v)?,
                    }
                }
            }
            "WIDTH" => self.width = Some(num(first())?),
            "HEIGHT" => self.height = Some(num(first())?),
            "POINTS" => self.points = Some(num(first())?),
            other => return err(format!("unknown header line `{}`", clip(other))),
        }
        Ok(())
    }

    /// Width, height and point count, checked against each other and the bound.
    fn size(&self) -> Result<(usize, usize, usize), PcdError> {
        let (w, h) = (self.width.unwrap_or(0), self.height.unwrap_or(1));
        let n = self.points.unwrap_or(w.saturating_mul(h));
        if w.checked_mul(h) != Some(n) {
            return err(format!("WIDTH {w} × HEIGHT {h} is not POINTS {n}"));
        }
        if n > MAX_PCD_POINTS {
            return err(format!(
                "{n} points is more than this reader accepts ({MAX_PCD_POINTS})"
            ));
        }
        for f in &self.fields {
            if !matches!((f.kind, f.size), (b'F', 4 | 8) | (b'I' | b'U', 1 | 2 | 4))
                || f.count == 0
                || f.count > 1 << 16
            {
                return err(format!(
                    "field `{}` has an unsupported type {}{} × {}",
                    clip(&f.name),
                    f.kind as char,
                    f.size,
                    f.count
                ));
            }
        }
        Ok((w, h, n))
    }

    /// Each field's start, counted in `unit`s of the fields before it.
    fn offsets(&self, unit: &dyn Fn(&Field) -> usize) -> Vec<usize> {
        self.fields
            .iter()
            .scan(0, |o, f| {
                let here = *o;
                *o += unit(f);
                Some(here)
            })
            .collect()
    }
}

/// `VIEWPOINT x y z qw qx qy qz` as a pose.
fn viewpoint(rest: &[&str]) -> Result<Pose, PcdError> {
    let v: Vec<f64> = rest.iter().filter_map(|s| s.parse().ok()).collect();
    if v.len() != 7 || rest.len() != 7 || !v.iter().all(|x| x.is_finite()) {
        return err("VIEWPOINT needs seven finite numbers: x y z qw qx qy qz");
    }
    let q = Quat::from_xyzw(v[4], v[5], v[6], v[3]);
    if q.length() < 1e-9 {
        return err("VIEWPOINT's quaternion is zero");
    }
    Ok(Pose::from_parts(Vec3::new(v[0], v[1], v[2]), q.normalize()))
}

/// Which fields a point is read from: x, y, z and the packed colour, if any.
struct Columns {
    xyz: [usize; 3],
    colour: Option<usize>,
    label: Option<usize>,
}

fn too_short<T>(what: &str, have: usize, need: Option<usize>) -> Result<T, PcdError> {
    err(format!(
        "{what} has {have} bytes, the header needs {}",
        need.map_or("more than memory holds".into(), |n| n.to_string())
    ))
}

/// `DATA ascii`: one point per non-empty line.
fn read_ascii(body: &[u8], n: usize, h: &PcdHeader, c: &Columns) -> Result<Decoded, PcdError> {
    let values: usize = h.fields.iter().map(|f| f.count).sum();
    let text = String::from_utf8_lossy(body);
    let at = h.offsets(&|f| f.count);
    let [ix, iy, iz] = c.xyz;
    let mut pts = Vec::new();
    let mut cols = Vec::new();
    let mut labels = Vec::new();
    for (k, line) in text.lines().filter(|l| !l.trim().is_empty()).enumerate() {
        if k >= n {
            break;
        }
        let vals: Vec<&str> = line.split_whitespace().collect();
        if vals.len() < values {
            return err(format!(
                "data line {} has {} values, expected {values}",
                k + 1,
                vals.len()
            ));
        }
        let v = |i: usize| parse_ascii(vals[at[i]], k + 1);
        pts.push(Vec3::new(v(ix)?, v(iy)?, v(iz)?));
        if let Some(ci) = c.colour {
            cols.push(unpack_rgb(ascii_rgb_bits(
                vals[at[ci]],
                &h.fields[ci],
                k + 1,
            )?));
        }
        if let Some(li) = c.label {
            labels.push(label_of(v(li)?, k)?);
        }
    }
    Ok(Decoded {
        points: pts,
        colors: c.colour.map(|_| cols),
        labels: c.label.map(|_| labels),
    })
}

/// `DATA binary`: point-major rows of `stride` bytes.
fn read_binary(body: &[u8], n: usize, h: &PcdHeader, c: &Columns) -> Result<Decoded, PcdError> {
    let stride: usize = h.fields.iter().map(|f| f.size * f.count).sum();
    let need = n.checked_mul(stride);
    if need.is_none_or(|need| body.len() < need) {
        return too_short("binary data", body.len(), need);
    }
    let offs = h.offsets(&|f| f.size * f.count);
    decode(n, &h.fields, c, &|i, k| &body[k * stride + offs[i]..])
}

/// `DATA binary_compressed`: an LZF block of field-major columns (all x, then all y, …).
fn read_compressed(body: &[u8], n: usize, h: &PcdHeader, c: &Columns) -> Result<Decoded, PcdError> {
    if body.len() < 8 {
        return err("compressed header truncated");
    }
    let csize = u32::from_le_bytes([body[0], body[1], body[2], body[3]]) as usize;
    let usize_ = u32::from_le_bytes([body[4], body[5], body[6], body[7]]) as usize;
    // The uncompressed size must be what the header's fields and points make, checked
    // before anything is reserved for it.
    let stride: usize = h.fields.iter().map(|f| f.size * f.count).sum();
    let need = n.checked_mul(stride);
    if need != Some(usize_) {
        return err(format!(
            "compressed block unpacks to {usize_} bytes, the header needs {}",
            need.map_or("more than memory holds".into(), |n| n.to_string())
        ));
    }
    if body.len() - 8 < csize {
        return too_short("compressed data", body.len() - 8, Some(csize));
    }
    let raw = lzf_decompress(&body[8..8 + csize], usize_)?;
    let starts = h.offsets(&|f| f.size * f.count * n);
    let fields = &h.fields;
    decode(n, fields, c, &|i, k| {
        &raw[starts[i] + k * fields[i].size * fields[i].count..]
    })
}

/// Parses PCD bytes: points, colours if the file has an `rgb`/`rgba` field, and the
/// `VIEWPOINT` pose (translation, then the quaternion w x y z, as PCL writes it).
pub fn read_pcd_file(bytes: &[u8]) -> Result<CloudFile, PcdError> {
    let h = parse_pcd_header(bytes)?;
    let (w, height, n) = h.size()?;
    let index = |name: &str| h.fields.iter().position(|f| f.name == name);
    let (Some(ix), Some(iy), Some(iz)) = (index("x"), index("y"), index("z")) else {
        return err("the fields must include x, y and z");
    };
    let colour = index("rgb")
        .or_else(|| index("rgba"))
        .filter(|&i| h.fields[i].size == 4 && h.fields[i].count == 1);
    let label = index("label").filter(|&i| h.fields[i].count == 1);
    let columns = Columns {
        xyz: [ix, iy, iz],
        colour,
        label,
    };
    let body = &bytes[h.body_start..];
    let decoded = match h.data.as_str() {
        "ascii" => read_ascii(body, n, &h, &columns)?,
        "binary" => read_binary(body, n, &h, &columns)?,
        "binary_compressed" => read_compressed(body, n, &h, &columns)?,
        other => return err(format!("unknown DATA encoding `{}`", clip(other))),
    };
    if decoded.points.len() != n {
        return err(format!(
            "{} points read, header says {n}",
            decoded.points.len()
        ));
    }
    Ok(CloudFile {
        cloud: PointCloud {
            width: w,
            height,
            points: decoded.points,
        },
        colors: decoded.colors,
        labels: decoded.labels,
        viewpoint: h.viewpoint,
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
    fn viewpoint_and_colours_round_trip_and_pcl_layouts_read() {
        let cloud = PointCloud::organized(
            2,
            1,
            vec![Vec3::new(1.0, 2.0, 3.0), Vec3::new(-1.0, 0.5, 2.0)],
        )
        .unwrap();
        let viewpoint = Pose::from_parts(
            Vec3::new(0.5, -1.0, 1.5),
            Quat::from_rotation_z(0.7) * Quat::from_rotation_x(-2.0),
        );
        let colours = [[255u8, 0, 10], [1, 2, 3]];
        let labels: Vec<u32> = (0..cloud.points.len() as u32)
            .map(|k| k * 100_003)
            .collect();
        for enc in [PcdEncoding::Ascii, PcdEncoding::Binary] {
            let mut bytes = Vec::new();
            let extras = crate::PcdExtras {
                viewpoint,
                colors: Some(&colours),
                labels: Some(&labels),
            };
            cloud.write_pcd_with(&mut bytes, enc, &extras).unwrap();
            let back = read_pcd_file(&bytes).unwrap();
            assert_eq!(back.colors.as_deref(), Some(&colours[..]), "{enc:?}");
            assert_eq!(back.labels.as_deref(), Some(&labels[..]), "{enc:?}");
            assert!((back.viewpoint.translation - viewpoint.translation).length() < 1e-9);
            assert!(back.viewpoint.rotation.dot(viewpoint.rotation).abs() > 1.0 - 1e-9);
        }
        // mOSD's layout: x y z rgba label, labels U4; a fractional or negative label is
        // an error.
        let mosd = b"VERSION .7\nFIELDS x y z rgba label\nSIZE 4 4 4 4 4\nTYPE F F F U U\nCOUNT 1 1 1 1 1\nWIDTH 2\nHEIGHT 1\nPOINTS 2\nDATA ascii\n1 2 3 0 1\nnan nan nan 0 21\n";
        assert_eq!(read_pcd_file(mosd).unwrap().labels, Some(vec![1, 21]));
        for bad in ["2.5", "-1", "nan"] {
            let text = format!(
                "FIELDS x y z label\nSIZE 4 4 4 4\nTYPE F F F F\nCOUNT 1 1 1 1\nWIDTH 1\nHEIGHT 1\nPOINTS 1\nDATA ascii\n1 2 3 {bad}\n"
            );
            let e = read_pcd_file(text.as_bytes()).unwrap_err();
            assert!(e.0.contains("label"), "{bad}: {e}");
        }
        // PCL's `VIEWPOINT tx ty tz qw qx qy qz`: w first.
        let pcl = b"VERSION 0.7\nFIELDS x y z rgba\nSIZE 4 4 4 4\nTYPE F F F U\nCOUNT 1 1 1 1\nWIDTH 1\nHEIGHT 1\nVIEWPOINT 0 0 0 0 1 0 0\nPOINTS 1\nDATA ascii\n1 2 3 4278255360\n";
        let f = read_pcd_file(pcl).unwrap();
        assert!((f.viewpoint.rotation * Vec3::Y - Vec3::NEG_Y).length() < 1e-12);
        assert_eq!(f.colors.unwrap()[0], [0, 255, 0]);
        // A float `rgb` printed as its bits (an integer), and as a float.
        let bits = (200u32 << 16) | (100 << 8) | 50;
        for tok in [bits.to_string(), format!("{:e}", f32::from_bits(bits))] {
            let text = format!("FIELDS x y z rgb\nWIDTH 1\nPOINTS 1\nDATA ascii\n1 2 3 {tok}\n");
            let f = read_pcd_file(text.as_bytes()).unwrap();
            assert_eq!(f.colors.unwrap()[0], [200, 100, 50], "{tok}");
        }
    }

    #[test]
    fn lies_in_headers_and_values_are_errors() {
        for junk in [
            // A non-numeric value is not a silent NaN (`nan` itself is a number).
            &b"FIELDS x y z\nWIDTH 1\nPOINTS 1\nDATA ascii\n1 two 3\n"[..],
            b"FIELDS x y z\nWIDTH 2\nPOINTS 2\nDATA ascii\n1 2 3\n",
            b"FIELDS x y z\nWIDTH 1\nVIEWPOINT 0 0 0 0 0 0 0\nPOINTS 1\nDATA ascii\n1 2 3\n",
            b"FIELDS x y z\nWIDTH 1\nVIEWPOINT 0 0 nan 1 0 0 0\nPOINTS 1\nDATA ascii\n1 2 3\n",
            // A compressed block that claims far more than the header's points make …
            b"FIELDS x y z\nWIDTH 1\nPOINTS 1\nDATA binary_compressed\n\x02\x00\x00\x00\x00\x00\x00\xff\x00\x00",
            // … or as much as they make, from far too few bytes.
            b"FIELDS x y z\nWIDTH 100000000\nPOINTS 100000000\nDATA binary_compressed\n\x02\x00\x00\x00\x00\x84\xd7\x47\x00\x00",
            // Sizes whose product overflows.
            b"FIELDS x y z\nSIZE 8 8 8\nTYPE F F F\nCOUNT 65536 65536 65536\nWIDTH 100000000\nPOINTS 100000000\nDATA binary\n",
        ] {
            assert!(
                read_pcd_file(junk).is_err(),
                "{:?}",
                String::from_utf8_lossy(junk)
            );
        }
        let nan = read_pcd(b"FIELDS x y z\nWIDTH 1\nPOINTS 1\nDATA ascii\nnan nan nan\n").unwrap();
        assert!(nan.points[0].x.is_nan());
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
