//! The demos the app opens with, each a scene shipped in the binary (the
//! project's scene files, meshes and crease patterns are embedded, so the
//! web page needs no file system), reachable from the menu and by URL
//! (`?demo=fold`).

use crate::session::BackendChoice;
use pleat::scene::{InMemory, MeshSpec, Scene, SceneErrors};

/// One entry of the demo menu.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Demo {
    /// Its name in URLs and on the command line.
    pub id: &'static str,
    /// Its name in the menu.
    pub title: &'static str,
    /// The scene file it starts from.
    file: &'static str,
    text: &'static str,
    /// The backend it runs best on, where that is not the GPU.
    pub backend: Option<BackendChoice>,
}

/// Every demo, in menu order; the first is the default.
pub const DEMOS: [Demo; 6] = [
    Demo {
        id: "rigid",
        title: "Cloth on a spinning sphere",
        file: "rotating_sphere.json",
        text: include_str!("../../../scenes/rotating_sphere.json"),
        backend: None,
    },
    Demo {
        id: "fold",
        title: "Paper folding a crease pattern",
        file: "fold_waterbomb.json",
        text: include_str!("../../../scenes/fold_waterbomb.json"),
        backend: None,
    },
    Demo {
        id: "sdf",
        title: "High-resolution cloth on a bunny (SDF)",
        file: "bunny_sdf.json",
        text: include_str!("../../../scenes/bunny_sdf.json"),
        backend: None,
    },
    Demo {
        id: "wind",
        title: "Flag in gusty wind",
        file: "flag.json",
        text: include_str!("../../../scenes/flag.json"),
        backend: None,
    },
    Demo {
        id: "self",
        title: "Cloth folding onto itself",
        file: "fold_onto_itself.json",
        text: include_str!("../../../scenes/fold_onto_itself.json"),
        // Self-contacts on the GPU do not cull by patch yet: on the CPU they
        // are many times faster (BENCHMARKS.md).
        backend: Some(BackendChoice::Cpu),
    },
    Demo {
        id: "drape",
        title: "Scene file (drop one on the window)",
        file: "drape.json",
        text: include_str!("../../../scenes/drape.json"),
        backend: None,
    },
];

/// Cloth vertices along each side in the high-resolution demo.
const HIGH_RESOLUTION: u32 = 128;

impl Demo {
    /// The demo named `id`.
    pub fn find(id: &str) -> Option<Demo> {
        DEMOS.iter().copied().find(|d| d.id == id)
    }

    /// Its scene, and the name errors give it.
    pub fn scene(&self) -> Result<(Scene, String), SceneErrors> {
        let mut scene = Scene::parse(self.text, self.file)?;
        if self.id == "sdf" {
            for cloth in &mut scene.cloths {
                if let MeshSpec::Grid(grid) = &mut cloth.mesh {
                    grid.resolution = [HIGH_RESOLUTION; 2];
                }
            }
            // The GPU's self-contacts rebuild their hash grid every substep:
            // at 128 x 128 they take most of a frame, and a software WebGPU
            // (SwiftShader) falls below a frame a minute. The demo starts
            // without them (the panel's checkbox turns them on); the scene
            // file, at its own resolution, keeps them.
            scene.solver.self_collision.enabled = false;
        }
        Ok((scene, self.file.to_string()))
    }
}

