//! The README and `docs/`: the README fits on a screen and starts with the two commands, every
//! relative link and anchor resolves, no table cell holds a page of text, and the commands the
//! docs give are whole (the MeshLab plugin's CMake configure names its source folder).

use std::collections::BTreeSet;
use std::path::{Path, PathBuf};

fn root() -> &'static Path {
    Path::new(env!("CARGO_MANIFEST_DIR"))
}

fn read(path: &Path) -> String {
    std::fs::read_to_string(path).unwrap_or_else(|e| panic!("{}: {e}", path.display()))
}

/// README.md and every Markdown page under docs/.
fn pages() -> Vec<PathBuf> {
    let mut v = vec![root().join("README.md")];
    let mut docs: Vec<PathBuf> = std::fs::read_dir(root().join("docs"))
        .unwrap()
        .map(|e| e.unwrap().path())
        .filter(|p| p.extension().is_some_and(|e| e == "md"))
        .collect();
    docs.sort();
    v.extend(docs);
    v
}

/// The lines outside fenced code blocks, with their 1-based numbers.
fn prose(text: &str) -> Vec<(usize, &str)> {
    let mut fenced = false;
    let mut out = Vec::new();
    for (i, line) in text.lines().enumerate() {
        if line.trim_start().starts_with("```") {
            fenced = !fenced;
            continue;
        }
        if !fenced {
            out.push((i + 1, line));
        }
    }
    out
}

/// GitHub's anchor for a heading: lower case, punctuation dropped, spaces to hyphens.
fn slug(heading: &str) -> String {
    heading
        .trim()
        .to_lowercase()
        .chars()
        .filter(|c| c.is_alphanumeric() || *c == ' ' || *c == '-' || *c == '_')
        .map(|c| if c == ' ' { '-' } else { c })
        .collect()
}

fn anchors(text: &str) -> BTreeSet<String> {
    prose(text)
        .into_iter()
        .filter_map(|(_, l)| l.strip_prefix('#'))
        .map(|l| slug(l.trim_start_matches('#')))
        .collect()
}

/// The targets of Markdown links and images `[text](target)` on a line.
fn link_targets(line: &str) -> Vec<&str> {
    let mut out = Vec::new();
    let mut rest = line;
    while let Some(i) = rest.find("](") {
        let after = &rest[i + 2..];
        let Some(end) = after.find(')') else { break };
        out.push(&after[..end]);
        rest = &after[end..];
    }
    out
}

#[test]
fn readme_fits_on_a_screen_and_starts_with_the_two_commands() {
    let text = read(&root().join("README.md"));
    let lines = text.lines().count();
    assert!(
        lines <= 50,
        "README.md has {lines} lines; at most 50 fit on a screen"
    );
    let first_block = text
        .split("```")
        .nth(1)
        .expect("README.md has no code block");
    for command in ["cargo run --release -- demo", "cargo xtask test"] {
        assert!(
            first_block.contains(command),
            "the README's first code block does not give `{command}`"
        );
    }
    for page in [
        "docs/cli.md",
        "docs/c.md",
        "docs/blender.md",
        "docs/meshlab.md",
        "docs/windows.md",
        "docs/benchmarks.md",
        "docs/ARCHITECTURE.md",
    ] {
        assert!(
            text.contains(&format!("({page})")),
            "the README does not link {page}"
        );
    }
    let images = link_targets(&text)
        .into_iter()
        .filter(|t| t.starts_with("docs/images/"))
        .count();
    assert!(
        (2..=3).contains(&images),
        "the README shows {images} pictures, not two or three"
    );
}

#[test]
fn every_relative_link_and_anchor_resolves() {
    let mut broken = Vec::new();
    for page in pages() {
        let text = read(&page);
        for (n, line) in prose(&text) {
            for target in link_targets(line) {
                if target.contains("://") || target.starts_with("mailto:") {
                    continue;
                }
                let (file, anchor) = match target.split_once('#') {
                    Some((f, a)) => (f, Some(a)),
                    None => (target, None),
                };
                let resolved = if file.is_empty() {
                    page.clone()
                } else {
                    page.parent().unwrap().join(file)
                };
                if !resolved.exists() {
                    broken.push(format!("{}:{n}: {target}: no such file", page.display()));
                    continue;
                }
                if let Some(anchor) = anchor {
                    if !anchors(&read(&resolved)).contains(anchor) {
                        broken.push(format!("{}:{n}: {target}: no such heading", page.display()));
                    }
                }
            }
        }
    }
    assert!(broken.is_empty(), "broken links:\n{}", broken.join("\n"));
}

#[test]
fn no_table_cell_holds_a_page_of_text() {
    const MAX: usize = 400;
    let mut long = Vec::new();
    for page in pages() {
        let text = read(&page);
        for (n, line) in prose(&text) {
            if !line.trim_start().starts_with('|') {
                continue;
            }
            for cell in line.split('|') {
                let chars = cell.trim().chars().count();
                if chars > MAX {
                    long.push(format!(
                        "{}:{n}: a cell of {chars} characters",
                        page.display()
                    ));
                }
            }
        }
    }
    assert!(
        long.is_empty(),
        "table cells over {MAX} characters (history belongs in docs/benchmarks.md, \
         explanations in prose):\n{}",
        long.join("\n")
    );
}

#[test]
fn cmake_configure_commands_name_their_source_folder() {
    // Without `-S`, CMake takes the current folder (the repository's root, which has no
    // CMakeLists.txt) as the source: "does not appear to contain CMakeLists.txt".
    let mut bad = Vec::new();
    for page in pages() {
        let text = read(&page);
        for (n, line) in text.lines().enumerate() {
            if let Some(i) = line.find("cmake -B") {
                bad.push(format!("{}:{}: {}", page.display(), n + 1, &line[i..]));
            }
            if line.contains("cmake ") && line.contains(" -B ") && !line.contains(" -S ") {
                bad.push(format!("{}:{}: {line}", page.display(), n + 1));
            }
        }
    }
    assert!(
        bad.is_empty(),
        "cmake configure commands without `-S <source folder>`:\n{}",
        bad.join("\n")
    );
}

#[test]
fn the_crate_claims_only_what_exists() {
    // Each capability a paper names, the words that claim it, and the modules that may hold it.
    let capabilities: [(&str, &[&str]); 6] = [
        ("subdivision", &["src/subdivide"]),
        ("stroke cut", &["src/cut"]),
        ("rough-model", &["src/rough", "src/edit"]),
        ("segmentation", &["src/rough", "src/segment"]),
        ("b-spline", &["src/rough", "src/spline"]),
        ("curved", &["src/curved"]),
    ];
    let manifest = read(&root().join("Cargo.toml"));
    let description = manifest
        .lines()
        .find_map(|l| l.strip_prefix("description = "))
        .expect("Cargo.toml has a description")
        .to_lowercase();
    let lib = read(&root().join("src/lib.rs"));
    let crate_docs: String = lib
        .lines()
        .take_while(|l| l.starts_with("//!"))
        .collect::<Vec<_>>()
        .join("\n")
        .to_lowercase();
    let mut claims = Vec::new();
    for (what, text) in [
        ("Cargo.toml's description", &description),
        ("the crate docs in src/lib.rs", &crate_docs),
    ] {
        for (word, modules) in capabilities {
            if text.contains(word) && !modules.iter().any(|m| root().join(m).is_dir()) {
                claims.push(format!(
                    "{what} claims {word}, but none of {} exists",
                    modules.join(", ")
                ));
            }
        }
    }
    assert!(claims.is_empty(), "{}", claims.join("\n"));
}
