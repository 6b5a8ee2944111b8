//! URDF robot descriptions.

use super::*;

pub(super) fn urdf(c: &mut Corpus) {
    let wam = read_repo("robots/wam.urdf");
    let info = |c: &mut Corpus, name: &str, class, expect, text: String| {
        let f = c.file(&format!("urdf/{name}.urdf"), text);
        c.case(
            &format!("urdf-{name}"),
            class,
            expect,
            &["ik", "info", "--robot", &f],
        );
    };
    info(c, "wam", "garbage", Ok, wam.clone());
    c.needs("wam_joint1");
    for cut in [0, 10, 100, 1000, 5000] {
        info(
            c,
            &format!("cut-{cut}"),
            "malformed",
            Error,
            wam[..cut].to_string(),
        );
    }
    let first_joint_origin = wam.find("<origin").unwrap();
    let with = |from: &str, to: &str| {
        assert!(wam.contains(from), "{from}");
        wam.replacen(from, to, 1)
    };
    let limit = &wam[wam.find("<limit").unwrap()..];
    let limit = &limit[..limit.find("/>").unwrap() + 2];
    for (name, text, class) in [
        ("not-xml", "robot { links }".to_string(), "malformed"),
        ("no-robot", "<?xml version=\"1.0\"?><thing/>".to_string(), "malformed"),
        ("no-links", "<robot name=\"r\"></robot>".to_string(), "garbage"),
        ("origin-nan", format!("{}<origin xyz=\"nan 0 0\" rpy=\"0 0 0\"/>{}", &wam[..first_joint_origin], &wam[wam[first_joint_origin..].find("/>").unwrap() + first_joint_origin + 2..]), "garbage"),
        ("limit-inf", with(limit, "<limit lower=\"-inf\" upper=\"inf\" effort=\"1\" velocity=\"1\"/>"), "garbage"),
        ("limit-nan", with(limit, "<limit lower=\"nan\" upper=\"1\" effort=\"1\" velocity=\"1\"/>"), "garbage"),
        ("limit-reversed", with(limit, "<limit lower=\"2\" upper=\"-2\" effort=\"1\" velocity=\"1\"/>"), "garbage"),
        ("limit-1e300", with(limit, "<limit lower=\"-1e300\" upper=\"1e300\" effort=\"1\" velocity=\"1\"/>"), "garbage"),
        ("axis-zero", with("<axis xyz=\"0.0 0.0 1.0\"/>", "<axis xyz=\"0 0 0\"/>"), "garbage"),
        ("axis-nan", with("<axis xyz=\"0.0 0.0 1.0\"/>", "<axis xyz=\"nan 0 1\"/>"), "garbage"),
        ("duplicate-link", wam.replacen("</robot>", "<link name=\"wam_link1\"/></robot>", 1), "garbage"),
        ("missing-parent", wam.replacen("</robot>", "<link name=\"extra\"/><joint name=\"jx\" type=\"fixed\"><parent link=\"nowhere\"/><child link=\"extra\"/></joint></robot>", 1), "garbage"),
        ("cycle", wam.replacen("</robot>", "<joint name=\"jx\" type=\"fixed\"><parent link=\"wam_tool\"/><child link=\"base_link\"/></joint></robot>", 1), "garbage"),
        ("self-loop", wam.replacen("</robot>", "<joint name=\"jx\" type=\"fixed\"><parent link=\"wam_tool\"/><child link=\"wam_tool\"/></joint></robot>", 1), "garbage"),
        ("joint-type-unknown", with("type=\"revolute\"", "type=\"teleport\""), "malformed"),
        ("mesh-escapes", wam.replacen("</robot>", "<link name=\"m\"><collision><geometry><mesh filename=\"package://x/../../../../etc/passwd\"/></geometry></collision></link><joint name=\"jm\" type=\"fixed\"><parent link=\"wam_tool\"/><child link=\"m\"/></joint></robot>", 1), "garbage"),
        ("mesh-dev-zero-unused", wam.replacen("</robot>", "<link name=\"m\"><collision><geometry><mesh filename=\"/dev/zero\"/></geometry></collision></link><joint name=\"jm\" type=\"fixed\"><parent link=\"wam_tool\"/><child link=\"m\"/></joint></robot>", 1), "special-file"),
        ("box-negative", wam.replacen("</robot>", "<link name=\"m\"><collision><geometry><box size=\"-1 1 1\"/></geometry></collision></link><joint name=\"jm\" type=\"fixed\"><parent link=\"wam_tool\"/><child link=\"m\"/></joint></robot>", 1), "garbage"),
        ("entity-expansion", ("<?xml version=\"1.0\"?><!DOCTYPE r [<!ENTITY a \"aaaaaaaaaa\"><!ENTITY b \"&a;&a;&a;&a;&a;&a;&a;&a;&a;&a;\"><!ENTITY c \"&b;&b;&b;&b;&b;&b;&b;&b;&b;&b;\"><!ENTITY d \"&c;&c;&c;&c;&c;&c;&c;&c;&c;&c;\"><!ENTITY e \"&d;&d;&d;&d;&d;&d;&d;&d;&d;&d;\"><!ENTITY f \"&e;&e;&e;&e;&e;&e;&e;&e;&e;&e;\"><!ENTITY g \"&f;&f;&f;&f;&f;&f;&f;&f;&f;&f;\"><!ENTITY h \"&g;&g;&g;&g;&g;&g;&g;&g;&g;&g;\">]><robot name=\"&h;\"><link name=\"a\"/></robot>").to_string(), "unbounded"),
    ] {
        info(c, name, class, Error, text);
    }
    // Deep nesting: 30,000 elements, and a 100,000-deep one inside a link.
    info(
        c,
        "nested-30000",
        "recursion",
        Error,
        format!(
            "<robot name=\"r\">{}{}</robot>",
            "<link name=\"a\">".repeat(30_000),
            "</link>".repeat(30_000)
        ),
    );
    info(
        c,
        "nested-100000-other",
        "recursion",
        Error,
        format!(
            "<robot name=\"r\"><link name=\"a\"/>{}{}</robot>",
            "<x>".repeat(100_000),
            "</x>".repeat(100_000)
        ),
    );
    // A 22 MB URDF: over the size limit, refused before parsing.
    let mut big = String::from("<robot name=\"big\"><link name=\"l0\"/>");
    let mut i = 0;
    while big.len() < 22 << 20 {
        let _ = write!(
            big,
            "<link name=\"l{}\"/><joint name=\"j{i}\" type=\"revolute\"><parent link=\"l{i}\"/><child link=\"l{}\"/><axis xyz=\"0 0 1\"/><limit lower=\"-1\" upper=\"1\" effort=\"1\" velocity=\"1\"/></joint>",
            i + 1,
            i + 1
        );
        i += 1;
    }
    big.push_str("</robot>");
    info(c, "size-22mb", "unbounded", Error, big);
    // A long chain (2,000 joints): legal, loads in bounded time.
    let mut chain = String::from("<robot name=\"chain\"><link name=\"l0\"/>");
    for i in 0..2000 {
        let _ = write!(
            chain,
            "<link name=\"l{}\"/><joint name=\"j{i}\" type=\"revolute\"><parent link=\"l{i}\"/><child link=\"l{}\"/><origin xyz=\"0 0 0.01\"/><axis xyz=\"0 0 1\"/><limit lower=\"-1\" upper=\"1\" effort=\"1\" velocity=\"1\"/></joint>",
            i + 1,
            i + 1
        );
    }
    chain.push_str("</robot>");
    info(c, "chain-2000", "unbounded", Ok, chain);
    c.needs("j1999");
    c.case(
        "urdf-chain-2000-fk",
        "unbounded",
        Ok,
        &[
            "ik",
            "fk",
            "--robot",
            "@urdf/chain-2000.urdf",
            "--base",
            "l0",
            "--tip",
            "l2000",
        ],
    );
    // A description TOML beside a URDF that is malformed.
    let f = c.file("urdf/described.urdf", &wam);
    c.file("urdf/described.toml", "[[arm]]\nname = 5\n");
    c.case(
        "urdf-description-malformed",
        "malformed",
        Error,
        &["ik", "info", "--robot", &f],
    );
    // FK at values that are not joint values.
    for (name, joints, class, expect) in [
        (
            "fk-nan",
            vec!["nan", "0", "0", "0", "0", "0", "0"],
            "garbage",
            Usage,
        ),
        (
            "fk-inf",
            vec!["inf", "0", "0", "0", "0", "0", "0"],
            "garbage",
            Usage,
        ),
        (
            "fk-1e300",
            vec!["1e300", "0", "0", "0", "0", "0", "0"],
            "garbage",
            Error,
        ),
        ("fk-too-few", vec!["0"], "malformed", Error),
        (
            "fk-word",
            vec!["zero", "0", "0", "0", "0", "0", "0"],
            "malformed",
            Usage,
        ),
    ] {
        let mut args = vec!["ik", "fk", "--robot", "wam", "--joints"];
        args.extend(joints);
        c.case(&format!("urdf-{name}"), class, expect, &args);
    }
    c.case(
        "urdf-base-unknown",
        "malformed",
        Error,
        &["ik", "info", "--robot", "wam", "--base", "nowhere"],
    );
}