/// A crease pattern the fold demo can fold.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum PatternChoice {
    /// One of pleat's built-in patterns, by name.
    Builtin(&'static str),
    /// A pattern file shipped with the project (in [`shipped_files`]).
    File(&'static str),
}

impl PatternChoice {
    /// Its name in the menu.
    pub fn label(&self) -> String {
        match self {
            PatternChoice::Builtin(name) => format!("{name} (built in)"),
            PatternChoice::File(name) => name.to_string(),
        }
    }

    /// Points the scene's paper at this pattern.
    pub fn apply(&self, scene: &mut Scene) {
        match self {
            PatternChoice::Builtin(name) => set_pattern(scene, None, Some(name)),
            PatternChoice::File(name) => set_pattern(scene, Some(name), None),
        }
    }
}

/// Points the scene's paper at the pattern file `path` or the built-in
/// pattern `builtin`.
pub fn set_pattern(scene: &mut Scene, path: Option<&str>, builtin: Option<&str>) {
    for cloth in &mut scene.cloths {
        if let MeshSpec::Pattern(pattern) = &mut cloth.mesh {
            pattern.path = path.map(str::to_string);
            pattern.builtin = builtin.map(str::to_string);
        }
    }
}

/// The files shipped in the binary: the meshes and crease patterns the
/// scenes name (found by file name), as (name, bytes).
const SHIPPED: [(&str, &[u8]); 15] = [
    (
        "bunny.obj",
        include_bytes!("../../../scenes/meshes/bunny.obj"),
    ),
    (
        "waterbomb_tess.cp",
        include_bytes!("../../../patterns/shared/waterbomb_tess.cp"),
    ),
    (
        "miura_ori.cp",
        include_bytes!("../../../patterns/shared/miura_ori.cp"),
    ),
    (
        "waterbombBase.svg",
        include_bytes!("../../../patterns/shared/waterbombBase.svg"),
    ),
    (
        "birdBase.svg",
        include_bytes!("../../../patterns/shared/birdBase.svg"),
    ),
    (
        "flappingBird.svg",
        include_bytes!("../../../patterns/shared/flappingBird.svg"),
    ),
    (
        "hypar.svg",
        include_bytes!("../../../patterns/shared/hypar.svg"),
    ),
    (
        "miura-ori.svg",
        include_bytes!("../../../patterns/shared/miura-ori.svg"),
    ),
    (
        "singlesquaretwist.svg",
        include_bytes!("../../../patterns/shared/singlesquaretwist.svg"),
    ),
    (
        "kresling.fold",
        include_bytes!("../../../patterns/kresling.fold"),
    ),
    (
        "square-twist.fold",
        include_bytes!("../../../patterns/square-twist.fold"),
    ),
    (
        "reschTriTessellation.svg",
        include_bytes!("../../../patterns/origami-simulator/reschTriTessellation.svg"),
    ),
    (
        "huffmanWaterbomb.svg",
        include_bytes!("../../../patterns/origami-simulator/huffmanWaterbomb.svg"),
    ),
    (
        "traditionalCrane.svg",
        include_bytes!("../../../patterns/origami-simulator/traditionalCrane.svg"),
    ),
    (
        "huffmanTower.svg",
        include_bytes!("../../../patterns/origami-simulator/huffmanTower.svg"),
    ),
];

/// The shipped files, ready for a scene to read.
pub fn shipped_files() -> InMemory {
    let mut files = InMemory::default();
    for (name, bytes) in SHIPPED {
        files.insert(name, bytes.to_vec());
    }
    files
}

/// The patterns of the fold demo's menu: the built-in ones, then the files.
pub fn pattern_choices() -> Vec<PatternChoice> {
    pleat::origami::BUILTIN_NAMES
        .iter()
        .map(|name| PatternChoice::Builtin(name))
        .chain(
            SHIPPED
                .iter()
                .filter(|(name, _)| !name.ends_with(".obj"))
                .map(|(name, _)| PatternChoice::File(name)),
        )
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_demo_builds_from_the_shipped_files() {
        let files = shipped_files();
        for demo in DEMOS {
            let (scene, file) = demo.scene().unwrap();
            let sim = scene.build_with(&files, &file).unwrap();
            assert!(sim.particles.len() > 10, "{}", demo.id);
        }
    }

    #[test]
    fn every_pattern_choice_folds_into_a_sheet() {
        let files = shipped_files();
        let (template, file) = Demo::find("fold").unwrap().scene().unwrap();
        for choice in pattern_choices() {
            let mut scene = template.clone();
            choice.apply(&mut scene);
            let sim = scene.build_with(&files, &file);
            assert!(sim.is_ok(), "{}: {:?}", choice.label(), sim.err());
        }
    }

    #[test]
    fn the_high_resolution_demo_is_high_resolution() {
        let (scene, _) = Demo::find("sdf").unwrap().scene().unwrap();
        let sim = scene
            .build_with(&shipped_files(), "bunny_sdf.json")
            .unwrap();
        assert_eq!(
            sim.particles.len(),
            (HIGH_RESOLUTION * HIGH_RESOLUTION) as usize
        );
    }
}
