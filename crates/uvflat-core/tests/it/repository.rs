//! The repository tests itself: no tracked file refers to a folder outside it, and every test mesh
//! under `tests/data/meshes` is listed in its `MANIFEST.tsv` with a source, a license and the
//! vertex and triangle counts the file really has.

use std::path::Path;
use std::process::Command;
use uvflat_test_support::meshes;

const ROOT: &str = uvflat_test_support::ROOT;

/// The files git tracks, relative to the root; `None` outside a git checkout (a source package).
fn tracked_files() -> Option<Vec<String>> {
    let out = Command::new("git").args(["ls-files", "-z"]).current_dir(ROOT).output().ok()?;
    out.status.success().then(|| {
        String::from_utf8_lossy(&out.stdout).split('\0').filter(|f| !f.is_empty()).map(str::to_string).collect()
    })
}

#[test]
fn no_tracked_file_refers_to_a_folder_beside_the_repository() {
    let Some(files) = tracked_files() else {
        eprintln!("skipped: not a git checkout");
        return;
    };
    // Spelled in two pieces so that this file does not match itself.
    let outside = ["..", "/shared"].concat();
    let offenders: Vec<&String> = files
        .iter()
        .filter(|f| {
            let bytes = std::fs::read(Path::new(ROOT).join(f)).unwrap_or_default();
            String::from_utf8_lossy(&bytes).contains(&outside)
        })
        .collect();
    assert!(offenders.is_empty(), "files referring to {outside}: {offenders:?}");
}

#[test]
fn every_test_mesh_is_in_the_manifest_with_its_source_license_and_true_counts() {
    let manifest = std::fs::read_to_string(Path::new(meshes::DIR).join("MANIFEST.tsv")).expect("MANIFEST.tsv");
    let mut lines = manifest.lines();
    let header: Vec<&str> = lines.next().expect("header").split('\t').collect();
    let column = |name: &str| header.iter().position(|c| *c == name).unwrap_or_else(|| panic!("no {name} column"));
    let (file, source, license, vertices, faces) =
        (column("file"), column("source"), column("license"), column("vertices"), column("faces"));
    let rows: Vec<Vec<&str>> = lines.map(|l| l.split('\t').collect()).collect();
    let files = meshes::names(|_| true);
    assert!(files.len() >= 50, "only {} test meshes", files.len());
    let listed: Vec<String> = rows.iter().map(|r| r[file].trim_end_matches(".gz").to_string()).collect();
    assert_eq!(listed.iter().collect::<std::collections::BTreeSet<_>>(), files.iter().collect(), "MANIFEST vs files");
    for row in &rows {
        let name = row[file].trim_end_matches(".gz");
        assert!(!row[source].trim().is_empty() && !row[license].trim().is_empty(), "{name}: source or license missing");
        let text = std::fs::read_to_string(meshes::unpacked(name)).expect("decompressed mesh");
        let count = |tag: &str| text.lines().filter(|l| l.starts_with(tag)).count().to_string();
        assert_eq!(count("v "), row[vertices], "{name}: vertices");
        assert_eq!(count("f "), row[faces], "{name}: faces");
    }
}

#[test]
fn the_readme_is_a_front_page_and_the_docs_tell_no_history() {
    let readme = std::fs::read_to_string(Path::new(ROOT).join("README.md")).expect("README.md");
    assert!(readme.lines().count() <= 250, "README.md has {} lines", readme.lines().count());
    let mut pages = vec![Path::new(ROOT).join("README.md")];
    let mut stack = vec![Path::new(ROOT).join("docs")];
    while let Some(dir) = stack.pop() {
        for path in std::fs::read_dir(&dir).expect("docs").flatten().map(|e| e.path()) {
            if path.is_dir() {
                stack.push(path);
            } else if path.extension().is_some_and(|e| e == "md") {
                pages.push(path);
            }
        }
    }
    let history = ["issue 1", "issue 2", "issue 3", "issue 4", "issue 5", "issue 6", "issue 7", "issue 8", "issue 9"];
    let narration = ["this session", "this branch"];
    for page in &pages {
        let text = std::fs::read_to_string(page).expect("page").to_lowercase();
        for phrase in history.iter().chain(&narration) {
            assert!(!text.contains(phrase), "{} says {phrase:?}", page.display());
        }
    }
}
