//! What `tabula perceive` draws: the top view of a frame (the table, the objects, the
//! free space), the frame's image coloured by segment, and the report page.

use anyhow::{Context, Result};
use std::path::Path;
use tabula_geom::{PointCloud, Vec3};
use tabula_perception::frame::{Perceived, box_yaw, mean_colour};
use tabula_perception::freespace::{Cell, FreeSpaceMap, Placement};
use tabula_perception::support::FrameSource;
use tabula_perception::tabletop::{TableObject, Tabletop};

/// What a top view shows: a surface's occupancy grid (free green, objects red, unseen
/// grey), its outline, object outlines and boxes, labels, and a chosen spot (blue).
/// Every polygon is in the world; the view is the surface's plane seen from above.
pub struct TopView<'a> {
    pub map: &'a FreeSpaceMap,
    pub outline: &'a [Vec3],
    pub objects: Vec<Vec<Vec3>>,
    pub boxes: Vec<Vec<Vec3>>,
    pub labels: Vec<(String, Vec3)>,
    pub spot: Option<Vec<Vec3>>,
}

impl<'a> TopView<'a> {
    /// The tabletop pipeline's result: footprints, minimal-area boxes, numbers, and a
    /// footprint of `size` placed where the map found room.
    pub fn of_tabletop(
        t: &'a Tabletop,
        map: &'a FreeSpaceMap,
        placement: Option<(Placement, &[f64])>,
    ) -> Self {
        let boxes = t
            .objects
            .iter()
            .map(|o| {
                let b = o.obb;
                [(-1.0, -1.0), (1.0, -1.0), (1.0, 1.0), (-1.0, 1.0)]
                    .iter()
                    .map(|(sx, sy)| {
                        b.center
                            + b.axes[0] * (sx * b.half_extents.x)
                            + b.axes[1] * (sy * b.half_extents.y)
                    })
                    .collect()
            })
            .collect();
        let spot = placement.map(|(p, size)| {
            let f = p.world_from_footprint;
            let (x, y) = (size[0] / 2.0, size[1] / 2.0);
            [(-x, -y), (x, -y), (x, y), (-x, y)]
                .iter()
                .map(|(a, b)| f * Vec3::new(*a, *b, 0.0))
                .collect()
        });
        Self {
            map,
            outline: &t.table.hull,
            objects: t.objects.iter().map(|o| o.footprint.clone()).collect(),
            boxes,
            labels: t
                .objects
                .iter()
                .enumerate()
                .map(|(n, o)| (format!("{}", n + 1), o.centroid))
                .collect(),
            spot,
        }
    }
}

/// A top view drawn with plotters: the SVG and a PNG of it (the PNG without text:
/// plotters' bitmap backend would need a font).
pub fn top_view(view: &TopView<'_>) -> Result<(String, image::RgbImage)> {
    const PX_PER_M: f64 = 400.0;
    let map = view.map;
    let (w_m, h_m) = (
        map.nx as f64 * map.resolution,
        map.ny as f64 * map.resolution,
    );
    let size = (
        ((w_m * PX_PER_M) as u32).clamp(120, 1600),
        ((h_m * PX_PER_M) as u32).clamp(120, 1600),
    );
    let mut svg = String::new();
    draw_top_view(
        plotters::prelude::SVGBackend::with_string(&mut svg, (size.0 + 70, size.1 + 60)),
        view,
        true,
    )?;
    let mut buf = vec![255u8; (size.0 * size.1 * 3) as usize];
    draw_top_view(
        plotters::prelude::BitMapBackend::with_buffer(&mut buf, size),
        view,
        false,
    )?;
    let png = image::RgbImage::from_raw(size.0, size.1, buf)
        .context("top view: buffer of the wrong size")?;
    Ok((svg, png))
}

