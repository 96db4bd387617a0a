//! The guides run as written (issue 35): every page of `docs/guide/` is played in page order
//! in a fresh folder — blocks marked `file=NAME` are written, blocks marked `runnable` are
//! run with `bash` and the `railfem` under test on `PATH` (with the page's `cap=ARG` caps
//! appended to each `railfem` command), and the files a `writes` block lists and the CSV
//! headers a `header=PATH` block shows are checked. The conventions are described for
//! writers in `docs/contributing.md`.

mod common;

use std::path::{Path, PathBuf};
use std::process::Command;

/// One fenced block of a page: its info string's words and its text.
#[derive(Debug, Clone, PartialEq)]
struct Block {
    /// Line of the opening fence (1-based).
    line: usize,
    /// The info string's words (`sh`, `runnable`, `cap=--quick`, …).
    words: Vec<String>,
    /// The lines between the fences, with the fence's indentation removed.
    text: String,
}

impl Block {
    fn has(&self, word: &str) -> bool {
        self.words.iter().any(|w| w == word)
    }
    fn value(&self, key: &str) -> Vec<String> {
        let prefix = format!("{key}=");
        self.words
            .iter()
            .filter_map(|w| w.strip_prefix(&prefix).map(str::to_string))
            .collect()
    }
}

/// The fenced blocks of a page (backtick fences, indented or not).
fn blocks(text: &str) -> Vec<Block> {
    let mut out = Vec::new();
    let mut open: Option<(usize, usize, String, Vec<String>)> = None;
    let mut body = Vec::new();
    for (i, line) in text.lines().enumerate() {
        let indent = line.len() - line.trim_start().len();
        let t = line.trim_start();
        let ticks = t.chars().take_while(|&c| c == '`').count();
        match &open {
            None if ticks >= 3 => {
                let info = t[ticks..].trim();
                let words = info.split_whitespace().map(str::to_string).collect();
                open = Some((i + 1, indent, "`".repeat(ticks), words));
                body.clear();
            }
            Some((line_no, ind, fence, words)) if t.trim_end() == fence.as_str() => {
                let _ = ind;
                out.push(Block {
                    line: *line_no,
                    words: words.clone(),
                    text: body.join("\n"),
                });
                open = None;
            }
            Some((_, ind, _, _)) => {
                let cut = line
                    .char_indices()
                    .take_while(|(k, c)| *k < *ind && c.is_whitespace())
                    .count();
                body.push(line[cut..].to_string());
            }
            None => {}
        }
    }
    out
}

/// `script` with `caps` appended to every line that runs `railfem` (a line that starts with
/// it, or with it after `|`, `&&` or `;`: the test's scripts are simple command lines).
fn capped(script: &str, caps: &[String]) -> String {
    if caps.is_empty() {
        return script.to_string();
    }
    let extra = format!(" {}", caps.join(" "));
    script
        .lines()
        .map(|l| {
            let t = l.trim_start();
            if t.starts_with("railfem ") {
                let (cmd, comment) = match l.find(" #") {
                    Some(p) => (&l[..p], &l[p..]),
                    None => (l, ""),
                };
                format!("{}{extra}{comment}", cmd.trim_end())
            } else {
                l.to_string()
            }
        })
        .collect::<Vec<_>>()
        .join("\n")
}

/// The folder a guide runs in: links to the repository's `examples/` and to the target
/// folder of this test, and `bin/railfem` pointing at the binary under test.
fn workspace(name: &str) -> PathBuf {
    let dir = common::temp_dir(name);
    let repo = Path::new(env!("CARGO_MANIFEST_DIR"));
    let exe = PathBuf::from(env!("CARGO_BIN_EXE_railfem"));
    let target = exe
        .parent()
        .and_then(Path::parent)
        .expect("target/<profile>/railfem");
    std::os::unix::fs::symlink(repo.join("examples"), dir.join("examples")).expect("link");
    std::os::unix::fs::symlink(target, dir.join("target")).expect("link");
    std::fs::create_dir_all(dir.join(".bin")).expect("bin folder");
    std::os::unix::fs::symlink(&exe, dir.join(".bin/railfem")).expect("link");
    dir
}

