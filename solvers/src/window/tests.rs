//! The structure's ends rule ([`super::end_bounds`]) on hand-derived cases: ends at 0 m
//! and 1 000 m, reach 100 m, so an end counts within `END_REACH·ahead` = 300 m of the
//! load. Every station is a whole number of metres, so the bounds are exact.

use super::{end_bounds, END_REACH};

const ENDS: [f64; 2] = [0.0, 1000.0];
const AHEAD: f64 = 100.0;

#[test]
fn end_reach_is_three_reaches() {
    assert_eq!(END_REACH * AHEAD, 300.0);
}

#[test]
fn no_end_within_reach_leaves_the_load_alone() {
    // Both ends farther than 300 m: behind 400 m, ahead 550 m.
    assert_eq!(
        end_bounds(&ENDS, 400.0, 450.0, AHEAD),
        [f64::INFINITY, 550.0]
    );
    // No ends at all.
    assert_eq!(end_bounds(&[], 400.0, 450.0, AHEAD), [f64::INFINITY, 550.0]);
}

#[test]
fn an_end_ahead_within_three_reaches_keeps_up_to_a_reach_beyond_it() {
    // End 0 is 150 m ahead of the front: join up to 0 + 100, past the front's −50.
    assert_eq!(
        end_bounds(&ENDS, -200.0, -150.0, AHEAD),
        [f64::INFINITY, 100.0]
    );
    // Exactly 300 m ahead counts; 301 m does not.
    assert_eq!(
        end_bounds(&ENDS, 650.0, 700.0, AHEAD),
        [f64::INFINITY, 1100.0]
    );
    assert_eq!(
        end_bounds(&ENDS, 649.0, 699.0, AHEAD),
        [f64::INFINITY, 799.0]
    );
    // Two ends ahead within reach (50 m and 150 m): the farther one decides.
    assert_eq!(
        end_bounds(&[0.0, 100.0, 1000.0], -60.0, -50.0, AHEAD),
        [f64::INFINITY, 200.0]
    );
}

#[test]
fn an_end_behind_within_three_reaches_keeps_from_a_reach_before_it() {
    // End 0 is 200 m behind the rear: keep from −100; end 1 000 is 750 m ahead.
    assert_eq!(end_bounds(&ENDS, 200.0, 250.0, AHEAD), [-100.0, 350.0]);
    // 300 m behind counts, 301 m does not.
    assert_eq!(end_bounds(&ENDS, 300.0, 350.0, AHEAD), [-100.0, 450.0]);
    assert_eq!(
        end_bounds(&ENDS, 301.0, 351.0, AHEAD),
        [f64::INFINITY, 451.0]
    );
}

#[test]
fn ends_on_both_sides_both_count() {
    // A load over [200, 750]: end 0 is 200 m behind, end 1 000 is 250 m ahead.
    assert_eq!(end_bounds(&ENDS, 200.0, 750.0, AHEAD), [-100.0, 1100.0]);
    // An end under the load is neither ahead nor behind it.
    assert_eq!(
        end_bounds(&[500.0], 400.0, 600.0, AHEAD),
        [f64::INFINITY, 700.0]
    );
}