fn draw_top_view<DB: plotters::prelude::DrawingBackend>(
    backend: DB,
    view: &TopView<'_>,
    labels: bool,
) -> Result<()> {
    use plotters::prelude::*;
    let map = view.map;
    let err = |e: &dyn std::fmt::Display| anyhow::anyhow!("top view: {e}");
    let root = backend.into_drawing_area();
    root.fill(&WHITE).map_err(|e| err(&e))?;
    let (x0, y0) = (map.lo.x, map.lo.y);
    let (x1, y1) = (
        x0 + map.nx as f64 * map.resolution,
        y0 + map.ny as f64 * map.resolution,
    );
    let mut builder = ChartBuilder::on(&root);
    if labels {
        builder
            .margin(8)
            .x_label_area_size(36)
            .y_label_area_size(50);
    }
    let mut chart = builder
        .build_cartesian_2d(x0..x1, y0..y1)
        .map_err(|e| err(&e))?;
    if labels {
        chart
            .configure_mesh()
            .disable_mesh()
            .x_desc("u (m, in the surface's plane)")
            .y_desc("v (m)")
            .draw()
            .map_err(|e| err(&e))?;
    }
    // Runs of equal cells along a row become one rectangle.
    let colour = |c: &Cell| match c {
        Cell::Outside => None,
        Cell::Free => Some(RGBColor(200, 235, 200)),
        Cell::Occupied => Some(RGBColor(225, 120, 110)),
        Cell::Unknown => Some(RGBColor(190, 190, 190)),
    };
    let r = map.resolution;
    let mut cells = Vec::new();
    for j in 0..map.ny {
        let mut i = 0;
        while i < map.nx {
            let c = &map.cells[j * map.nx + i];
            let mut end = i + 1;
            while end < map.nx && map.cells[j * map.nx + end] == *c {
                end += 1;
            }
            if let Some(col) = colour(c) {
                cells.push(Rectangle::new(
                    [
                        (x0 + i as f64 * r, y0 + j as f64 * r),
                        // A hair taller than the row: no seam between rows once drawn.
                        (x0 + end as f64 * r, y0 + (j as f64 + 1.05) * r),
                    ],
                    col.filled(),
                ));
            }
            i = end;
        }
    }
    chart.draw_series(cells).map_err(|e| err(&e))?;
    let closed = |pts: &[Vec3]| -> Vec<(f64, f64)> {
        let mut q: Vec<(f64, f64)> = pts
            .iter()
            .map(|p| {
                let v = map.to_plane(*p);
                (v.x, v.y)
            })
            .collect();
        if let Some(first) = q.first().copied() {
            q.push(first);
        }
        q
    };
    let mut lines = vec![PathElement::new(
        closed(view.outline),
        RGBColor(60, 60, 60).stroke_width(2),
    )];
    for o in &view.objects {
        lines.push(PathElement::new(
            closed(o),
            RGBColor(150, 30, 30).stroke_width(2),
        ));
    }
    for b in &view.boxes {
        lines.push(PathElement::new(
            closed(b),
            RGBColor(40, 40, 40).stroke_width(1),
        ));
    }
    chart.draw_series(lines).map_err(|e| err(&e))?;
    if let Some(spot) = &view.spot {
        let rect = closed(spot);
        chart
            .draw_series([Polygon::new(rect.clone(), RGBColor(120, 160, 240).filled())])
            .map_err(|e| err(&e))?;
        chart
            .draw_series([PathElement::new(
                rect,
                RGBColor(20, 40, 160).stroke_width(2),
            )])
            .map_err(|e| err(&e))?;
    }
    if labels {
        chart
            .draw_series(view.labels.iter().map(|(text, at)| {
                let c = map.to_plane(*at);
                Text::new(text.clone(), (c.x, c.y), ("sans-serif", 13))
            }))
            .map_err(|e| err(&e))?;
    }
    root.present().map_err(|e| err(&e))?;
    Ok(())
}