/// Plays one guide; returns what went wrong, one line each, and the number of checks.
fn play(page: &Path) -> (Vec<String>, usize) {
    let name = page.file_stem().and_then(|s| s.to_str()).unwrap_or("guide");
    let shown = format!("docs/guide/{name}.md");
    let text = std::fs::read_to_string(page).expect("read guide");
    let dir = workspace(name);
    let path = format!(
        "{}:{}",
        dir.join(".bin").display(),
        std::env::var("PATH").unwrap_or_default()
    );
    let mut problems = Vec::new();
    let mut checks = 0;
    for b in blocks(&text) {
        let at = format!("{shown}:{}", b.line);
        if let Some(file) = b.value("file").first() {
            let dest = dir.join(file);
            if let Some(parent) = dest.parent() {
                std::fs::create_dir_all(parent).expect("folder of a guide file");
            }
            std::fs::write(&dest, format!("{}\n", b.text)).expect("write guide file");
        }
        if b.has("runnable") {
            checks += 1;
            if b.text.split_whitespace().any(|w| w == "cargo") {
                problems.push(format!(
                    "{at}: a runnable block calls cargo; mark it `needs-cargo` instead"
                ));
                continue;
            }
            if b.text.contains("librailfem_plugin_hysteretic") {
                common::plugin_lib();
            }
            let script = capped(&b.text, &b.value("cap"));
            let out = Command::new("bash")
                .args(["-euo", "pipefail", "-c", &script])
                .current_dir(&dir)
                .env("PATH", &path)
                .output()
                .expect("run bash");
            if !out.status.success() {
                problems.push(format!(
                    "{at}: `{}` exited with {:?}: {}",
                    script.replace('\n', "; "),
                    out.status.code(),
                    String::from_utf8_lossy(&out.stderr)
                        .lines()
                        .last()
                        .unwrap_or("")
                ));
            }
        }
        if b.has("writes") {
            for f in b.text.lines().map(str::trim).filter(|l| !l.is_empty()) {
                checks += 1;
                let len = std::fs::metadata(dir.join(f)).map(|m| m.len()).unwrap_or(0);
                if len == 0 {
                    problems.push(format!(
                        "{at}: the page says {f} is written; it is missing or empty"
                    ));
                }
            }
        }
        if let Some(file) = b.value("header").first() {
            checks += 1;
            let want = b.text.trim();
            let got = std::fs::read_to_string(dir.join(file))
                .ok()
                .and_then(|t| t.lines().next().map(str::to_string))
                .unwrap_or_default();
            let ok = match want.strip_suffix('…') {
                Some(prefix) => got.starts_with(prefix),
                None => got == want,
            };
            if !ok {
                problems.push(format!(
                    "{at}: the header of {file} is `{got}`, the page shows `{want}`"
                ));
            }
        }
    }
    let _ = std::fs::remove_dir_all(&dir);
    (problems, checks)
}

fn guides() -> Vec<PathBuf> {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("docs/guide");
    let mut v: Vec<PathBuf> = std::fs::read_dir(&dir)
        .expect("docs/guide")
        .map(|e| e.expect("entry").path())
        .filter(|p| p.extension().is_some_and(|e| e == "md"))
        .collect();
    v.sort();
    v
}

#[test]
fn every_guide_runs_as_written() {
    let pages = guides();
    assert!(
        pages.len() >= 6,
        "six guides expected, found {}",
        pages.len()
    );
    let mut problems = Vec::new();
    let mut total = 0;
    for page in &pages {
        let (p, checks) = play(page);
        total += checks;
        problems.extend(p);
    }
    assert!(
        total >= 30,
        "only {total} checks over the guides: are the blocks marked?"
    );
    assert!(problems.is_empty(), "{}", problems.join("\n"));
}

#[test]
fn every_command_guide_runs_something() {
    // Each guide but the Python one (which needs a build of the bindings) runs at least one
    // block, so a guide cannot drift out of the test by losing its marks.
    for page in guides() {
        let text = std::fs::read_to_string(&page).expect("read guide");
        let b = blocks(&text);
        let runs = b.iter().filter(|b| b.has("runnable")).count();
        let name = page.file_name().and_then(|n| n.to_str()).unwrap_or("");
        if name != "python-session.md" {
            assert!(runs >= 1, "{name} has no runnable block");
        } else {
            assert!(
                b.iter().any(|b| b.has("needs-python")),
                "{name}: mark its cells"
            );
        }
    }
}

#[test]
fn blocks_and_caps_are_read_as_documented() {
    let page = "text\n```sh runnable cap=--steps=10\nrailfem train-bridge --out out/tb   # c\necho done\n```\n  ```csv header=out/a.csv\n  time [s],x [m]\n  ```\n";
    let b = blocks(page);
    assert_eq!(b.len(), 2);
    assert_eq!(b[0].line, 2);
    assert!(b[0].has("runnable"));
    assert_eq!(b[0].value("cap"), vec!["--steps=10"]);
    assert_eq!(
        capped(&b[0].text, &b[0].value("cap")),
        "railfem train-bridge --out out/tb --steps=10 # c\necho done"
    );
    assert_eq!(b[1].value("header"), vec!["out/a.csv"]);
    assert_eq!(b[1].text, "time [s],x [m]");
}
