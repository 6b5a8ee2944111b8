//! URDF pieces the robot tests share.

/// `<robot name="arm">` opened, a `base` link and `n` revolute joints `j1…jn` each 0.2 m
/// up from the last (axes alternating between z and a tilted y+z), ending at `link{n}`.
pub fn revolute_chain(n: usize) -> String {
    let mut s = String::from(r#"<robot name="arm"><link name="base"/>"#);
    let mut parent = "base".to_string();
    for k in 1..=n {
        s += &format!(
            r#"<link name="link{k}"/><joint name="j{k}" type="revolute"><parent link="{parent}"/><child link="link{k}"/><origin xyz="0 0 0.2"/><axis xyz="0 {y} 1"/><limit lower="-2" upper="2" effort="1" velocity="1"/></joint>"#,
            y = k % 2
        );
        parent = format!("link{k}");
    }
    s
}