/// `perceive --report DIR`: the top view (top.svg, top.png), the labelled frame
/// (frame.png) and index.html with the numbers.
pub fn perceive_page(
    dir: &Path,
    t: &Tabletop,
    map: &FreeSpaceMap,
    placement: Option<(Placement, &[f64])>,
    frame: Option<(&PointCloud, Option<&[[u8; 3]]>)>,
    json: &serde_json::Value,
) -> Result<()> {
    let mut report = super::Report::create(dir, "tabula perceive")?;
    let mut s = super::Section::new("The table, its objects and free space");
    s.number("objects", t.objects.len())
        .number("objects cut by the frame's edge", t.partial.len())
        .number("table area seen (m²)", format!("{:.3}", t.table.area))
        .number("free area (m²)", format!("{:.3}", map.free_area()));
    if let Some((p, size)) = placement {
        s.number(
            "free spot",
            format!(
                "{:.2} × {:.2} m footprint at ({:.3}, {:.3}, {:.3}), turned {:.0}°, {:.0} mm clear",
                size[0],
                size[1],
                p.position.x,
                p.position.y,
                p.position.z,
                p.yaw.to_degrees(),
                p.clearance * 1e3
            ),
        );
    }
    let (svg, png) = top_view(&TopView::of_tabletop(t, map, placement))?;
    std::fs::write(dir.join("top.svg"), &svg).context("cannot write top.svg")?;
    png.save(dir.join("top.png"))
        .context("cannot write top.png")?;
    s.figures.push(super::Figure {
        file: "top.svg".into(),
        caption:
            "Top view: free (green), objects (red), unseen (grey), boxes, the free spot (blue)"
                .into(),
    });
    if let Some((cloud, colors)) = frame
        && cloud.is_organized()
    {
        write_frame_image(dir, cloud, colors, t)?;
        s.figures.push(super::Figure {
            file: "frame.png".into(),
            caption: "The frame: the support green, each object in its own colour".into(),
        });
    }
    report.sections.push(s);
    report.finish(json)?;
    Ok(())
}

/// Object colours in the labelled frame: distinct hues, repeated after twelve.
const LABEL_COLOURS: [[u8; 3]; 12] = [
    [230, 25, 75],
    [60, 180, 75],
    [255, 225, 25],
    [0, 130, 200],
    [245, 130, 48],
    [145, 30, 180],
    [70, 240, 240],
    [240, 50, 230],
    [210, 245, 60],
    [250, 190, 212],
    [0, 128, 128],
    [170, 110, 40],
];

/// The organized frame as the sensor saw it (its colours, or grey by depth), the
/// support tinted green and each object in its own colour: `frame.png`.
fn write_frame_image(
    dir: &Path,
    cloud: &PointCloud,
    colors: Option<&[[u8; 3]]>,
    t: &Tabletop,
) -> Result<()> {
    let (w, h) = (cloud.width, cloud.height);
    let (lo, hi) = cloud
        .points
        .iter()
        .filter(|p| p.is_finite())
        .map(|p| p.z)
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), z| {
            (a.min(z), b.max(z))
        });
    let base = |i: usize| -> [u8; 3] {
        let p = cloud.points[i];
        if !p.is_finite() {
            return [0, 0, 0];
        }
        match colors {
            Some(c) => c[i],
            None => {
                let g = (60.0 + 160.0 * (p.z - lo) / (hi - lo).max(1e-9)) as u8;
                [g, g, g]
            }
        }
    };
    let mut label = vec![None; w * h];
    for &i in &t.table.inliers {
        label[i] = Some([40u8, 200, 60]);
    }
    for (k, o) in t.objects.iter().enumerate() {
        for &i in &o.indices {
            label[i] = Some(LABEL_COLOURS[k % LABEL_COLOURS.len()]);
        }
    }
    // Objects cut by the frame's edge: white.
    for &i in t.partial.iter().flat_map(|o| &o.indices) {
        label[i] = Some([255, 255, 255]);
    }
    let pixels: Vec<u8> = label
        .iter()
        .enumerate()
        .flat_map(|(i, l)| {
            let b = base(i);
            match l {
                Some(l) => [0, 1, 2].map(|c| ((b[c] as u16 + 2 * l[c] as u16) / 3) as u8),
                None => b,
            }
        })
        .collect();
    let img = image::RgbImage::from_raw(w as u32, h as u32, pixels)
        .context("frame.png: the frame's size and its points disagree")?;
    img.save(dir.join("frame.png"))
        .context("cannot write frame.png")?;
    Ok(())
}

