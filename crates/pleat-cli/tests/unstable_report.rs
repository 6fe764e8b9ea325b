//! `pleat run` on a mass-spring cloth too stiff for its step: the run ends
//! without a panic, exits non-zero and report.json says `unstable`.

use std::process::Command;

const SCENE: &str = r#"{
  "name": "stiff_springs",
  "solver": { "kind": "mass_spring", "substeps": 1 },
  "cloths": [{
    "mesh": { "grid": { "resolution": [32, 32], "orientation": "vertical", "center": [0, 1.5, 0] } },
    "material": { "spring_stiffness": { "structural": 50000, "shear": 50000, "bend": 100 } },
    "pins": [ { "corners": ["top_left", "top_right"] } ]
  }]
}"#;

#[test]
fn unstable_run_is_reported_not_crashed() {
    let dir = std::env::temp_dir().join(format!("pleat-unstable-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let scene = dir.join("stiff_springs.json");
    std::fs::write(&scene, SCENE).unwrap();
    let out = dir.join("out");
    let status = Command::new(env!("CARGO_BIN_EXE_pleat"))
        .args(["run", "--frames", "30", "--out"])
        .arg(&out)
        .arg(&scene)
        .output()
        .unwrap();
    assert_eq!(status.status.code(), Some(1), "{status:?}");
    let report: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(out.join("report.json")).unwrap()).unwrap();
    assert_eq!(report["solver"], "mass_spring");
    assert_eq!(report["unstable"], true);
    assert_eq!(report["nan"], true);
    assert!(report["unstable_at"].as_f64().unwrap() < 0.1);
    assert!(report["unstable_particle"].as_u64().unwrap() < 33 * 33);
    // The energy runs away before the positions overflow.
    assert_eq!(report["unstable_kind"], "runaway");
    std::fs::remove_dir_all(&dir).unwrap();
}
