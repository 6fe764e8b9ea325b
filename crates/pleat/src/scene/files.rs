//! Where a scene's own files come from (OBJ meshes, crease patterns): a
//! folder on disk ([`Folder`], the command line) or files held in memory
//! ([`InMemory`]: the app's demos, files dropped on a window or a web page,
//! where there is no file system).

use std::collections::HashMap;
use std::path::{Path, PathBuf};

/// Why a file a scene names cannot be read.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum FileError {
    /// The file system refused the file (missing, a folder, no permission).
    #[error("cannot open the file: {0}")]
    Io(#[from] std::io::Error),
    /// No file held in memory answers to the path.
    #[error("not found: add this file (drop it beside the scene)")]
    NotInMemory,
}

/// Reads the files a scene names by the path written in it.
pub trait SceneFiles {
    /// The bytes of `path`, or why they cannot be had.
    fn read(&self, path: &str) -> Result<Vec<u8>, FileError>;
    /// How `path` is named in errors (the full path on disk).
    fn display(&self, path: &str) -> String {
        path.to_string()
    }
}

/// Paths relative to a folder (the scene file's own).
#[derive(Clone, Copy, Debug)]
pub struct Folder<'a>(pub &'a Path);

impl Folder<'_> {
    fn join(&self, path: &str) -> PathBuf {
        self.0.join(path)
    }
}

impl SceneFiles for Folder<'_> {
    fn read(&self, path: &str) -> Result<Vec<u8>, FileError> {
        Ok(std::fs::read(self.join(path))?)
    }

    fn display(&self, path: &str) -> String {
        self.join(path).display().to_string()
    }
}

/// Files held in memory, found by the path the scene writes or, failing
/// that, by its last component (a scene that says `meshes/bunny.obj` finds
/// a dropped `bunny.obj`).
#[derive(Clone, Debug, Default)]
pub struct InMemory {
    files: HashMap<String, Vec<u8>>,
}

impl InMemory {
    /// Adds (or replaces) the file `name`.
    pub fn insert(&mut self, name: impl Into<String>, bytes: Vec<u8>) {
        self.files.insert(name.into(), bytes);
    }

    /// Whether a file answers to `path`.
    pub fn contains(&self, path: &str) -> bool {
        self.find(path).is_some()
    }

    fn find(&self, path: &str) -> Option<&Vec<u8>> {
        let file_name = |p: &str| p.rsplit(['/', '\\']).next().unwrap_or(p).to_string();
        self.files.get(path).or_else(|| {
            let wanted = file_name(path);
            self.files
                .iter()
                .find(|(name, _)| file_name(name) == wanted)
                .map(|(_, bytes)| bytes)
        })
    }
}

impl SceneFiles for InMemory {
    fn read(&self, path: &str) -> Result<Vec<u8>, FileError> {
        self.find(path).cloned().ok_or(FileError::NotInMemory)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn memory_finds_by_path_then_by_file_name() {
        let mut files = InMemory::default();
        files.insert("bunny.obj", b"v 0 0 0".to_vec());
        files.insert("meshes/teapot.obj", b"v 1 1 1".to_vec());
        assert_eq!(files.read("meshes/bunny.obj").unwrap(), b"v 0 0 0");
        assert_eq!(files.read("meshes/teapot.obj").unwrap(), b"v 1 1 1");
        assert_eq!(files.read("teapot.obj").unwrap(), b"v 1 1 1");
        let missing = files.read("suzanne.obj").unwrap_err();
        assert!(matches!(missing, FileError::NotInMemory), "{missing}");
        assert!(missing.to_string().contains("not found"), "{missing}");
    }

    #[test]
    fn folder_names_the_full_path() {
        let folder = Folder(Path::new("/nonexistent"));
        assert_eq!(folder.display("a.obj"), "/nonexistent/a.obj");
        let e = folder.read("a.obj").unwrap_err();
        assert!(matches!(&e, FileError::Io(io) if io.kind() == std::io::ErrorKind::NotFound));
        assert!(e.to_string().starts_with("cannot open the file"), "{e}");
    }
}