/// What `tabula perceive` prints without `--json`.
pub fn perceived_lines(
    perceived: &Perceived,
    placement: Option<Option<Placement>>,
    colors: Option<&[[u8; 3]]>,
) -> Vec<String> {
    let mut lines = Vec::new();
    let Perceived {
        framing,
        result,
        surfaces,
        map,
        removed,
        ms,
        ..
    } = perceived;
    let t = &framing.world_from_cloud;
    match framing.source {
        FrameSource::GivenPose => lines.push("frame: the world, from the sensor pose given".to_string()),
        FrameSource::Viewpoint => lines.push(format!(
            "frame: the cloud's own (z up), sensor at ({:.3}, {:.3}, {:.3}) from its VIEWPOINT",
            framing.eye.x, framing.eye.y, framing.eye.z
        )),
        FrameSource::Support => lines.push(format!(
            "frame: the support's (z up, support at z = 0, sensor {:.3} m above it looking along +x); \
             world_from_cloud ({:.3}, {:.3}, {:.3}) ({:.4}, {:.4}, {:.4}, {:.4})",
            framing.eye.z,
            t.translation.x,
            t.translation.y,
            t.translation.z,
            t.rotation.x,
            t.rotation.y,
            t.rotation.z,
            t.rotation.w
        )),
    }
    if framing.support.as_ref().is_some_and(|s| s.hint_flipped) {
        lines.push(
            "  (nothing faced the up hint; the support faces its opposite: the cloud is taken \
             as saved y-up — `--up` overrides)"
                .to_string(),
        );
    }
    lines.push(format!(
        "table: {} points, height {:.3} m, normal ({:.3}, {:.3}, {:.3}), {:.2} m² seen, hull {:.2} m² ({} corners); free {:.2} m²",
        result.table.inliers.len(),
        result.table.centroid.z,
        result.plane.normal.x,
        result.plane.normal.y,
        result.plane.normal.z,
        result.table.area,
        result.table.hull_area,
        result.table.hull.len(),
        map.free_area()
    ));
    if *removed > 0 {
        lines.push(format!("self-filter: {removed} robot points removed"));
    }
    lines.push("surfaces (all horizontal surfaces in reach):".to_string());
    for s in &surfaces.surfaces {
        lines.push(format!(
            "  at {:.3} m: {} points, {:.2} m², centroid ({:.3}, {:.3}, {:.3})",
            s.centroid.z,
            s.inliers.len(),
            s.area,
            s.centroid.x,
            s.centroid.y,
            s.centroid.z
        ));
    }
    let line = |i: usize, o: &TableObject| {
        let (c, s) = (o.obb.center, o.obb.half_extents * 2.0);
        format!(
            "  {}: {} points, box centre ({:.3}, {:.3}, {:.3}), {:.3} × {:.3} × {:.3} m, yaw {:.0}°{}{}",
            i + 1,
            o.indices.len(),
            c.x,
            c.y,
            c.z,
            s.x,
            s.y,
            s.z,
            box_yaw(o).to_degrees(),
            o.top.as_ref().map_or(String::new(), |t| format!(
                ", flat top {:.0} cm²",
                t.area * 1e4
            )),
            colors.map_or(String::new(), |c| {
                let [r, g, b] = mean_colour(c, &o.indices);
                format!(", colour #{r:02x}{g:02x}{b:02x}")
            })
        )
    };
    lines.push("objects:".to_string());
    for (i, o) in result.objects.iter().enumerate() {
        lines.push(line(i, o));
    }
    if !result.partial.is_empty() {
        lines.push("cut by the frame's edge (partly seen):".to_string());
        for (i, o) in result.partial.iter().enumerate() {
            lines.push(line(i, o));
        }
    }
    match placement {
        Some(Some(p)) => lines.push(format!(
            "place: ({:.3}, {:.3}, {:.3}) yaw {:.0}°, {:.3} m clear",
            p.position.x,
            p.position.y,
            p.position.z,
            p.yaw.to_degrees(),
            p.clearance
        )),
        Some(None) => lines
            .push("place: the footprint fits nowhere on the table with that margin".to_string()),
        None => {}
    }
    lines.push(format!(
        "{ms:.1} ms (outliers {:.1}, planes {:.1}, prism {:.1}, normals {:.1}, segmentation {:.1}, objects {:.1})",
        result.times.outliers,
        result.times.planes,
        result.times.prism,
        result.times.normals,
        result.times.segmentation,
        result.times.objects
    ));
    lines
}
