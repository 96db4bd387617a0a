//! The book's generated reference pages are those the code writes now (issue 35):
//! `docs/reference/*.md` against [`railfem::reference::pages`], and what the pages must
//! hold, read off the registries and clap independently of the generator.

use std::path::Path;

fn dir() -> std::path::PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("docs/reference")
}

#[test]
fn checked_in_reference_pages_are_up_to_date() {
    let mut stale = Vec::new();
    for page in railfem::reference::pages(&railfem::cli::clap_command()) {
        let path = dir().join(page.file);
        let on_disk = std::fs::read_to_string(&path).unwrap_or_default();
        if on_disk != page.text {
            stale.push(format!("docs/reference/{}", page.file));
        }
    }
    assert!(
        stale.is_empty(),
        "{} differ from the code; run `railfem reference --out docs/reference` (or `cargo run --release -- reference --out docs/reference`) and commit them",
        stale.join(", ")
    );
}

#[test]
fn the_pages_hold_every_kind_key_command_and_option() {
    railfem::elements::link();
    let read = |f: &str| std::fs::read_to_string(dir().join(f)).expect("reference page");
    let elements = read("elements.md");
    for k in railfem::framework::registry::kinds() {
        assert!(
            elements.contains(&format!("\n## {}\n", k.name)),
            "element {}",
            k.name
        );
        for p in (k.params)() {
            assert!(
                elements.contains(&format!("| `{}` |", p.key)),
                "{} key {}",
                k.name,
                p.key
            );
        }
    }
    let loads = read("loads.md");
    for k in railfem::framework::load_kind::kinds() {
        assert!(
            loads.contains(&format!("\n## {}\n", k.name)),
            "load {}",
            k.name
        );
    }
    let recorders = read("recorders.md");
    for k in railfem::framework::recorder_kind::kinds() {
        assert!(
            recorders.contains(&format!("\n## {}\n", k.name)),
            "recorder {}",
            k.name
        );
    }
    let integrators = read("integrators.md");
    for e in railfem::solvers::time_integrator::entries() {
        assert!(
            integrators.contains(&format!("\n## {}\n", e.name)),
            "integrator {}",
            e.name
        );
    }
    let cli = read("cli.md");
    let cmd = railfem::cli::clap_command();
    for sub in cmd.get_subcommands().filter(|s| s.get_name() != "help") {
        assert!(
            cli.contains(&format!("\n## railfem {}\n", sub.get_name())),
            "command {}",
            sub.get_name()
        );
        for a in sub.get_arguments().filter(|a| !a.is_global_set()) {
            if let Some(long) = a.get_long().filter(|l| *l != "help") {
                assert!(
                    cli.contains(&format!("`--{long}")),
                    "{} --{long}",
                    sub.get_name()
                );
            }
        }
    }
    let every = cli
        .split("\n## ")
        .find(|s| s.starts_with("Options of every command\n"))
        .expect("the section of the options of every command");
    for global in ["--plugin", "--max-memory", "--max-steps", "--quiet"] {
        assert!(every.contains(global), "{global}");
    }
}

#[test]
fn beam3d_keys_read_as_the_model_format_page_gives_them() {
    // docs/model-format.md's hand-written beam3d table gives E in Pa (required), rho in
    // kg/m³ (default 0) and Iy in m⁴ (required): the generated rows must say the same, in
    // the registry's spelling of the units.
    let elements = std::fs::read_to_string(dir().join("elements.md")).expect("elements.md");
    let beam = elements
        .split("\n## ")
        .find(|s| s.starts_with("beam3d\n"))
        .expect("beam3d section");
    for row in [
        "| `E` | Pa | required |",
        "| `rho` | kg/m^3 | `0.0` |",
        "| `Iy` | m^4 | required |",
    ] {
        assert!(beam.contains(row), "beam3d row {row}");
    }
}

#[test]
fn the_command_writes_the_pages() {
    let out = std::env::temp_dir().join(format!("railfem-reference-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&out);
    let o = std::process::Command::new(env!("CARGO_BIN_EXE_railfem"))
        .args(["reference", "--out"])
        .arg(&out)
        .output()
        .expect("run railfem");
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    for page in railfem::reference::pages(&railfem::cli::clap_command()) {
        let written = std::fs::read_to_string(out.join(page.file)).expect("written page");
        assert_eq!(written, page.text, "{}", page.file);
    }
    let _ = std::fs::remove_dir_all(&out);
    // A plugin would make the pages depend on one machine's library: refused, one line.
    let o = std::process::Command::new(env!("CARGO_BIN_EXE_railfem"))
        .args(["reference", "--plugin", "x.so", "--out", "unused"])
        .output()
        .expect("run railfem");
    assert_eq!(o.status.code(), Some(2));
}

#[test]
fn every_table_row_has_as_many_cells_as_its_header() {
    // A `|` left unescaped in a cell (`<linear|nonlinear>`) would split it in two.
    let cells = |line: &str| {
        let b = line.as_bytes();
        (0..b.len())
            .filter(|&i| b[i] == b'|' && (i == 0 || b[i - 1] != b'\\'))
            .count()
    };
    for page in railfem::reference::pages(&railfem::cli::clap_command()) {
        let mut header: Option<usize> = None;
        for (i, line) in page.text.lines().enumerate() {
            if !line.starts_with('|') {
                header = None;
                continue;
            }
            let n = cells(line);
            match header {
                None => header = Some(n),
                Some(h) => assert_eq!(n, h, "{}:{}: {line}", page.file, i + 1),
            }
        }
    }
}
