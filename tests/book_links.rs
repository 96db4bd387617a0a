//! The book cannot rot (issue 35): every page of `docs/` is in `SUMMARY.md` exactly once and
//! every entry there exists; every relative link, `#anchor` and image in `docs/**/*.md` and
//! `README.md` resolves; no page names a path of a machine or a `wip-` branch. The rules are
//! described for writers in `docs/contributing.md`.
//!
//! Anchors are slugged as mdBook and GitHub slug headings ([`slug`]), checked against
//! hand-written cases below. Web links (`https://…`) are not fetched.

use std::collections::{BTreeMap, BTreeSet};
use std::path::{Component, Path, PathBuf};

/// Pages other work adds to the book: `SUMMARY.md` lists them and links may point to them
/// before they are in the tree. Delete an entry once its page has landed.
const PENDING: &[&str] = &[];

/// Pages other work removes or rewrites whole: `validation.md` is split into
/// `validation/*.md` (so it need not be in `SUMMARY.md`), and these four skip the
/// machine-path rule until their rewrite lands. Delete an entry once that work has landed.
const LEAVING: &[&str] = &[];

/// Paths of a machine a page must not name.
const MACHINE_PATHS: &[&str] = &["/home/", "/work/", "/root/", "/tmp/", "/Users/"];

fn repo() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
}

fn docs() -> PathBuf {
    repo().join("docs")
}

/// The heading's anchor as mdBook 0.4 writes it (`ascii_lower = true`: it lowercases
/// ASCII only) or as mdBook 0.5 and GitHub do (every letter lowercased): the text without markdown and HTML,
/// letters, digits, `_` and `-` kept, white space turned into `-`, everything else dropped.
fn slug(heading: &str, ascii_lower: bool) -> String {
    let text = plain_text(heading);
    text.trim()
        .chars()
        .filter_map(|c| {
            if c.is_alphanumeric() || c == '_' || c == '-' {
                Some(c)
            } else if c.is_whitespace() {
                Some('-')
            } else {
                None
            }
        })
        .flat_map(|c| {
            let lower: Vec<char> = if ascii_lower {
                vec![c.to_ascii_lowercase()]
            } else {
                c.to_lowercase().collect()
            };
            lower
        })
        .collect()
}

/// A heading's text as rendered: code spans keep their text, links their text, HTML tags
/// and emphasis markers (`*`) go.
fn plain_text(s: &str) -> String {
    let mut out = String::new();
    let chars: Vec<char> = s.chars().collect();
    let mut i = 0;
    while i < chars.len() {
        match chars[i] {
            '`' => {
                let ticks = chars[i..].iter().take_while(|&&c| c == '`').count();
                let rest: String = chars[i + ticks..].iter().collect();
                let close = "`".repeat(ticks);
                match rest.find(&close) {
                    Some(end) => {
                        out.push_str(rest[..end].trim());
                        i += ticks + rest[..end].chars().count() + ticks;
                    }
                    None => i += ticks,
                }
            }
            '<' => {
                let rest: String = chars[i..].iter().collect();
                match rest.find('>') {
                    Some(end) => i += rest[..=end].chars().count(),
                    None => i += 1,
                }
            }
            '*' => i += 1,
            '!' if chars.get(i + 1) == Some(&'[') => i += 1,
            '[' => i += 1,
            ']' if chars.get(i + 1) == Some(&'(') => {
                let rest: String = chars[i + 1..].iter().collect();
                match rest.find(')') {
                    Some(end) => i += 1 + rest[..=end].chars().count(),
                    None => i += 1,
                }
            }
            c => {
                out.push(c);
                i += 1;
            }
        }
    }
    out
}

