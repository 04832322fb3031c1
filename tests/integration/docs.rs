//! The documentation stays true: every scene in README.md and `docs/` is checked as a
//! scene, every relative link and image resolves, every `#anchor` names a heading, and
//! every test that docs/performance.md names as holding a bound exists.
//!
//! Fenced TOML blocks carry a marker after the language, which docs/development.md
//! explains: ```` ```toml scene ```` is a whole scene that must validate;
//! ```` ```toml scene-invalid ```` is a scene that must be rejected, followed by a
//! ```` ```text ```` block whose first line the error must contain; ```` ```toml fragment ````
//! is part of a scene, shown for its keys, and not checked alone. A TOML block without a
//! marker fails the test, so that no new example goes unchecked by accident.

use std::collections::HashSet;
use std::path::{Path, PathBuf};

use physframes::scene::parse;

/// One fenced block of a Markdown file.
struct Block {
    /// The info string: the language and its marker, e.g. "toml scene".
    info: String,
    text: String,
    /// The 1-based line of the opening fence.
    line: usize,
}

/// README.md and every page of docs/.
fn documents() -> Vec<PathBuf> {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let mut files = vec![root.join("README.md")];
    let mut pages: Vec<PathBuf> = std::fs::read_dir(root.join("docs"))
        .expect("docs/ exists")
        .flatten()
        .map(|e| e.path())
        .filter(|p| p.extension().is_some_and(|e| e == "md"))
        .collect();
    pages.sort();
    assert!(pages.len() >= 10, "the guide has its pages: {pages:?}");
    files.extend(pages);
    files
}

/// Returns the fenced blocks of a Markdown text (fences of three backticks, possibly
/// indented, as in list items).
fn blocks(markdown: &str) -> Vec<Block> {
    let mut out = Vec::new();
    let mut open: Option<Block> = None;
    for (i, line) in markdown.lines().enumerate() {
        let trimmed = line.trim_start();
        // A fence is three backticks, not inline code of four that opens a line.
        if let Some(rest) = trimmed
            .strip_prefix("```")
            .filter(|rest| !rest.starts_with('`'))
        {
            match open.take() {
                Some(block) => out.push(block),
                None => {
                    open = Some(Block {
                        info: rest.trim().to_string(),
                        text: String::new(),
                        line: i + 1,
                    })
                }
            }
        } else if let Some(block) = &mut open {
            block.text.push_str(line);
            block.text.push('\n');
        }
    }
    assert!(open.is_none(), "a fence is left open");
    out
}

/// Returns the text outside fenced blocks, where links live.
fn prose(markdown: &str) -> String {
    let mut inside = false;
    let mut out = String::new();
    for line in markdown.lines() {
        let trimmed = line.trim_start();
        if trimmed.starts_with("```") && !trimmed.starts_with("````") {
            inside = !inside;
            continue;
        }
        if !inside {
            out.push_str(line);
            out.push('\n');
        }
    }
    out
}

/// The anchor GitHub gives a heading: lower case, punctuation other than `-` and `_`
/// dropped, spaces turned into `-`.
fn slug(heading: &str) -> String {
    heading
        .trim()
        .to_lowercase()
        .chars()
        .filter(|c| c.is_alphanumeric() || *c == '-' || *c == '_' || *c == ' ')
        .map(|c| if c == ' ' { '-' } else { c })
        .collect()
}

/// The anchors of a Markdown file's headings.
fn anchors(markdown: &str) -> HashSet<String> {
    prose(markdown)
        .lines()
        .filter_map(|l| {
            let hashes = l.chars().take_while(|c| *c == '#').count();
            (hashes > 0 && l[hashes..].starts_with(' ')).then(|| slug(&l[hashes..]))
        })
        .collect()
}

/// Returns every link and image target `(...)` after `](` in the prose, with its line.
fn links(markdown: &str) -> Vec<(String, usize)> {
    let mut out = Vec::new();
    for (i, line) in prose(markdown).lines().enumerate() {
        let mut rest = line;
        while let Some(at) = rest.find("](") {
            let after = &rest[at + 2..];
            let Some(end) = after.find(')') else { break };
            out.push((after[..end].to_string(), i + 1));
            rest = &after[end..];
        }
    }
    out
}

