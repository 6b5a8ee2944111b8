//! Labelled clouds and ground truths: `label` fields that are not labels, truths that
//! are not on the frame's grid, PNGs that lie about their size, outputs that cannot be
//! written.

use super::*;

/// A 120 × 80 organized table frame with a `label` field holding `label` as text.
fn labelled(label: &str, count: &str) -> Vec<u8> {
    let pts = table_points();
    let mut text = format!(
        "VERSION 0.7\nFIELDS x y z label\nSIZE 4 4 4 4\nTYPE F F F F\nCOUNT 1 1 1 {count}\nWIDTH 120\nHEIGHT 80\nVIEWPOINT 0.5 0 1.6 1 0 0 0\nPOINTS {}\nDATA ascii\n",
        pts.len()
    );
    let extra = if count == "2" {
        format!(" {label}")
    } else {
        String::new()
    };
    for p in &pts {
        text.push_str(&format!("{} {} {} {label}{extra}\n", p[0], p[1], p[2]));
    }
    text.into_bytes()
}

/// A PNG's bytes: the signature and a well-formed IHDR chunk (16-bit grey) claiming
/// `w × h`, then no image data.
fn png_claiming(w: u32, h: u32) -> Vec<u8> {
    let mut chunk = b"IHDR".to_vec();
    chunk.extend_from_slice(&w.to_be_bytes());
    chunk.extend_from_slice(&h.to_be_bytes());
    chunk.extend_from_slice(&[16, 0, 0, 0, 0]);
    let mut v = b"\x89PNG\r\n\x1a\n".to_vec();
    v.extend_from_slice(&13u32.to_be_bytes());
    v.extend_from_slice(&chunk);
    v.extend_from_slice(&crc32(&chunk).to_be_bytes());
    v
}

/// PNG's CRC-32 (ISO 3309), bit by bit: a test needs a few dozen bytes of it.
fn crc32(bytes: &[u8]) -> u32 {
    let mut crc = u32::MAX;
    for &b in bytes {
        crc ^= u32::from(b);
        for _ in 0..8 {
            crc = if crc & 1 == 1 {
                (crc >> 1) ^ 0xEDB8_8320
            } else {
                crc >> 1
            };
        }
    }
    !crc
}

pub(super) fn labels(c: &mut Corpus) {
    let frame = c.file("labels/frame.pcd", labelled("20", "1"));
    let score = |c: &mut Corpus, name: &str, class, expect, truth: &str| {
        c.case(
            &format!("labels-score-{name}"),
            class,
            expect,
            &["perceive", "--cloud", &frame, "--score", truth],
        );
    };
    score(c, "itself", "odd-legal", Ok, &frame);
    c.needs("score: 1 objects");
    for (name, value, class) in [
        ("negative", "-1", "garbage"),
        ("fraction", "2.5", "garbage"),
        ("nan", "nan", "garbage"),
        ("huge", "1e300", "overflow"),
        ("word", "table", "malformed"),
    ] {
        let f = c.file(&format!("labels/{name}.pcd"), labelled(value, "1"));
        c.case(
            &format!("labels-value-{name}"),
            class,
            Error,
            &["perceive", "--cloud", &f],
        );
        c.needs(if name == "word" {
            "not a number"
        } else {
            "label"
        });
    }
    // A two-valued `label` is not PCL's label: skipped by its size, the cloud read.
    let two = c.file("labels/count-2.pcd", labelled("3", "2"));
    c.case(
        "labels-count-2",
        "odd-legal",
        Ok,
        &["perceive", "--cloud", &two],
    );
    score(c, "count-2-is-no-truth", "garbage", Error, &two);
    c.needs("no `label` field");
    let text = c.file("labels/truth.txt", "0 1 2 3\n");
    score(c, "text", "malformed", Error, &text);
    let small = c.file("labels/small.png", png_claiming(10, 10));
    score(c, "png-truncated", "malformed", Error, &small);
    let bomb = c.file("labels/bomb.png", png_claiming(1 << 30, 1 << 30));
    score(c, "png-claims-2^60-pixels", "overflow", Error, &bomb);
    let zero = c.file("labels/zero.png", png_claiming(0, 0));
    score(c, "png-zero-size", "malformed", Error, &zero);
    score(c, "folder", "special-file", Error, "@labels");
    score(c, "dev-zero", "special-file", Error, "/dev/zero");
    c.case(
        "labels-truth-format-alone",
        "malformed",
        Usage,
        &["perceive", "--cloud", &frame, "--truth-format", "mosd"],
    );
    c.case(
        "labels-truth-format-unknown",
        "malformed",
        Usage,
        &[
            "perceive",
            "--cloud",
            &frame,
            "--score",
            &frame,
            "--truth-format",
            "coco",
        ],
    );
    for (name, out) in [("to-folder", "@labels"), ("to-dev-full", "/dev/full")] {
        c.case(
            &format!("labels-write-{name}"),
            "special-file",
            Error,
            &["perceive", "--cloud", &frame, "--labels", out],
        );
        c.needs("--labels");
    }
}