#[test]
fn slugs_match_hand_written_cases() {
    // As mdBook and GitHub render these headings (worked out by hand from their rules).
    let cases = [
        ("The plan", "the-plan"),
        ("1. Parameters", "1-parameters"),
        ("`railfem curve`", "railfem-curve"),
        (
            "Bridge dynamic check (`railfem bridge-check`)",
            "bridge-dynamic-check-railfem-bridge-check",
        ),
        (
            "What is shared and what is replicated",
            "what-is-shared-and-what-is-replicated",
        ),
        (
            "Against OpenSees and run time against error",
            "against-opensees-and-run-time-against-error",
        ),
        (
            "The block factors — not kept",
            "the-block-factors--not-kept",
        ),
        (
            "`[analysis]` keys: `first_active_set`",
            "analysis-keys-first_active_set",
        ),
        ("Results (2026-11-22)", "results-2026-11-22"),
        ("A *new* [link](x.md) here", "a-new-link-here"),
        // Two ids mdBook 0.5.4 wrote for headings of docs/bridge-check.md.
        (
            "Bridge dynamic check (EN 1991-2 §6.4.6): `railfem bridge-check`",
            "bridge-dynamic-check-en-1991-2-646-railfem-bridge-check",
        ),
        (
            "Validation (`cargo test --release -p railfem --test bridge_check`)",
            "validation-cargo-test---release--p-railfem---test-bridge_check",
        ),
    ];
    for (heading, want) in cases {
        assert_eq!(slug(heading, true), want, "mdBook slug of {heading:?}");
        assert_eq!(slug(heading, false), want, "GitHub slug of {heading:?}");
    }
    // Non-ASCII capitals: mdBook 0.4 keeps them, mdBook 0.5 (`p-δ-beams` in
    // geometric-nonlinearity.html) and GitHub lowercase them; both are accepted.
    assert_eq!(slug("Δt and ΔQ/Q", true), "δt-and-δqq".replace('δ', "Δ"));
    assert_eq!(slug("Δt and ΔQ/Q", false), "δt-and-δqq");
}

/// A page's lines with fenced code blocks blanked (kept as empty lines, so that line
/// numbers stay) and inline code spans removed.
fn prose_lines(text: &str) -> Vec<String> {
    let mut fence: Option<String> = None;
    text.lines()
        .map(|line| {
            let t = line.trim_start();
            let marker: String = t.chars().take_while(|&c| c == '`' || c == '~').collect();
            if let Some(open) = &fence {
                if marker.len() >= open.len()
                    && marker.starts_with(&open[..1])
                    && t.trim() == marker
                {
                    fence = None;
                }
                return String::new();
            }
            if marker.len() >= 3
                && (marker.chars().all(|c| c == '`') || marker.chars().all(|c| c == '~'))
            {
                fence = Some(marker);
                return String::new();
            }
            strip_code_spans(line)
        })
        .collect()
}

/// The line without its inline code spans (any number of backticks).
fn strip_code_spans(line: &str) -> String {
    let mut out = String::new();
    let mut rest = line;
    while let Some(start) = rest.find('`') {
        out.push_str(&rest[..start]);
        let ticks = rest[start..].chars().take_while(|&c| c == '`').count();
        let after = &rest[start + ticks..];
        let close = "`".repeat(ticks);
        match after.find(&close) {
            Some(end) => rest = &after[end + ticks..],
            None => {
                rest = after;
            }
        }
    }
    out.push_str(rest);
    out
}

/// The anchors of a page: its headings slugged both ways (with `-1`, `-2` … for repeats)
/// and explicit `id="…"`/`name="…"` attributes.
fn anchors(text: &str) -> BTreeSet<String> {
    let mut set = BTreeSet::new();
    let mut fence = false;
    let mut seen: [BTreeMap<String, usize>; 2] = [BTreeMap::new(), BTreeMap::new()];
    for line in text.lines() {
        let t = line.trim_start();
        if t.starts_with("```") || t.starts_with("~~~") {
            fence = !fence;
            continue;
        }
        if fence {
            continue;
        }
        let hashes = t.chars().take_while(|&c| c == '#').count();
        if (1..=6).contains(&hashes) && t[hashes..].starts_with(' ') {
            let heading = t[hashes..].trim().trim_end_matches('#').trim();
            for (k, ascii) in [true, false].into_iter().enumerate() {
                let s = slug(heading, ascii);
                let n = seen[k].entry(s.clone()).or_insert(0);
                set.insert(if *n == 0 {
                    s.clone()
                } else {
                    format!("{s}-{n}")
                });
                *n += 1;
            }
        }
        for attr in ["id=\"", "name=\""] {
            let mut rest = line;
            while let Some(p) = rest.find(attr) {
                let after = &rest[p + attr.len()..];
                if let Some(end) = after.find('"') {
                    set.insert(after[..end].to_string());
                }
                rest = after;
            }
        }
    }
    set
}