#[test]
fn every_scene_in_the_docs_is_checked_as_it_is_marked() {
    let mut checked = 0;
    for path in documents() {
        let text = std::fs::read_to_string(&path).expect("readable");
        let all = blocks(&text);
        for (k, block) in all.iter().enumerate() {
            let mut words = block.info.split_whitespace();
            let (language, marker) = (words.next().unwrap_or(""), words.next());
            if language != "toml" {
                continue;
            }
            let place = format!("{}:{}", path.display(), block.line);
            match marker {
                Some("scene") => {
                    if let Err(e) = parse(Path::new("doc.toml"), &block.text) {
                        panic!("{place}: a block marked as a scene is not valid:\n{e}");
                    }
                    checked += 1;
                }
                Some("scene-invalid") => {
                    let shown = all
                        .get(k + 1)
                        .filter(|b| b.info == "text")
                        .unwrap_or_else(|| {
                            panic!("{place}: an invalid scene must be followed by a ```text block with its error")
                        });
                    let expected = shown.text.lines().next().unwrap_or("").trim();
                    match parse(Path::new("doc.toml"), &block.text) {
                        Ok(_) => panic!("{place}: a block marked invalid is a valid scene"),
                        Err(e) => {
                            let message = e.to_string();
                            assert!(
                                !expected.is_empty() && message.contains(expected),
                                "{place}: the error shown, `{expected}`, is not the error:\n{message}"
                            );
                        }
                    }
                    checked += 1;
                }
                Some("fragment") => {}
                other => panic!(
                    "{place}: a TOML block needs a marker: `toml scene`, `toml scene-invalid` or `toml fragment` (found {other:?})"
                ),
            }
        }
    }
    assert!(checked >= 3, "only {checked} scenes were checked");
}

#[test]
fn every_relative_link_and_image_in_the_docs_resolves() {
    let mut count = 0;
    for path in documents() {
        let text = std::fs::read_to_string(&path).expect("readable");
        let dir = path.parent().expect("a folder");
        for (target, line) in links(&text) {
            let place = format!("{}:{line}", path.display());
            if target.starts_with("http://") || target.starts_with("https://") {
                continue;
            }
            let (file, anchor) = match target.split_once('#') {
                Some((file, anchor)) => (file, Some(anchor)),
                None => (target.as_str(), None),
            };
            let resolved = if file.is_empty() {
                path.clone()
            } else {
                dir.join(file)
            };
            assert!(
                resolved.exists(),
                "{place}: `{target}` points at {}, which does not exist",
                resolved.display()
            );
            if let Some(anchor) = anchor {
                let page = std::fs::read_to_string(&resolved).expect("a Markdown page");
                assert!(
                    anchors(&page).contains(anchor),
                    "{place}: `{target}`: no heading of {} has the anchor `{anchor}`",
                    resolved.display()
                );
            }
            count += 1;
        }
    }
    assert!(count >= 30, "only {count} links were checked");
}

/// The tests a page names in its table rows, as `` `file.rs`: `a_test`, `another` ``:
/// each (file, test name), in the order they appear.
fn named_tests(markdown: &str) -> Vec<(String, String)> {
    let mut out = Vec::new();
    for line in markdown.lines().filter(|l| l.trim_start().starts_with('|')) {
        for cell in line.split('|') {
            // A cell that names its file first: `perf.rs`: `a`, `b`.
            let Some((file, rest)) = cell.trim().split_once(": ") else {
                continue;
            };
            let file = file.trim_matches('`');
            if !file.ends_with(".rs") || file.contains(' ') {
                continue;
            }
            for name in rest.split(',') {
                let name = name.trim().trim_matches('`');
                if !name.is_empty()
                    && name
                        .chars()
                        .all(|c| c.is_ascii_lowercase() || c.is_ascii_digit() || c == '_')
                {
                    out.push((file.to_string(), name.to_string()));
                }
            }
        }
    }
    out
}

#[test]
fn every_test_the_performance_page_names_exists() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let page = std::fs::read_to_string(root.join("docs/performance.md")).expect("readable");
    let named = named_tests(&page);
    for (file, name) in &named {
        let source = std::fs::read_to_string(root.join("tests/integration").join(file))
            .unwrap_or_else(|e| panic!("docs/performance.md names `{file}`: {e}"));
        assert!(
            source.contains(&format!("fn {name}(")),
            "docs/performance.md names the test `{name}` in `{file}`, which has no such test"
        );
    }
    // The table of what each fast way costs in pixels names a test for each way.
    assert!(named.len() >= 15, "only {} tests were named", named.len());
}

#[test]
fn the_checks_of_the_docs_can_fail() {
    // The helpers find what a broken page would hide: a missing anchor, a TOML block,
    // and a link inside a table.
    let page = "# A title\n\n## Some heading: with `code`\n\n| a | [b](other.md#x) |\n\n```toml scene\nx = 1\n```\n";
    let found = anchors(page);
    assert!(found.contains("a-title") && found.contains("some-heading-with-code"));
    assert!(!found.contains("missing"));
    assert_eq!(links(page), vec![("other.md#x".to_string(), 5)]);
    let b = blocks(page);
    assert_eq!(
        (b.len(), b[0].info.as_str(), b[0].line),
        (1, "toml scene", 7)
    );
    assert!(parse(Path::new("doc.toml"), &b[0].text).is_err());
    // A row naming its tests is read, and so is a test that does not exist.
    let row = "| a way | `perf.rs`: `a_test_here`, `no_such_test` | not `a.rs` |";
    assert_eq!(
        named_tests(row),
        vec![
            ("perf.rs".to_string(), "a_test_here".to_string()),
            ("perf.rs".to_string(), "no_such_test".to_string()),
        ]
    );
}
