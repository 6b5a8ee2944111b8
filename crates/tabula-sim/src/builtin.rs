//! The scenes shipped with tabula, compiled in: `--scene clutter` works from any folder,
//! not only from a checkout (a file of that name, if there is one, still wins), and
//! `tabula scenes` lists them.

/// A built-in scene: its name and its TOML text (the repository's `scenes/<name>.toml`).
pub struct BuiltinScene {
    pub name: &'static str,
    pub text: &'static str,
}

pub const CLUTTER: &str = include_str!("../../../scenes/clutter.toml");
pub const GOLEM_SHELVES: &str = include_str!("../../../scenes/golem_shelves.toml");
pub const PR2_HOLDING: &str = include_str!("../../../scenes/pr2_holding.toml");
pub const SURFACES: &str = include_str!("../../../scenes/surfaces.toml");
pub const TIDY: &str = include_str!("../../../scenes/tidy.toml");

pub const SCENES: [BuiltinScene; 5] = [
    BuiltinScene {
        name: "clutter",
        text: CLUTTER,
    },
    BuiltinScene {
        name: "golem_shelves",
        text: GOLEM_SHELVES,
    },
    BuiltinScene {
        name: "pr2_holding",
        text: PR2_HOLDING,
    },
    BuiltinScene {
        name: "surfaces",
        text: SURFACES,
    },
    BuiltinScene {
        name: "tidy",
        text: TIDY,
    },
];

/// The built-in scene called `name` (`clutter`, or `clutter.toml`).
pub fn scene(name: &str) -> Option<&'static BuiltinScene> {
    let name = name.strip_suffix(".toml").unwrap_or(name);
    SCENES.iter().find(|s| s.name == name)
}

/// The built-in scenes' names, for messages.
pub fn names() -> String {
    SCENES.map(|s| s.name).join(", ")
}

impl BuiltinScene {
    /// What the scene is: its leading comment, as one line.
    pub fn about(&self) -> String {
        self.text
            .lines()
            .map_while(|l| l.strip_prefix('#'))
            .map(str::trim)
            .collect::<Vec<_>>()
            .join(" ")
    }
}

#[cfg(test)]
mod tests {
    #[test]
    fn every_builtin_scene_parses_and_says_what_it_is() {
        for s in &super::SCENES {
            crate::Scene::parse(s.text, s.name).unwrap();
            assert!(s.about().len() > 20, "{}", s.name);
        }
        assert!(super::scene("clutter.toml").is_some());
        assert!(super::scene("nothing").is_none());
    }
}