/// The link targets of a line of prose: `[text](target)`, `![alt](target)`, reference
/// definitions `[label]: target` and `<img src="target">`.
fn link_targets(line: &str) -> Vec<String> {
    let mut out = Vec::new();
    let mut rest = line;
    while let Some(p) = rest.find("](") {
        let after = &rest[p + 2..];
        let mut depth = 0usize;
        let mut end = after.len();
        for (i, c) in after.char_indices() {
            match c {
                '(' => depth += 1,
                ')' if depth == 0 => {
                    end = i;
                    break;
                }
                ')' => depth -= 1,
                _ => {}
            }
        }
        let target = after[..end].split_whitespace().next().unwrap_or("");
        out.push(target.trim_matches(|c| c == '<' || c == '>').to_string());
        rest = &after[end.min(after.len())..];
    }
    let t = line.trim_start();
    if t.starts_with('[') {
        if let Some(p) = t.find("]: ") {
            if let Some(target) = t[p + 3..].split_whitespace().next() {
                out.push(target.to_string());
            }
        }
    }
    let mut rest = line;
    while let Some(p) = rest.find("src=\"") {
        let after = &rest[p + 5..];
        if let Some(end) = after.find('"') {
            out.push(after[..end].to_string());
        }
        rest = after;
    }
    out
}

/// Every markdown page of `docs/` (not the built book in `docs/book/`), relative to
/// `docs/`, with `/` separators.
fn pages() -> Vec<String> {
    fn walk(dir: &Path, base: &Path, out: &mut Vec<String>) {
        let mut entries: Vec<_> = std::fs::read_dir(dir)
            .expect("read docs folder")
            .map(|e| e.expect("entry").path())
            .collect();
        entries.sort();
        for p in entries {
            if p.is_dir() {
                if p != base.join("book") {
                    walk(&p, base, out);
                }
            } else if p.extension().is_some_and(|e| e == "md") {
                let rel = p.strip_prefix(base).expect("under docs");
                out.push(rel.to_string_lossy().replace('\\', "/"));
            }
        }
    }
    let mut out = Vec::new();
    walk(&docs(), &docs(), &mut out);
    out
}

/// `path` with `.` and `..` folded (no file-system access).
fn normalize(path: &Path) -> PathBuf {
    let mut out = PathBuf::new();
    for c in path.components() {
        match c {
            Component::ParentDir => {
                out.pop();
            }
            Component::CurDir => {}
            other => out.push(other),
        }
    }
    out
}

/// `docs/`-relative name of `path` when it lies in `docs/`.
fn docs_relative(path: &Path) -> Option<String> {
    path.strip_prefix(normalize(&docs()))
        .ok()
        .map(|p| p.to_string_lossy().replace('\\', "/"))
}

/// The entries of SUMMARY.md: (line number, target).
fn summary_entries() -> Vec<(usize, String)> {
    let text = std::fs::read_to_string(docs().join("SUMMARY.md")).expect("docs/SUMMARY.md");
    prose_lines(&text)
        .iter()
        .enumerate()
        .flat_map(|(i, l)| link_targets(l).into_iter().map(move |t| (i + 1, t)))
        .collect()
}

#[test]
fn summary_lists_every_page_once_and_only_pages_that_exist() {
    let mut problems = Vec::new();
    let mut count: BTreeMap<String, usize> = BTreeMap::new();
    for (line, target) in summary_entries() {
        let path = normalize(&docs().join(&target));
        let rel = docs_relative(&path).unwrap_or_else(|| target.clone());
        if !path.is_file() && !PENDING.contains(&rel.as_str()) {
            problems.push(format!(
                "docs/SUMMARY.md:{line}: `{target}` does not exist; create it or remove the entry"
            ));
        }
        *count.entry(rel).or_insert(0) += 1;
    }
    for page in pages() {
        if page == "SUMMARY.md" || LEAVING.contains(&page.as_str()) && !count.contains_key(&page) {
            continue;
        }
        match count.get(&page) {
            None => problems.push(format!(
                "docs/{page} is not in docs/SUMMARY.md; add it under its part"
            )),
            Some(&n) if n > 1 => problems.push(format!(
                "docs/{page} is listed {n} times in docs/SUMMARY.md; keep one entry"
            )),
            _ => {}
        }
    }
    for p in PENDING {
        if docs().join(p).is_file() {
            // Not an error: the page has landed; its PENDING entry can go.
            eprintln!("note: docs/{p} exists; remove it from PENDING in tests/book_links.rs");
        }
        assert!(
            count.contains_key(*p),
            "PENDING lists docs/{p}, which SUMMARY.md does not: remove it from PENDING"
        );
    }
    assert!(problems.is_empty(), "{}", problems.join("\n"));
}

