//! Files dropped on the window or the page become a scene: a scene file
//! (with the meshes and patterns dropped beside it), a crease pattern
//! (folded as paper), or an OBJ mesh (a cloth draped over it). A bad file
//! gives an error naming the file, and the line or JSON path, and why.

use crate::demos::Demo;
use pleat::mesh::obj::parse_obj;
use pleat::scene::{InMemory, Scene};

/// Edge of the box a dropped mesh is scaled into (m).
const MESH_SIZE: f32 = 0.8;

/// The scene the dropped `files` (name, bytes) make; the meshes and
/// patterns among them are kept in `kept` for scenes that name them.
pub fn scene_from(
    files: Vec<(String, Vec<u8>)>,
    kept: &mut InMemory,
) -> Result<(Scene, String), String> {
    let mut scene_file = None;
    let mut last_other = None;
    for (name, bytes) in files {
        match extension(&name).as_str() {
            "json" => scene_file = Some((name, bytes)),
            "obj" | "cp" | "fold" | "svg" => {
                kept.insert(name.clone(), bytes);
                last_other = Some(name);
            }
            other => {
                return Err(format!(
                    "{name}: cannot open .{other} files: drop a scene (.json), a mesh (.obj) or a crease pattern (.cp, .fold, .svg)"
                ))
            }
        }
    }
    if let Some((name, bytes)) = scene_file {
        let text = String::from_utf8(bytes).map_err(|_| format!("{name}: not UTF-8 text"))?;
        let scene = Scene::parse(&text, &name).map_err(|e| e.to_string())?;
        return Ok((scene, name));
    }
    let name = last_other.ok_or("nothing was dropped")?;
    if extension(&name) == "obj" {
        draped_over(&name, kept)
    } else {
        folded(&name)
    }
}

fn extension(name: &str) -> String {
    name.rsplit_once('.')
        .map(|(_, e)| e.to_ascii_lowercase())
        .unwrap_or_default()
}

/// The fold demo's scene with the pattern `name`.
fn folded(name: &str) -> Result<(Scene, String), String> {
    let (mut scene, _) = Demo::find("fold")
        .expect("a fold demo")
        .scene()
        .map_err(|e| e.to_string())?;
    crate::demos::set_pattern(&mut scene, Some(name), None);
    scene.name = name.to_string();
    Ok((scene, name.to_string()))
}

/// A cloth draped over the mesh `name`, scaled to fit and set on the ground.
fn draped_over(name: &str, files: &InMemory) -> Result<(Scene, String), String> {
    use pleat::scene::SceneFiles;
    let bytes = files.read(name).map_err(|e| format!("{name}: {e}"))?;
    let text = String::from_utf8(bytes).map_err(|_| format!("{name}: not UTF-8 text"))?;
    let mesh = parse_obj(&text, name).map_err(|e| e.to_string())?;
    let (lo, hi) = mesh.positions.iter().fold(
        (glam::Vec3::splat(f32::MAX), glam::Vec3::splat(f32::MIN)),
        |(lo, hi), p| (lo.min(*p), hi.max(*p)),
    );
    let scale = MESH_SIZE / (hi - lo).max_element().max(1e-9);
    let centre = (lo + hi) * 0.5 * scale;
    let translate = [-centre.x, -lo.y * scale, -centre.z];
    let json = format!(
        r#"{{
  "name": {json_name},
  "solver": {{ "kind": "xpbd", "substeps": 10, "iterations": 1, "damping": 0.1 }},
  "cloths": [{{
    "name": "sheet",
    "mesh": {{ "grid": {{ "resolution": [64, 64], "size": [1.2, 1.2], "orientation": "horizontal", "center": [0.0, {height}, 0.0] }} }},
    "material": {{ "density": 0.2, "stretch_compliance": 0.0, "shear_compliance": 1e-6, "bend_compliance": 1.0, "thickness": 0.005 }}
  }}],
  "colliders": [
    {{ "shape": {{ "sdf": {{ "path": {json_name}, "scale": {scale}, "translate": [{tx}, {ty}, {tz}], "cell_size": 0.01 }} }}, "friction": {{ "static": 0.5, "kinetic": 0.4 }} }},
    {{ "shape": {{ "plane": {{}} }}, "friction": {{ "static": 0.6, "kinetic": 0.5 }} }}
  ]
}}"#,
        json_name = serde_json::Value::from(name),
        height = (hi.y - lo.y) * scale + 0.15,
        tx = translate[0],
        ty = translate[1],
        tz = translate[2],
    );
    let scene = Scene::parse(&json, name).map_err(|e| e.to_string())?;
    Ok((scene, name.to_string()))
}

#[cfg(test)]
mod tests {
    use super::*;

    fn drop(files: &[(&str, &[u8])]) -> Result<(Scene, String), String> {
        let files = files
            .iter()
            .map(|(n, b)| (n.to_string(), b.to_vec()))
            .collect();
        scene_from(files, &mut InMemory::default())
    }

    #[test]
    fn a_bad_scene_names_the_file_and_the_json_path() {
        let e = drop(&[("bad.json", br#"{"cloths": [{"mesh": 3}]}"#)]).unwrap_err();
        assert!(
            e.contains("bad.json") && e.contains("cloths[0].mesh"),
            "{e}"
        );
    }

    #[test]
    fn a_bad_pattern_names_the_file_and_the_line() {
        let (scene, file) = drop(&[("broken.cp", b"1 0 0 1\n")]).unwrap();
        let mut files = InMemory::default();
        files.insert("broken.cp", b"1 0 0 1\n".to_vec());
        let e = scene.build_with(&files, &file).err().unwrap().to_string();
        assert!(e.contains("broken.cp") && e.contains("line 1"), "{e}");
    }

    #[test]
    fn unknown_types_are_refused() {
        let e = drop(&[("photo.png", b"\x89PNG")]).unwrap_err();
        assert!(e.contains("photo.png") && e.contains(".png"), "{e}");
    }

    #[test]
    fn a_mesh_is_draped_after_scaling_onto_the_ground() {
        let obj =
            b"v 0 10 0\nv 100 10 0\nv 0 10 100\nv 0 60 0\nf 1 2 3\nf 1 2 4\nf 1 3 4\nf 2 3 4\n";
        let mut kept = InMemory::default();
        let files = vec![("tet.obj".to_string(), obj.to_vec())];
        let (scene, file) = scene_from(files, &mut kept).unwrap();
        let sim = scene.build_with(&kept, &file).unwrap();
        let low = sim.particles.x.iter().map(|p| p.y).fold(f32::MAX, f32::min);
        assert!(low > MESH_SIZE * 0.5 && low < MESH_SIZE, "{low}");
    }
}
