//! The demo's perception part: seed 002's tabletop pipeline on the simulator's frame and
//! on the nine-object frame scored against its labels.

use super::Tour;
use crate::report::{Report, Section};
use anyhow::Result;
use std::time::Instant;

/// Seed 002's perception on the simulator's frame: the table, the objects on it, and
/// where a new box would fit; then the nine-object frame scored against the
/// simulator's labels.
pub fn perception(
    frame: &tabula_sim::DepthFrame,
    tour: &mut Tour,
    report: &mut Report,
) -> Result<Section> {
    use tabula_geom::Vec2;
    use tabula_perception::freespace::{FreeSpaceMap, FreeSpaceParams};
    use tabula_perception::{TabletopParams, extract, to_world};
    say!(
        tour,
        "8. Perception (PCL's role): the table, its objects and its free space in that frame\n"
    );
    let t0 = Instant::now();
    let cloud = to_world(&frame.world_from_camera, &frame.cloud);
    let t = extract(
        &cloud,
        frame.world_from_camera.translation,
        &TabletopParams::default(),
    )?;
    let ms = t0.elapsed().as_secs_f64() * 1e3;
    say!(
        tour,
        "  table at {:.3} m ({} points, {:.2} m² seen), {} objects, {ms:.1} ms",
        t.table.centroid.z,
        t.table.inliers.len(),
        t.table.area,
        t.objects.len(),
    );
    for o in &t.objects {
        let c = o.obb.center;
        let s = o.obb.half_extents * 2000.0;
        say!(
            tour,
            "    centre ({:.3}, {:.3}), {:.0} × {:.0} × {:.0} mm box, {} points{}",
            c.x,
            c.y,
            s.x,
            s.y,
            s.z,
            o.indices.len(),
            o.top.as_ref().map_or(String::new(), |top| format!(
                ", flat top {:.0} cm²",
                top.area * 1e4
            ))
        );
    }
    let map = FreeSpaceMap::from_tabletop(&t, &cloud.points, &FreeSpaceParams::default())?;
    let footprint = [
        Vec2::new(-0.05, -0.04),
        Vec2::new(0.05, -0.04),
        Vec2::new(0.05, 0.04),
        Vec2::new(-0.05, 0.04),
    ];
    let spot = map.find_place(&footprint, 0.03, t.table.centroid);
    let mut section = Section::new("Perception on the simulator's frame");
    section.text(format!(
        "Seed 002's tabletop pipeline on the overhead Kinect-like frame of the cluttered table: \
         the table ({:.2} m² seen), {} objects with their footprints and minimal-area boxes, the \
         free space, and where a 10 × 8 cm box fits with 3 cm to spare (blue).",
        t.table.area,
        t.objects.len()
    ));
    let (svg, _) = crate::report::frame::top_view(&crate::report::frame::TopView::of_tabletop(
        &t,
        &map,
        spot.map(|p| (p, &[0.1, 0.08][..])),
    ))?;
    let fig = report.svg("top-view", "Top view of the table: free (green), objects (red), unseen (grey), boxes, the free spot (blue)", &svg)?;
    section.figures.push(fig);
    match spot {
        Some(p) => say!(
            tour,
            "  free: {:.2} m²; a 10 × 8 cm box with 3 cm to spare fits at ({:.3}, {:.3}), turned {:.0}°",
            map.free_area(),
            p.position.x,
            p.position.y,
            p.yaw.to_degrees()
        ),
        None => say!(
            tour,
            "  free: {:.2} m²; a 10 × 8 cm box fits nowhere",
            map.free_area()
        ),
    }
    nine_object_frame(tour, &mut section)?;
    Ok(section)
}

/// The nine-object frame (two touching pairs, a stack, 0.5 % outliers) scored
/// against the simulator's labels, into the tour and `section`.
fn nine_object_frame(tour: &mut Tour, section: &mut Section) -> Result<()> {
    use tabula_perception::eval::{Truth, score, table_top_truth};
    use tabula_perception::{TabletopParams, extract, to_world};
    use tabula_sim::generate::{TABLE_TOP, TabletopLayout, tabletop_frame};
    let g = tabletop_frame(0, &TabletopLayout::nine())?;
    let cloud = to_world(&g.frame.world_from_camera, &g.frame.cloud);
    let t0 = Instant::now();
    let t = extract(
        &cloud,
        g.frame.world_from_camera.translation,
        &TabletopParams::default(),
    )?;
    let ms = t0.elapsed().as_secs_f64() * 1e3;
    let finite: Vec<bool> = cloud.points.iter().map(|p| p.is_finite()).collect();
    let labels: Vec<u32> = g.object_labels.iter().map(|o| o.1).collect();
    let s = score(
        &t,
        &Truth {
            finite: &finite,
            labels: &g.frame.labels,
            table_label: g.table_label,
            table_top: &table_top_truth(&cloud.points, TABLE_TOP),
            object_labels: &labels,
        },
        0.8,
        200,
    );
    say!(
        tour,
        "  nine-object frame (two touching pairs, a stack, 0.5 % outliers): {} of {} objects with IoU > 0.8, \
         table precision {:.3} recall {:.3}, {ms:.1} ms (PCL: 1.2 s)\n",
        s.recovered,
        s.objects,
        s.table_precision,
        s.table_recall
    );
    section
        .number(
            "objects recovered (IoU > 0.8) in the nine-object frame",
            format!("{} of {}", s.recovered, s.objects),
        )
        .number(
            "table precision / recall",
            format!("{:.3} / {:.3}", s.table_precision, s.table_recall),
        )
        .number("pipeline time on that frame (ms, wall)", format!("{ms:.1}"));
    Ok(())
}
