//! What every CSV input reader shares (irregularity tables, wheel and rail profiles, ground
//! motion records, peer timings): the byte-order mark removed before the first line is
//! looked at, and the physical bound of a value in the unit its header declares.
//!
//! A bound is a magnitude no real input reaches in any unit (a track irregularity of more
//! than 0.1 m, a profile 1 m wide): a value beyond it is a unit slip or a broken file, and
//! reaching the solver it would only come back as "residual is not finite" with neither the
//! file nor the value named. [`check_bound`] refuses it with the row, the column as the
//! header writes it, the value in the declared unit and the bound in both units.

use crate::limits::fmt_num;

/// The text without a leading UTF-8 byte-order mark (U+FEFF), which some editors write
/// at the start of a CSV file: left in place it makes a `#` comment line look like a header
/// and is invisible in the message that follows.
pub fn strip_bom(text: &str) -> &str {
    text.strip_prefix('\u{feff}').unwrap_or(text)
}

/// The physical bound of one column.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Bound<'a> {
    /// Largest magnitude allowed, in SI units.
    pub max_si: f64,
    /// The SI unit (`"m"`).
    pub si_unit: &'a str,
    /// Why no real input is larger (a sentence fragment: "no track in service deviates
    /// that far from its mean").
    pub why: &'a str,
}

/// Refuses `value`, read under the header column `column` whose declared unit is `unit`
/// (one unit = `scale` SI units), when its magnitude exceeds `bound` (or it is not finite).
/// The message names the column, the value and unit, the bound in SI and in the declared
/// unit, the reason and the fix; the caller puts the file and the row before it.
pub fn check_bound(
    column: &str,
    value: f64,
    unit: &str,
    scale: f64,
    bound: &Bound,
) -> Result<(), String> {
    let si = value * scale;
    if si.is_finite() && si.abs() <= bound.max_si {
        return Ok(());
    }
    // The bound to six significant digits: 10 g is 98.0665 m/s², not 98.06649999999999.
    let short = |v: f64| fmt_num(format!("{v:.5e}").parse().unwrap_or(v));
    let in_unit = if scale == 1.0 || unit == bound.si_unit {
        String::new()
    } else {
        format!(" ({} {unit})", short(bound.max_si / scale))
    };
    Err(format!(
        "column `{column}` = {} {unit} is beyond ±{} {}{in_unit}: {}; correct that row, or the column's unit in the header",
        fmt_num(value),
        short(bound.max_si),
        bound.si_unit,
        bound.why
    ))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_mark_before_a_comment_is_removed() {
        assert_eq!(strip_bom("\u{feff}# c\nx"), "# c\nx");
        assert_eq!(strip_bom("# c"), "# c");
    }

    #[test]
    fn a_value_beyond_its_bound_names_row_column_and_value() {
        let b = Bound {
            max_si: 0.1,
            si_unit: "m",
            why: "no track deviates that far",
        };
        assert!(check_bound("vertical_mm", 99.0, "mm", 1e-3, &b).is_ok());
        let e = check_bound("vertical_mm", 1e300, "mm", 1e-3, &b).unwrap_err();
        assert!(
            e.starts_with("column `vertical_mm` = 1e300 mm is beyond ±0.1 m (100 mm)"),
            "{e}"
        );
        assert!(check_bound("v_m", f64::NAN, "m", 1.0, &b).is_err());
    }
}
