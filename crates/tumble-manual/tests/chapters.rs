//! The manual's table of contents, its files and its links agree: every
//! chapter file is in `SUMMARY.md` and every entry there exists; every
//! chapter with Rust blocks is included by `src/lib.rs` (so its blocks run as
//! doc-tests); every relative link points at a file of the repository (so
//! the chapters also work as plain Markdown on a code host).

use std::path::{Path, PathBuf};

fn src_dir() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../../docs/manual/src")
}

fn chapters(dir: &Path, out: &mut Vec<PathBuf>) {
    let mut entries: Vec<_> = std::fs::read_dir(dir)
        .unwrap()
        .map(|e| e.unwrap().path())
        .collect();
    entries.sort();
    for path in entries {
        if path.is_dir() {
            chapters(&path, out);
        } else if path.extension().is_some_and(|e| e == "md") && !path.ends_with("SUMMARY.md") {
            out.push(path);
        }
    }
}

/// `(text, target)` of every inline Markdown link `[text](target)`.
fn links(markdown: &str) -> Vec<String> {
    let mut found = Vec::new();
    let mut in_code = false;
    for line in markdown.lines() {
        if line.trim_start().starts_with("```") {
            in_code = !in_code;
            continue;
        }
        if in_code {
            continue;
        }
        let mut rest = line;
        while let Some(i) = rest.find("](") {
            let after = &rest[i + 2..];
            let Some(end) = after.find(')') else { break };
            found.push(after[..end].to_string());
            rest = &after[end..];
        }
    }
    found
}

#[test]
fn summary_lists_every_chapter_and_only_existing_ones() {
    let src = src_dir();
    let summary = std::fs::read_to_string(src.join("SUMMARY.md")).unwrap();
    let listed: Vec<String> = links(&summary);
    let mut files = Vec::new();
    chapters(&src, &mut files);
    for target in &listed {
        assert!(
            src.join(target).is_file(),
            "SUMMARY.md lists {target}, which does not exist"
        );
    }
    for file in &files {
        let rel = file
            .strip_prefix(&src)
            .unwrap()
            .to_string_lossy()
            .replace('\\', "/");
        assert!(listed.contains(&rel), "{rel} is not in SUMMARY.md");
    }
    assert!(files.len() >= 15, "only {} chapters", files.len());
}

#[test]
fn chapters_with_rust_blocks_are_doc_tested() {
    let lib = std::fs::read_to_string(Path::new(env!("CARGO_MANIFEST_DIR")).join("src/lib.rs")).unwrap();
    let mut files = Vec::new();
    chapters(&src_dir(), &mut files);
    let mut rust_chapters = 0;
    for file in files {
        let text = std::fs::read_to_string(&file).unwrap();
        let rel = file
            .strip_prefix(src_dir())
            .unwrap()
            .to_string_lossy()
            .replace('\\', "/");
        if text.contains("```rust") {
            rust_chapters += 1;
            let include = format!("include_str!(\"../../../docs/manual/src/{rel}\")");
            assert!(
                lib.contains(&include),
                "{rel} has Rust blocks but src/lib.rs does not include it"
            );
        }
        // rustdoc would run an unlabelled block as Rust: every block says what it is.
        let mut open = false;
        for (n, line) in text.lines().enumerate() {
            let t = line.trim_start();
            if let Some(info) = t.strip_prefix("```") {
                if !open {
                    assert!(
                        !info.trim().is_empty(),
                        "{rel}:{}: a code block without a language",
                        n + 1
                    );
                }
                open = !open;
            }
        }
        assert!(!open, "{rel}: a code block is not closed");
    }
    assert!(
        rust_chapters >= 6,
        "only {rust_chapters} chapters with Rust blocks"
    );
}

#[test]
fn relative_links_point_at_files() {
    let mut files = Vec::new();
    chapters(&src_dir(), &mut files);
    for file in files {
        let text = std::fs::read_to_string(&file).unwrap();
        let dir = file.parent().unwrap();
        for target in links(&text) {
            if target.contains("://") || target.starts_with('#') || target.starts_with("mailto:") {
                continue;
            }
            let path = target.split('#').next().unwrap();
            assert!(
                dir.join(path).exists(),
                "{}: link to {target}, which does not exist",
                file.display()
            );
        }
    }
}
