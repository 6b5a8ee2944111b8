//! PLY point clouds (ascii, binary little- and big-endian), read and written.
//!
//! The reader keeps the `x y z` properties of the `vertex` element (any numeric type)
//! and skips every other property and element, lists included, so meshes and coloured
//! clouds read as their points. Organized clouds carry PCL's `obj_info num_cols` /
//! `num_rows` lines. Every malformed header or short body is a [`PlyError`]; sizes are
//! checked against the file before anything is allocated.

use crate::input::clip;
use crate::{PointCloud, Vec3};
use std::io::Write;

/// Why a PLY file cannot be read.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[error("PLY: {0}")]
pub struct PlyError(pub String);

fn err<T>(m: impl Into<String>) -> Result<T, PlyError> {
    Err(PlyError(m.into()))
}

/// How to write a PLY body.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum PlyEncoding {
    Ascii,
    BinaryLittleEndian,
}

#[derive(Debug, Clone, Copy, PartialEq)]
enum Scalar {
    I8,
    U8,
    I16,
    U16,
    I32,
    U32,
    F32,
    F64,
}

impl Scalar {
    fn parse(name: &str) -> Option<Self> {
        Some(match name {
            "char" | "int8" => Scalar::I8,
            "uchar" | "uint8" => Scalar::U8,
            "short" | "int16" => Scalar::I16,
            "ushort" | "uint16" => Scalar::U16,
            "int" | "int32" => Scalar::I32,
            "uint" | "uint32" => Scalar::U32,
            "float" | "float32" => Scalar::F32,
            "double" | "float64" => Scalar::F64,
            _ => return None,
        })
    }

    fn size(self) -> usize {
        match self {
            Scalar::I8 | Scalar::U8 => 1,
            Scalar::I16 | Scalar::U16 => 2,
            Scalar::I32 | Scalar::U32 | Scalar::F32 => 4,
            Scalar::F64 => 8,
        }
    }

    fn read(self, b: &[u8], little: bool) -> f64 {
        macro_rules! get {
            ($t:ty, $n:expr) => {{
                let mut a = [0u8; $n];
                a.copy_from_slice(&b[..$n]);
                (if little {
                    <$t>::from_le_bytes(a)
                } else {
                    <$t>::from_be_bytes(a)
                }) as f64
            }};
        }
        match self {
            Scalar::I8 => b[0] as i8 as f64,
            Scalar::U8 => b[0] as f64,
            Scalar::I16 => get!(i16, 2),
            Scalar::U16 => get!(u16, 2),
            Scalar::I32 => get!(i32, 4),
            Scalar::U32 => get!(u32, 4),
            Scalar::F32 => get!(f32, 4),
            Scalar::F64 => get!(f64, 8),
        }
    }
}

#[derive(Debug)]
enum Property {
    Scalar(String, Scalar),
    /// A list: count type, item type.
    List(Scalar, Scalar),
}

#[derive(Debug)]
struct Element {
    name: String,
    count: usize,
    props: Vec<Property>,
}

#[derive(Debug, Clone, Copy, PartialEq)]
enum Format {
    Ascii,
    Binary { little: bool },
}

/// Reads a PLY file's vertices into a cloud (organized when the header says so).
pub fn read_ply(bytes: &[u8]) -> Result<PointCloud, PlyError> {
    read_ply_parts(bytes, false).map(|(cloud, _)| cloud)
}

/// Reads a PLY mesh: its vertices and its faces (`vertex_indices` or `vertex_index`
/// lists of the `face` element), each face a polygon of vertex indices.
pub fn read_ply_mesh(bytes: &[u8]) -> Result<(Vec<Vec3>, Vec<Vec<u32>>), PlyError> {
    read_ply_parts(bytes, true).map(|(cloud, faces)| (cloud.points, faces))
}

/// Where the header ends: after the first line that is exactly `end_header` (a
/// comment may contain the word).
fn header_end(bytes: &[u8]) -> Option<(usize, usize)> {
    let mut start = 0;
    while start < bytes.len() {
        let len = bytes[start..].iter().position(|&b| b == b'\n');
        let line_end = len.map_or(bytes.len(), |l| start + l);
        let line = &bytes[start..line_end];
        let line = line.strip_suffix(b"\r").unwrap_or(line);
        if line.trim_ascii() == b"end_header" {
            return Some((start, (line_end + 1).min(bytes.len())));
        }
        start = line_end + 1;
    }
    None
}

