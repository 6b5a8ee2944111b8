//! An object is partly seen only where the image's border cuts it (issue 33): not where
//! it borders pixels without depth (the space beyond a table's far edge), and its
//! neighbours touching it on a crowded table are whole objects of their own.

use super::pieces::tabletop_seen;
use tabula_geom::Vec3;

/// A box's TOML: `size` (m), its centre over the table top (z = 0.72) at `(x, y)`.
fn block(name: &str, size: [f64; 3], (x, y): (f64, f64)) -> String {
    format!(
        "[[object]]\nname = \"{name}\"\nshape = {{ box = {size:?} }}\n\
         pose = {{ xyz = [{x}, {y}, {}] }}\n",
        0.72 + size[2] / 2.0
    )
}

#[test]
fn only_the_image_border_cuts_an_object() {
    // The camera sees nothing beyond the table's far edge (x = 1.1): no depth there. Its
    // view's right border crosses the table at y ≈ −0.43 by the middle.
    let objects = [
        block("cut", [0.06, 0.24, 0.08], (0.75, -0.40)),
        block("beside", [0.06, 0.06, 0.12], (0.75, -0.245)),
        block("next", [0.06, 0.06, 0.10], (0.75, -0.18)),
        block("far", [0.06, 0.06, 0.08], (1.06, 0.0)),
    ]
    .concat();
    let (_, t) = tabletop_seen(&objects, 1.2, [0.15, 0.0, 1.25]);
    let whole: Vec<Vec3> = t.objects.iter().map(|o| o.centroid).collect();
    let cut: Vec<Vec3> = t.partial.iter().map(|o| o.centroid).collect();
    let near = |c: &Vec3, x: f64, y: f64| (c.x - x).abs() < 0.05 && (c.y - y).abs() < 0.05;
    assert_eq!(cut.len(), 1, "whole {whole:?}, cut {cut:?}");
    assert!(cut[0].y < -0.3, "{cut:?}");
    for (name, x, y) in [
        ("beside", 0.75, -0.245),
        ("next", 0.75, -0.18),
        ("far", 1.06, 0.0),
    ] {
        assert!(
            whole.iter().any(|c| near(c, x, y)),
            "{name} not whole: {whole:?}, cut {cut:?}"
        );
    }
}
