//! Robot description packages: xacro, SRDF, package paths.

use super::*;

/// Robots as description packages bring them: xacro (includes, `load_yaml`, `$(find)`,
/// macro and property bombs), SRDF and COLLADA meshes — each refused with what is wrong,
/// within the time and memory bounds.
pub(super) fn robot_packages(c: &mut Corpus) {
    let head = r#"<robot name="r" xmlns:xacro="http://www.ros.org/wiki/xacro">"#;
    let xacro = |c: &mut Corpus, name: &str, class, expect, text: String, needle: &str| {
        let f = c.file(&format!("xacro/{name}.urdf.xacro"), text);
        c.case(
            &format!("xacro-{name}"),
            class,
            expect,
            &["ik", "info", "--robot", &f],
        );
        c.needs(needle);
    };
    let mut macro_bomb = String::from(head);
    for k in 0..10 {
        let call = format!(r#"<xacro:m{} p="${{p}}x"/>"#, k + 1);
        macro_bomb += &format!(
            r#"<xacro:macro name="m{k}" params="p">{}</xacro:macro>"#,
            call.repeat(10)
        );
    }
    macro_bomb += r#"<xacro:macro name="m10" params="p"><link name="${p}"/></xacro:macro><xacro:m0 p="a"/></robot>"#;
    let mut property_bomb =
        format!(r#"{head}<xacro:property name="p0" value="aaaaaaaaaaaaaaaa"/>"#);
    for k in 1..48 {
        property_bomb += &format!(
            r#"<xacro:property name="p{k}" value="${{p{0}}}${{p{0}}}"/>"#,
            k - 1
        );
    }
    property_bomb += r#"<link name="${p47}"/></robot>"#;
    for (name, text, class, needle) in [
        (
            "include-dev-zero",
            format!(r#"{head}<xacro:include filename="/dev/zero"/></robot>"#),
            "special-file",
            "not a regular file",
        ),
        (
            "include-folder",
            format!(r#"{head}<xacro:include filename="/tmp"/></robot>"#),
            "special-file",
            "not a regular file",
        ),
        (
            "yaml-dev-urandom",
            format!(
                r#"{head}<xacro:property name="y" value="${{xacro.load_yaml('/dev/urandom')}}"/><link name="a"/></robot>"#
            ),
            "special-file",
            "not a regular file",
        ),
        (
            "include-self",
            format!(
                r#"{head}<xacro:include filename="include-self.urdf.xacro"/><link name="a"/></robot>"#
            ),
            "recursion",
            "xacro",
        ),
        (
            "macro-recursion",
            format!(
                r#"{head}<xacro:macro name="m" params=""><xacro:m/></xacro:macro><xacro:m/></robot>"#
            ),
            "recursion",
            "xacro",
        ),
        ("macro-bomb", macro_bomb, "unbounded", "xacro"),
        ("property-bomb", property_bomb, "unbounded", "xacro"),
        (
            "find-missing-package",
            format!(r#"{head}<xacro:include filename="$(find no_such_package)/a.xacro"/></robot>"#),
            "special-file",
            "no_such_package",
        ),
        (
            "arg-undefined",
            format!(r#"{head}<link name="$(arg nothing)"/></robot>"#),
            "malformed",
            "nothing",
        ),
        (
            "extension-unknown",
            format!(r#"{head}<link name="$(launch everything)"/></robot>"#),
            "malformed",
            "xacro",
        ),
        (
            "yaml-missing",
            format!(
                r#"{head}<xacro:property name="y" value="${{xacro.load_yaml('gone.yaml')}}"/><link name="${{y}}"/></robot>"#
            ),
            "special-file",
            "gone.yaml",
        ),
    ] {
        xacro(c, name, class, Error, text, needle);
    }
    // A legal xacro with an argument from the command line, and the argument malformed.
    let f = c.file(
        "xacro/arg.urdf.xacro",
        format!(r#"{head}<xacro:arg name="n" default="a"/><link name="$(arg n)_base"/></robot>"#),
    );
    // XML read as YAML is one string: legal, and unused here.
    let f_yaml = c.file(
        "xacro/yaml-not-yaml.urdf.xacro",
        format!(r#"{head}<xacro:property name="y" value="${{xacro.load_yaml('../urdf/wam.urdf')}}"/><link name="a"/></robot>"#),
    );
    c.case(
        "xacro-yaml-not-yaml",
        "odd-legal",
        Ok,
        &["ik", "info", "--robot", &f_yaml],
    );
    c.case(
        "xacro-arg-given",
        "odd-legal",
        Ok,
        &["ik", "info", "--robot", &f, "--xacro-arg", "n:=left"],
    );
    c.needs("left_base");
    c.case(
        "xacro-arg-malformed",
        "malformed",
        Usage,
        &["ik", "info", "--robot", &f, "--xacro-arg", "no-separator"],
    );

    // SRDF against the WAM.
    let wam = c.file("srdf/wam.urdf", read_repo("robots/wam.urdf"));
    let srdf = |c: &mut Corpus, name: &str, class, expect, text: String, needle: &str| {
        let s = c.file(&format!("srdf/{name}.srdf"), text);
        c.case(
            &format!("srdf-{name}"),
            class,
            expect,
            &["ik", "info", "--robot", &wam, "--srdf", &s],
        );
        c.needs(needle);
    };
    let group = r#"<group name="arm"><chain base_link="base_link" tip_link="wam_tool"/></group>"#;
    srdf(
        c,
        "good",
        "garbage",
        Ok,
        format!(
            r#"<robot name="wam">{group}<group_state name="home" group="arm"><joint name="wam_joint1" value="0.1"/></group_state><disable_collisions link1="wam_link1" link2="gone" reason="Never"/></robot>"#
        ),
        "wam_joint1",
    );
    for (name, text, class, needle) in [
        ("group-link-missing", r#"<robot name="wam"><group name="arm"><link name="no_such_link"/></group></robot>"#.to_string(), "garbage", "no_such_link"),
        ("group-chain-missing", r#"<robot name="wam"><group name="arm"><chain base_link="base_link" tip_link="gone_tip"/></group></robot>"#.to_string(), "garbage", "gone_tip"),
        ("group-joint-missing", r#"<robot name="wam"><group name="arm"><joint name="jx"/></group></robot>"#.to_string(), "garbage", "jx"),
        ("subgroup-undefined", r#"<robot name="wam"><group name="all"><group name="ghost"/></group></robot>"#.to_string(), "garbage", "ghost"),
        ("state-nan", format!(r#"<robot name="wam">{group}<group_state name="s" group="arm"><joint name="wam_joint1" value="nan"/></group_state></robot>"#), "garbage", "wam_joint1"),
        ("state-1e300", format!(r#"<robot name="wam">{group}<group_state name="s" group="arm"><joint name="wam_joint1" value="1e300"/></group_state></robot>"#), "garbage", "wam_joint1"),
        ("state-unknown-group", r#"<robot name="wam"><group_state name="s" group="nope"><joint name="wam_joint1" value="0"/></group_state></robot>"#.to_string(), "garbage", "nope"),
        ("state-joint-missing", format!(r#"<robot name="wam">{group}<group_state name="s" group="arm"><joint name="elbow_x" value="0"/></group_state></robot>"#), "garbage", "elbow_x"),
        ("not-xml", "group arm { }".to_string(), "malformed", "SRDF"),
        ("entity-expansion", r#"<?xml version="1.0"?><!DOCTYPE r [<!ENTITY a "aaaaaaaaaa"><!ENTITY b "&a;&a;&a;&a;&a;&a;&a;&a;&a;&a;">]><robot name="&b;"/>"#.to_string(), "unbounded", "SRDF"),
        ("nested-10000", format!("<robot>{}{}</robot>", "<group name=\"g\">".repeat(10_000), "</group>".repeat(10_000)), "recursion", "nest"),
        ("attribute-missing", r#"<robot name="wam"><disable_collisions link1="wam_link1"/></robot>"#.to_string(), "malformed", "link2"),
    ] {
        srdf(c, name, class, Error, text, needle);
    }
    c.case(
        "srdf-dev-zero",
        "special-file",
        Usage,
        &["ik", "info", "--robot", &wam, "--srdf", "/dev/zero"],
    );
    c.needs("regular file");

    // COLLADA meshes.
    let stable = |c: &mut Corpus, name: &str, class, expect, text: String| {
        let f = c.file(&format!("mesh/{name}.dae"), text);
        c.case(
            &format!("dae-{name}"),
            class,
            expect,
            &["stable-poses", "--mesh", &f],
        );
    };
    let dae = |geometry: &str, scene: &str| {
        format!(
            r##"<?xml version="1.0"?><COLLADA xmlns="http://www.collada.org/2005/11/COLLADASchema" version="1.4.1"><library_geometries>{geometry}</library_geometries><library_visual_scenes><visual_scene id="s">{scene}</visual_scene></library_visual_scenes><scene><instance_visual_scene url="#s"/></scene></COLLADA>"##
        )
    };
    let cube = |indices: &str| {
        format!(
            r##"<geometry id="g"><mesh><source id="p"><float_array id="pa" count="24">0 0 0 1 0 0 1 1 0 0 1 0 0 0 1 1 0 1 1 1 1 0 1 1</float_array><technique_common><accessor source="#pa" count="8" stride="3"/></technique_common></source><vertices id="v"><input semantic="POSITION" source="#p"/></vertices><triangles count="12"><input semantic="VERTEX" source="#v" offset="0"/><p>{indices}</p></triangles></mesh></geometry>"##
        )
    };
    let faces = "0 2 1 0 3 2 4 5 6 4 6 7 0 1 5 0 5 4 1 2 6 1 6 5 2 3 7 2 7 6 3 0 4 3 4 7";
    let placed = r##"<node><instance_geometry url="#g"/></node>"##;
    stable(c, "cube", "garbage", Ok, dae(&cube(faces), placed));
    c.needs("most likely");
    for (name, text, class) in [
        (
            "index-past-end",
            dae(&cube(&faces.replacen("0 2 1", "0 2 99", 1)), placed),
            "malformed",
        ),
        (
            "index-negative",
            dae(&cube(&faces.replacen("0 2 1", "0 2 -1", 1)), placed),
            "malformed",
        ),
        (
            "float-word",
            dae(&cube(faces).replace("1 1 1 0 1 1", "1 1 one 0 1 1"), placed),
            "malformed",
        ),
        (
            "vertex-nan",
            dae(&cube(faces).replace("1 1 1 0 1 1", "1 1 nan 0 1 1"), placed),
            "garbage",
        ),
        (
            "url-dangling",
            dae(
                &cube(faces),
                r##"<node><instance_geometry url="#nowhere"/></node>"##,
            ),
            "malformed",
        ),
        (
            "instance-node-loop",
            dae(
                &cube(faces),
                r##"<node id="n"><instance_node url="#n"/></node>"##,
            ),
            "recursion",
        ),
        (
            "matrix-short",
            dae(
                &cube(faces),
                r##"<node><matrix>1 0 0</matrix><instance_geometry url="#g"/></node>"##,
            ),
            "malformed",
        ),
        ("no-triangles", dae("", ""), "garbage"),
        ("not-collada", "<robot/>".to_string(), "malformed"),
        (
            "dtd",
            format!(
                "<!DOCTYPE c [<!ENTITY a \"b\">]>{}",
                dae(&cube(faces), placed)
            ),
            "unbounded",
        ),
    ] {
        stable(c, name, class, Error, text);
    }
}