/// What a PLY header says: the body's format, its elements, PCL's organized size.
struct Header {
    format: Format,
    elements: Vec<Element>,
    cols: Option<usize>,
    rows: Option<usize>,
}

/// The header's lines after the `ply` magic, checked.
fn parse_header(header: &str) -> Result<Header, PlyError> {
    let mut lines = header.lines().map(str::trim).filter(|l| !l.is_empty());
    if lines.next() != Some("ply") {
        return err("missing `ply` magic");
    }
    let mut format = None;
    let mut elements: Vec<Element> = Vec::new();
    let (mut cols, mut rows) = (None, None);
    for line in lines {
        let words: Vec<&str> = line.split_whitespace().collect();
        match words.as_slice() {
            ["format", _, version] if *version != "1.0" => {
                return err(format!(
                    "PLY version `{}` (only 1.0 exists)",
                    clip(version, 20)
                ));
            }
            ["format", f, _version] => format = Some(parse_format(f)?),
            ["comment", ..] => {}
            ["obj_info", "num_cols", n] => cols = n.parse::<usize>().ok(),
            ["obj_info", "num_rows", n] => rows = n.parse::<usize>().ok(),
            ["obj_info", ..] => {}
            ["element", name, count] => elements.push(Element {
                name: name.to_string(),
                count: count
                    .parse()
                    .map_err(|_| PlyError(format!("bad element count `{}`", clip(count, 40))))?,
                props: Vec::new(),
            }),
            ["property", "list", c, t, _name] => {
                let (Some(c), Some(t)) = (Scalar::parse(c), Scalar::parse(t)) else {
                    return err(format!("bad list types in `{}`", clip(line, 80)));
                };
                last(&mut elements)?.props.push(Property::List(c, t));
            }
            ["property", t, name] => {
                let t = Scalar::parse(t)
                    .ok_or(PlyError(format!("unknown type in `{}`", clip(line, 80))))?;
                last(&mut elements)?
                    .props
                    .push(Property::Scalar(name.to_string(), t));
            }
            _ => return err(format!("unexpected header line `{}`", clip(line, 80))),
        }
    }
    let format = format.ok_or(PlyError("missing format line".into()))?;
    Ok(Header {
        format,
        elements,
        cols,
        rows,
    })
}

/// The element a `property` line belongs to: the last one declared.
fn last(elements: &mut [Element]) -> Result<&mut Element, PlyError> {
    elements
        .last_mut()
        .ok_or(PlyError("property before any element".into()))
}

fn parse_format(f: &str) -> Result<Format, PlyError> {
    Ok(match f {
        "ascii" => Format::Ascii,
        "binary_little_endian" => Format::Binary { little: true },
        "binary_big_endian" => Format::Binary { little: false },
        other => return err(format!("unknown format `{other}`")),
    })
}

/// The next `n` bytes of a binary body at `offset`, which moves past them.
fn take<'a>(bytes: &'a [u8], offset: &mut usize, n: usize) -> Result<&'a [u8], PlyError> {
    let b = bytes
        .get(*offset..*offset + n)
        .ok_or(PlyError("binary body ends early".into()))?;
    *offset += n;
    Ok(b)
}

/// The body, read one value at a time: ASCII tokens or binary bytes.
enum Body<'a> {
    Ascii(std::str::SplitAsciiWhitespace<'a>),
    Binary {
        bytes: &'a [u8],
        offset: usize,
        little: bool,
    },
}

impl<'a> Body<'a> {
    fn new(body: &'a [u8], format: Format) -> Result<Self, PlyError> {
        Ok(match format {
            Format::Ascii => Body::Ascii(
                std::str::from_utf8(body)
                    .map_err(|_| PlyError("ascii body is not text".into()))?
                    .split_ascii_whitespace(),
            ),
            Format::Binary { little } => Body::Binary {
                bytes: body,
                offset: 0,
                little,
            },
        })
    }

