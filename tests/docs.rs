//! Every path the documentation cites exists: each `` `PATH` `` in the README, the
//! CHANGELOG and `docs/` that names a place in the repository (it starts with one of the
//! repository's top-level folders, or with a crate's folder, as `docs/architecture.md` cites
//! them relative to `crates/`) must be a file or folder of this checkout. Glob patterns and
//! placeholders in capitals (`docs/results/<topic>.md`, `FILE`) are left alone.

use std::path::{Path, PathBuf};

const ROOTS: [&str; 7] = [
    "crates/",
    "docs/",
    "src/",
    "tests/",
    "benches/",
    "examples/",
    ".ci/",
];

/// The markdown files to check: the README, the CHANGELOG, and every `.md` under `docs/`.
fn documents(root: &Path) -> Vec<PathBuf> {
    let mut out = vec![root.join("README.md"), root.join("CHANGELOG.md")];
    let mut stack = vec![root.join("docs")];
    while let Some(dir) = stack.pop() {
        for entry in std::fs::read_dir(&dir).expect("docs/ is readable") {
            let path = entry.expect("an entry").path();
            if path.is_dir() {
                stack.push(path);
            } else if path.extension().is_some_and(|e| e == "md") {
                out.push(path);
            }
        }
    }
    out.sort();
    out
}

/// The backquoted spans of `text` that look like repository paths.
fn cited_paths(text: &str) -> Vec<String> {
    let mut out = Vec::new();
    for (i, span) in text.split('`').enumerate() {
        // Odd pieces are inside backquotes; a fenced block's marks make empty pieces.
        if i % 2 == 0 || span.contains(char::is_whitespace) || span.is_empty() {
            continue;
        }
        let span = span.trim_end_matches([':', ',', '.']);
        let crate_dir = span.starts_with("kinetic-") && span.contains('/');
        if !(ROOTS.iter().any(|r| span.starts_with(r)) || crate_dir) {
            continue;
        }
        if span.contains(['*', '<', '>', '{', '}', '$'])
            || span.chars().any(|c| c.is_ascii_uppercase()) && !span.ends_with(".md")
        {
            continue;
        }
        out.push(span.to_string());
    }
    out
}

#[test]
fn every_path_the_docs_cite_exists() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let mut missing = Vec::new();
    let mut checked = 0;
    for doc in documents(root) {
        let text = std::fs::read_to_string(&doc).expect("a readable document");
        for path in cited_paths(&text) {
            checked += 1;
            let found = root.join(&path).exists() || root.join("crates").join(&path).exists();
            if !found {
                missing.push(format!(
                    "{}: `{path}`",
                    doc.strip_prefix(root).unwrap().display()
                ));
            }
        }
    }
    assert!(
        checked > 20,
        "the docs cite {checked} paths: the scan finds too few"
    );
    assert!(
        missing.is_empty(),
        "paths cited that do not exist:\n{}",
        missing.join("\n")
    );
}

#[test]
fn the_scan_finds_paths_and_skips_placeholders() {
    let text = "see `crates/kinetic-core/src/plan.rs`, `docs/results/<topic>.md`, \
                `kinetic-rolling/src/tree.rs`, `cargo test`, `out/frames/` and `docs/FILE`";
    assert_eq!(
        cited_paths(text),
        [
            "crates/kinetic-core/src/plan.rs",
            "kinetic-rolling/src/tree.rs"
        ]
    );
}
