//! Paths as the user reads them in messages.
use std::path::{Path, PathBuf};

/// Lexically removes `.` and `name/..` pairs (`jobs/../meshes/a.msh` → `meshes/a.msh`), so the
/// paths in messages read as the user would write them. Leading `..` are kept.
pub fn normalize(p: &Path) -> PathBuf {
    use std::path::Component;
    let mut out: Vec<Component> = Vec::new();
    for c in p.components() {
        match c {
            Component::CurDir => {}
            Component::ParentDir => match out.last() {
                Some(Component::Normal(_)) => {
                    out.pop();
                }
                Some(Component::RootDir) => {}
                _ => out.push(c),
            },
            _ => out.push(c),
        }
    }
    if out.is_empty() {
        PathBuf::from(".")
    } else {
        out.iter().collect()
    }
}

#[cfg(test)]
mod tests {
    use super::normalize;
    use std::path::Path;

    #[test]
    fn normalize_removes_dot_dot_pairs() {
        assert_eq!(normalize(Path::new("jobs/../meshes/a.msh")), Path::new("meshes/a.msh"));
        assert_eq!(normalize(Path::new("../x/./y")), Path::new("../x/y"));
        assert_eq!(normalize(Path::new("/a/../../b")), Path::new("/b"));
        assert_eq!(normalize(Path::new("a/..")), Path::new("."));
    }
}
