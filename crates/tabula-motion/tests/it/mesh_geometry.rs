//! Collision geometry from the robot's own mesh files: a COLLADA link blocks what it
//! covers, and a collision mesh that cannot be read refuses the robot instead of
//! leaving the link without geometry (a planner would route through it).

use tabula_geom::parry::shape::SharedShape;
use tabula_geom::{Pose, Vec3};
use tabula_motion::{CollisionWorld, WorldParams};
use tabula_robot::{Chain, RobotModel};

/// A 10 cm cube, two triangles a face.
fn cube_dae() -> String {
    let v = "-1 -1 -1 1 -1 -1 1 1 -1 -1 1 -1 -1 -1 1 1 -1 1 1 1 1 -1 1 1".replace('1', "0.05");
    let t = "0 2 1 0 3 2 4 5 6 4 6 7 0 1 5 0 5 4 1 2 6 1 6 5 2 3 7 2 7 6 3 0 4 3 4 7";
    format!(
        r##"<?xml version="1.0"?><COLLADA xmlns="http://www.collada.org/2005/11/COLLADASchema" version="1.4.1">
<asset><unit meter="1" name="meter"/><up_axis>Z_UP</up_axis></asset>
<library_geometries><geometry id="g"><mesh><source id="p"><float_array id="pa" count="24">{v}</float_array>
<technique_common><accessor source="#pa" count="8" stride="3"><param name="X" type="float"/><param name="Y" type="float"/><param name="Z" type="float"/></accessor></technique_common></source>
<vertices id="v"><input semantic="POSITION" source="#p"/></vertices>
<triangles count="12"><input semantic="VERTEX" source="#v" offset="0"/><p>{t}</p></triangles></mesh></geometry></library_geometries>
<library_visual_scenes><visual_scene id="s"><node id="n"><instance_geometry url="#g"/></node></visual_scene></library_visual_scenes>
<scene><instance_visual_scene url="#s"/></scene></COLLADA>"##
    )
}

fn urdf(mesh: &str) -> String {
    format!(
        r#"<robot name="r"><link name="base"/><link name="forearm"><collision><origin xyz="0.5 0 0"/><geometry><mesh filename="{mesh}"/></geometry></collision></link>
<joint name="j" type="revolute"><parent link="base"/><child link="forearm"/><axis xyz="0 0 1"/><limit lower="-1" upper="1" effort="1" velocity="1"/></joint></robot>"#
    )
}

fn world(model: RobotModel) -> Result<CollisionWorld, tabula_motion::WorldError> {
    let chain = Chain::new(&model, "base", "forearm").unwrap();
    let params = WorldParams {
        acm_samples: 10,
        ..Default::default()
    };
    CollisionWorld::new(model, chain, Pose::IDENTITY, None, params)
}

#[test]
fn a_box_through_a_collada_link_is_a_collision_and_a_missing_mesh_an_error() {
    let dir = std::env::temp_dir().join(format!("tabula-dae-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    std::fs::write(dir.join("forearm.dae"), cube_dae()).unwrap();
    std::fs::write(dir.join("r.urdf"), urdf("forearm.dae")).unwrap();
    let model = RobotModel::from_urdf_file(dir.join("r.urdf")).unwrap();
    let mut w = world(model).unwrap();
    // A thin box 4 cm beside the mesh's centre: inside the 10 cm cube (not its hull's
    // padding alone), and clear of it once the arm turns away.
    w.add_object(
        "pole",
        SharedShape::cuboid(0.01, 0.01, 0.3),
        Pose::from_translation(Vec3::new(0.54, 0.0, 0.0)),
    )
    .unwrap();
    assert!(!w.is_valid(&[0.0]), "the DAE link must block the pole");
    assert!(w.is_valid(&[0.8]), "turned away, the link is clear");

    std::fs::write(dir.join("gone.urdf"), urdf("missing.dae")).unwrap();
    let model = RobotModel::from_urdf_file(dir.join("gone.urdf")).unwrap();
    assert_eq!(model.unreadable_meshes.len(), 1, "kinematics still loads");
    let e = world(model).err().expect("an error").to_string();
    assert!(e.contains("forearm") && e.contains("missing.dae"), "{e}");
    std::fs::remove_dir_all(&dir).ok();
}
