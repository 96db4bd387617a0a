//! Issue 36, round five of bad input: the last string choices read as enums (item 5) —
//! DOF lists (`fix`, a node recorder's `dofs`, a link's `dofs`, a comfort recorder's
//! directions), an irregularity's `components`, a wheel's `model`, a study's `case`, and
//! `railfem contact --profiles/--inclination`. Each case asserts exit code 2 and one stderr
//! line naming the file (or the command line), the key path and the valid values in the
//! order the enum declares them (serde's own wording).

use super::common::{railfem, refused_with, study, temp_dir};
use super::{check, check_train, edit};

/// The words of a DOF list, as the enum declares them.
const DOF_WORDS: &str =
    "expected one of `ux`, `uy`, `uz`, `rx`, `ry`, `rz`, `all`, `translations`, `rotations`";

/// A node recorder's `dofs` and a rigid link's `dofs` take the words of `fix`.
#[test]
fn a_dof_list_word_outside_the_list_is_refused_with_the_list() {
    check(
        "rec_dofs.toml",
        &edit("dofs = [\"uz\"]", "dofs = [\"uz\", \"uzz\"]"),
        &[
            "`recorder[0].dofs[1]`: unknown variant `uzz`",
            DOF_WORDS,
            "give one of the values listed",
        ],
    );
    check(
        "fix_word.toml",
        &edit("fix = \"all\"", "fix = \"everything\""),
        &["`node[0].fix`: unknown variant `everything`", DOF_WORDS],
    );
    check(
        "link_dofs.toml",
        &edit(
            "[[element]]",
            "[[node]]\nid = 3\nxyz = [2.0, 0.0, 0.5]\n\n[[link]]\nmaster = 2\nslave = 3\ndofs = [\"ux\", \"rotation\"]\n\n[[element]]",
        ),
        &["`link[0].dofs[1]`: unknown variant `rotation`", DOF_WORDS],
    );
}

/// A comfort recorder's directions are DOFs (`Dof`): a word outside the six is refused
/// with the six; a rotation, a DOF, is refused by the comfort rule with its own fix.
#[test]
fn a_comfort_direction_outside_the_dofs_is_refused_with_the_list() {
    let text = include_str!("../../examples/models/comfort_oscillator.toml");
    assert!(text.contains("vertical = [\"uz\"]\nlateral = [\"uy\"]\nfile = \"comfort.csv\""));
    check(
        "comfort_dir.toml",
        &text.replacen("lateral = [\"uy\"]", "lateral = [\"sideways\"]", 1),
        &[
            "`recorder[2].lateral[0]`: unknown variant `sideways`",
            "expected one of `ux`, `uy`, `uz`, `rx`, `ry`, `rz`",
        ],
    );
    check(
        "comfort_rot.toml",
        &text.replacen("lateral = [\"uy\"]", "lateral = [\"rx\"]", 1),
        &[
            "recorder[2]",
            "`lateral` names `rx`",
            "translational accelerations: use ux, uy or uz",
        ],
    );
}

/// An irregularity's `components`: a name outside the four is refused with the four.
#[test]
fn an_irregularity_component_outside_the_list_is_refused_with_the_list() {
    check_train(
        "irr_comp",
        "support = {type = \"rigid\"}",
        "support = {type = \"rigid\"}\nirregularity = {psd = \"german_low\", seed = 1, wavelengths = [1.0, 50.0], components = [\"vertical\", \"heave\"]}",
        &[],
        &[
            "components[1]`: unknown variant `heave`",
            "expected one of `vertical`, `alignment`, `cross_level`, `gauge`",
        ],
    );
}

/// A wheel's `model` (the train's `wheel` table; a vehicle file's wheelsets take the same
/// enum): a name outside the three is refused with the three.
#[test]
fn a_wheel_model_outside_the_list_is_refused_with_the_list() {
    check_train(
        "wheel_model",
        "wheel = {mu = 0.3}",
        "wheel = {mu = 0.3, model = \"maglev\"}",
        &[],
        &[
            "`wheel.model`: unknown variant `maglev`",
            "expected one of `moving_axle`, `hertz_wheel`, `rigid_wheel`",
            "give one of the values listed",
        ],
    );
}

/// A study plan's `case`: a name outside the built-in cases is refused with them, before
/// any case runs.
#[test]
fn a_study_case_outside_the_list_is_refused_with_the_list() {
    let dir = temp_dir("study_case");
    let plan = dir.join("plan.toml");
    std::fs::write(
        &plan,
        "case = \"bridge\"\n\n[[axis]]\nname = \"speed\"\nvalues = [60, 100]\n",
    )
    .expect("write plan");
    let out = dir.join("out");
    let o = study(&plan, &out, &[]);
    refused_with(
        "study case",
        &o,
        &[
            "plan.toml: top level",
            "`case` bridge: unknown variant `bridge`, expected `train-bridge` or `curve`",
            "give one of the values listed",
        ],
    );
    assert!(!out.join("study.csv").exists());
    let _ = std::fs::remove_dir_all(&dir);
}

/// `railfem contact --profiles` and `--inclination` are read into their enums, as a model
/// file's `inclination` is.
#[test]
fn a_contact_profile_set_or_inclination_outside_the_list_is_refused_with_the_list() {
    for (args, says) in [
        (
            ["--profiles", "s1003"],
            "command line: --profiles s1003: unknown variant `s1003`, expected `s1002-60e1` or `mbench`; give one of the values listed",
        ),
        (
            ["--inclination", "1:30"],
            "command line: --inclination 1:30: unknown variant `1:30`, expected one of `none`, `1:40`, `1:20`; give one of the values listed",
        ),
    ] {
        let o = railfem(&["contact", args[0], args[1]]);
        let line = refused_with(args[0], &o, &[]);
        assert_eq!(line.trim_end(), format!("error: {says}"), "{args:?}");
    }
}