    fn token(tokens: &mut std::str::SplitAsciiWhitespace<'a>) -> Result<&'a str, PlyError> {
        tokens
            .next()
            .ok_or(PlyError("ascii body ends early".into()))
    }

    /// The next scalar of type `t`.
    fn scalar(&mut self, t: Scalar) -> Result<f64, PlyError> {
        match self {
            Body::Ascii(tokens) => parse_number(Self::token(tokens)?, t),
            Body::Binary {
                bytes,
                offset,
                little,
            } => {
                let b = take(bytes, offset, t.size())?;
                Ok(t.read(b, *little))
            }
        }
    }

    /// The next list (count type `c`, items `t`): its items as vertex indices into
    /// `face` when `keep`, else skipped.
    fn list(
        &mut self,
        (c, t): (Scalar, Scalar),
        keep: bool,
        face: &mut Vec<u32>,
    ) -> Result<(), PlyError> {
        match self {
            Body::Ascii(tokens) => {
                let tok = Self::token(tokens)?;
                let n: usize = tok
                    .parse()
                    .map_err(|_| PlyError(format!("bad list length `{}`", clip(tok, 40))))?;
                for _ in 0..n {
                    let item = Self::token(tokens)?;
                    if keep {
                        face.push(item.parse().map_err(|_| {
                            PlyError(format!("bad vertex index `{}`", clip(item, 40)))
                        })?);
                    }
                }
                Ok(())
            }
            Body::Binary {
                bytes,
                offset,
                little,
            } => {
                let b = take(bytes, offset, c.size())?;
                let n = c.read(b, *little);
                if !(n >= 0.0 && n.fract() == 0.0) {
                    return err("bad list length");
                }
                let skip = (n as usize)
                    .checked_mul(t.size())
                    .ok_or(PlyError("list too long".into()))?;
                if offset.checked_add(skip).is_none_or(|end| end > bytes.len()) {
                    return err("binary body ends early");
                }
                if keep {
                    for i in 0..n as usize {
                        let at = *offset + i * t.size();
                        let index = t.read(&bytes[at..at + t.size()], *little);
                        if !(index >= 0.0 && index <= u32::MAX as f64) {
                            return err("bad vertex index");
                        }
                        face.push(index as u32);
                    }
                }
                *offset += skip;
                Ok(())
            }
        }
    }
}

/// Refuses an element count the body cannot hold: the fewest bytes an element takes
/// are its binary row (a list at least its count), or in ASCII a digit and a separator
/// per property. Nothing is reserved for more elements than the body can hold.
fn check_fits(e: &Element, format: Format, body_len: usize) -> Result<(), PlyError> {
    let least: usize = e
        .props
        .iter()
        .map(|p| match (p, format) {
            (_, Format::Ascii) => 2,
            (Property::Scalar(_, t), Format::Binary { .. }) => t.size(),
            (Property::List(c, _), Format::Binary { .. }) => c.size(),
        })
        .sum();
    if e.count.checked_mul(least).is_none_or(|n| n > body_len + 1) {
        return err(format!(
            "{} `{}` elements cannot fit in {} bytes",
            e.count,
            clip(&e.name, 40),
            body_len
        ));
    }
    Ok(())
}

/// What the body's elements give: the vertices' points and, when asked, the faces.
#[derive(Default)]
struct Parts {
    points: Vec<Vec3>,
    faces: Vec<Vec<u32>>,
    found_vertex: bool,
}

impl Parts {
    /// Reads element `e`'s rows, keeping the vertices' x y z and (`want_faces`) the
    /// faces' index lists.
    fn read(&mut self, e: &Element, body: &mut Body, want_faces: bool) -> Result<(), PlyError> {
        let is_vertex = e.name == "vertex";
        let is_face = want_faces && e.name == "face";
        if is_face {
            self.faces.reserve(e.count);
        }
        let xyz: [Option<usize>; 3] = ["x", "y", "z"].map(|axis| {
            e.props
                .iter()
                .position(|p| matches!(p, Property::Scalar(n, _) if n == axis))
        });
        if is_vertex {
            if xyz.iter().any(|k| k.is_none()) {
                return err("vertex element lacks x, y or z");
            }
            self.found_vertex = true;
            self.points.reserve(e.count);
        }
        for _ in 0..e.count {
            let mut v = [f64::NAN; 3];
            let mut face: Vec<u32> = Vec::new();
            for (k, prop) in e.props.iter().enumerate() {
                match prop {
                    Property::Scalar(_, t) => {
                        let value = body.scalar(*t)?;
                        if let Some(axis) = xyz.iter().position(|&a| a == Some(k)) {
                            v[axis] = value;
                        }
                    }
                    Property::List(c, t) => body.list((*c, *t), is_face, &mut face)?,
                }
            }
            if is_vertex {
                self.points.push(Vec3::new(v[0], v[1], v[2]));
            }
            if is_face {
                self.faces.push(face);
            }
        }
        Ok(())
    }
}

fn read_ply_parts(bytes: &[u8], want_faces: bool) -> Result<(PointCloud, Vec<Vec<u32>>), PlyError> {
    let (end, body_start) = header_end(bytes).ok_or(PlyError("no end_header line".into()))?;
    let header =
        std::str::from_utf8(&bytes[..end]).map_err(|_| PlyError("header is not text".into()))?;
    let header = parse_header(header)?;
    let bytes = &bytes[body_start..];
    let mut body = Body::new(bytes, header.format)?;
    let mut parts = Parts::default();
    for e in &header.elements {
        if e.props.is_empty() {
            // No property: nothing stored, whatever the count says.
            continue;
        }
        check_fits(e, header.format, bytes.len())?;
        parts.read(e, &mut body, want_faces)?;
    }
    if !parts.found_vertex {
        return err("no vertex element");
    }
    let points = parts.points;
    let cloud = match (header.cols, header.rows) {
        (Some(w), Some(h)) if w.checked_mul(h) == Some(points.len()) && h > 1 => {
            PointCloud::organized(w, h, points).ok_or(PlyError("bad organized size".into()))?
        }
        _ => PointCloud::unorganized(points),
    };
    Ok((cloud, parts.faces))
}

fn parse_number(tok: &str, t: Scalar) -> Result<f64, PlyError> {
    match t {
        Scalar::F32 | Scalar::F64 => tok
            .parse::<f64>()
            .map_err(|_| PlyError(format!("bad number `{tok}`"))),
        _ => tok
            .parse::<i64>()
            .map(|v| v as f64)
            .map_err(|_| PlyError(format!("bad integer `{tok}`"))),
    }
}

/// Writes a cloud as PLY (float x y z; NaN where a pixel has no point).
pub fn write_ply(
    cloud: &PointCloud,
    out: &mut impl Write,
    encoding: PlyEncoding,
) -> std::io::Result<()> {
    let format = match encoding {
        PlyEncoding::Ascii => "ascii",
        PlyEncoding::BinaryLittleEndian => "binary_little_endian",
    };
    writeln!(out, "ply\nformat {format} 1.0\ncomment written by tabula")?;
    if cloud.is_organized() {
        writeln!(
            out,
            "obj_info num_cols {}\nobj_info num_rows {}",
            cloud.width, cloud.height
        )?;
    }
    writeln!(
        out,
        "element vertex {}\nproperty float x\nproperty float y\nproperty float z\nend_header",
        cloud.points.len()
    )?;
    match encoding {
        PlyEncoding::Ascii => {
            for p in &cloud.points {
                writeln!(out, "{} {} {}", p.x as f32, p.y as f32, p.z as f32)?;
            }
        }
        PlyEncoding::BinaryLittleEndian => cloud.write_xyz_f32_le(out)?,
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_comment_naming_end_header_does_not_end_the_header() {
        let ply = b"ply\nformat ascii 1.0\ncomment see end_header below\nelement vertex 1\n\
                    property float x\nproperty float y\nproperty float z\nend_header\n1 2 3\n";
        let cloud = read_ply(ply).unwrap();
        assert_eq!(cloud.points, vec![Vec3::new(1.0, 2.0, 3.0)]);
    }

    #[test]
    fn element_counts_are_bounded_by_the_body_and_propertyless_ones_skipped() {
        let huge = b"ply\nformat binary_little_endian 1.0\nelement junk 18446744073709551615\n\
                     element vertex 99999999\nproperty float x\nproperty float y\nproperty float z\n\
                     end_header\n\0\0\0\0";
        assert!(
            read_ply(huge)
                .unwrap_err()
                .to_string()
                .contains("cannot fit")
        );
    }

    #[test]
    fn faces_are_read_as_polygons() {
        let ply = b"ply\nformat ascii 1.0\nelement vertex 4\nproperty float x\nproperty float y\n\
                    property float z\nelement face 1\nproperty list uchar int vertex_indices\nend_header\n\
                    0 0 0\n1 0 0\n1 1 0\n0 1 0\n4 0 1 2 3\n";
        let (v, f) = read_ply_mesh(ply).unwrap();
        assert_eq!((v.len(), f), (4, vec![vec![0, 1, 2, 3]]));
    }

    fn sample() -> PointCloud {
        PointCloud::organized(
            2,
            2,
            vec![
                Vec3::new(1.0, 2.0, 3.0),
                Vec3::NAN,
                Vec3::new(-1.0, 0.5, 2.0),
                Vec3::new(0.25, 0.0, -4.0),
            ],
        )
        .unwrap()
    }

    #[test]
    fn round_trips_both_encodings() {
        for enc in [PlyEncoding::Ascii, PlyEncoding::BinaryLittleEndian] {
            let mut bytes = Vec::new();
            write_ply(&sample(), &mut bytes, enc).unwrap();
            let back = read_ply(&bytes).unwrap();
            assert_eq!((back.width, back.height), (2, 2));
            for (a, b) in back.points.iter().zip(&sample().points) {
                assert!(a == b || (a.is_nan() && b.is_nan()), "{a:?} vs {b:?}");
            }
        }
    }

    #[test]
    fn reads_meshes_with_extra_properties_and_big_endian() {
        let ascii = b"ply\nformat ascii 1.0\nelement vertex 3\nproperty double x\nproperty double y\nproperty double z\nproperty uchar red\nelement face 1\nproperty list uchar int vertex_indices\nend_header\n0 0 0 255\n1 0 0 0\n0 1 0 7\n3 0 1 2\n";
        let c = read_ply(ascii).unwrap();
        assert_eq!(c.points.len(), 3);
        assert_eq!(c.points[1], Vec3::X);
        // A face element before the vertices, big-endian shorts.
        let mut be = b"ply\nformat binary_big_endian 1.0\nelement face 1\nproperty list uchar int vertex_indices\nelement vertex 1\nproperty short x\nproperty short y\nproperty short z\nend_header\n".to_vec();
        be.extend_from_slice(&[2, 0, 0, 0, 1, 0, 0, 0, 2]);
        be.extend_from_slice(&[0, 1, 0xff, 0xfe, 0, 3]);
        let c = read_ply(&be).unwrap();
        assert_eq!(c.points, vec![Vec3::new(1.0, -2.0, 3.0)]);
    }

    #[test]
    fn malformed_files_are_errors_not_panics() {
        let mut good = Vec::new();
        write_ply(&sample(), &mut good, PlyEncoding::BinaryLittleEndian).unwrap();
        let cases: Vec<&[u8]> = vec![
            b"",
            b"ply",
            b"ply\nend_header\n",
            b"ply\nformat ascii 1.0\nend_header\n",
            b"ply\nformat ascii 1.0\nelement vertex 2\nproperty float x\nend_header\n1\n2\n",
            b"ply\nformat ascii 1.0\nelement vertex 2\nproperty float x\nproperty float y\nproperty float z\nend_header\n1 2 3\n",
            b"ply\nformat ascii 1.0\nelement vertex 99999999999\nproperty float x\nproperty float y\nproperty float z\nend_header\n",
            b"ply\nformat binary_little_endian 1.0\nelement vertex 1\nproperty list uint float x\nproperty float y\nproperty float z\nend_header\n\xff\xff\xff\xff",
            b"ply\nformat nonsense 1.0\nend_header\n",
            b"ply\nproperty float x\nend_header\n",
            &good[..good.len() - 3],
        ];
        for c in cases {
            assert!(read_ply(c).is_err(), "{:?}", String::from_utf8_lossy(c));
        }
        // Every truncation and every single-byte change of a good file.
        for n in 0..good.len() {
            let _ = read_ply(&good[..n]);
            let mut bad = good.clone();
            bad[n] ^= 0x5a;
            let _ = read_ply(&bad);
        }
    }
}