#[test]
fn every_internal_link_anchor_and_image_resolves() {
    let mut files: Vec<PathBuf> = pages().iter().map(|p| docs().join(p)).collect();
    files.push(repo().join("README.md"));
    let mut anchor_cache: BTreeMap<PathBuf, BTreeSet<String>> = BTreeMap::new();
    let mut anchors_of = |p: &Path| -> BTreeSet<String> {
        anchor_cache
            .entry(p.to_path_buf())
            .or_insert_with(|| anchors(&std::fs::read_to_string(p).unwrap_or_default()))
            .clone()
    };
    let mut problems = Vec::new();
    let mut checked = 0usize;
    for file in &files {
        let text = std::fs::read_to_string(file).expect("read page");
        let shown = file
            .strip_prefix(repo())
            .unwrap_or(file)
            .display()
            .to_string();
        for (i, line) in prose_lines(&text).iter().enumerate() {
            for target in link_targets(line) {
                if target.is_empty() || target.contains("://") || target.starts_with("mailto:") {
                    continue;
                }
                checked += 1;
                let (path_part, anchor) = match target.split_once('#') {
                    Some((p, a)) => (p, Some(a)),
                    None => (target.as_str(), None),
                };
                let dest = if path_part.is_empty() {
                    file.clone()
                } else {
                    normalize(&file.parent().expect("folder").join(path_part))
                };
                let pending = docs_relative(&dest).is_some_and(|r| PENDING.contains(&r.as_str()));
                if !dest.exists() {
                    if !pending {
                        problems.push(format!(
                            "{shown}:{}: `{target}`: {} does not exist",
                            i + 1,
                            path_part
                        ));
                    }
                    continue;
                }
                if let Some(a) = anchor {
                    let is_md = dest.extension().is_some_and(|e| e == "md");
                    if is_md && !anchors_of(&dest).contains(a) {
                        problems.push(format!(
                            "{shown}:{}: `{target}`: no heading slugs to `#{a}` in {}",
                            i + 1,
                            dest.strip_prefix(repo()).unwrap_or(&dest).display()
                        ));
                    }
                }
            }
        }
    }
    assert!(
        checked > 100,
        "only {checked} links found: is the parser broken?"
    );
    assert!(
        problems.is_empty(),
        "{} broken links:\n{}",
        problems.len(),
        problems.join("\n")
    );
}

#[test]
fn no_machine_path_or_branch_name_in_docs_or_readme() {
    let mut files: Vec<(String, PathBuf)> = pages()
        .into_iter()
        .map(|p| (p.clone(), docs().join(&p)))
        .collect();
    files.push(("../README.md".into(), repo().join("README.md")));
    let mut problems = Vec::new();
    for (rel, path) in files {
        if LEAVING.contains(&rel.as_str()) {
            continue;
        }
        let text = std::fs::read_to_string(&path).expect("read page");
        for (i, line) in text.lines().enumerate() {
            for m in MACHINE_PATHS {
                if line.contains(m) {
                    problems.push(format!(
                        "docs/{rel}:{}: `{m}` is a path of one machine; use a relative path (`out/…`) or one in the repository",
                        i + 1
                    ));
                }
            }
            if line.contains("wip-") {
                problems.push(format!(
                    "docs/{rel}:{}: a `wip-` branch name; history belongs in commit messages",
                    i + 1
                ));
            }
        }
    }
    assert!(problems.is_empty(), "{}", problems.join("\n"));
}

#[test]
fn the_link_parser_finds_what_it_should() {
    // Hand-written lines: what a reader of the markdown sees as links.
    assert_eq!(
        link_targets("see [a](x.md#b) and ![f](figures/f.svg \"t\")"),
        vec!["x.md#b", "figures/f.svg"]
    );
    assert_eq!(link_targets("[ref]: ../README.md"), vec!["../README.md"]);
    assert_eq!(
        link_targets("<img src=\"figures/a.png\" width=\"50%\">"),
        vec!["figures/a.png"]
    );
    assert_eq!(strip_code_spans("a `[x](y)` b ``c`d`` e"), "a  b  e");
    let lines = prose_lines("x\n```sh\n[a](b)\n```\n[c](d)");
    assert_eq!(lines, vec!["x", "", "", "", "[c](d)"]);
    let a =
        anchors("# Top\n## The plan\n## The plan\n```\n# not a heading\n```\n<a id=\"here\"></a>");
    for want in ["top", "the-plan", "the-plan-1", "here"] {
        assert!(a.contains(want), "{want} in {a:?}");
    }
    assert!(!a.contains("not-a-heading"));
}
