//! Closed choices given as text outside a model file — a command-line value
//! (`--tangential polach`), a study axis value — read into their serde enums, so that they
//! are spelt and refused exactly as in a model file: one line naming the option and the
//! valid values (`--tangential contact: unknown variant `contact`, expected one of
//! `coulomb`, `kalker_linear`, `polach`, `fastsim``).

use crate::framework::FemError;
use serde::de::DeserializeOwned;

/// Reads `value`, given for `what` (`--tangential`, `` `tangential` ``) at `origin`
/// (`command line`, `study case`), into the enum `T`.
pub fn parse<T: DeserializeOwned>(origin: &str, what: &str, value: &str) -> Result<T, FemError> {
    serde_json::from_value(serde_json::Value::String(value.to_string())).map_err(|e| {
        FemError::input(
            origin,
            format!("{what} {value}: {e}; give one of the values listed"),
        )
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::elements::rail::contact::creep::law::Tangential;

    #[test]
    fn a_choice_is_read_or_refused_with_the_list() {
        let t: Tangential = parse("command line", "--tangential", "fastsim").unwrap();
        assert_eq!(t, Tangential::Fastsim);
        let e = parse::<Tangential>("command line", "--tangential", "contact")
            .unwrap_err()
            .to_string();
        assert_eq!(
            e,
            "command line: --tangential contact: unknown variant `contact`, expected one of \
             `coulomb`, `kalker_linear`, `polach`, `fastsim`; give one of the values listed"
        );
    }
}
