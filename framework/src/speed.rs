//! Speed histories of things that travel along a path: constant speed, constant
//! acceleration (braking stops at rest), or a table of speed against time.
//!
//! A [`SpeedHistory`] answers three questions at time `t`: the station `s(t)` (m), the
//! speed `v(t) = ds/dt` (m/s) and the acceleration `a(t) = dv/dt` (m/s²). Moving
//! oscillators use it now; vehicles can later. It does not move anything itself.
//!
//! - **Uniform**: `v(t) = v0 + a·t`, `s(t) = s0 + v0·t + ½·a·t²`. With `a < 0` the
//!   traveller stops at `t_stop = v0/|a|` and stays at `s0 + v0²/(2|a|)`; it never runs
//!   backwards.
//! - **Table** `[[t_i, v_i], …]`: `v` is piecewise linear between the rows, constant
//!   (`v_0`, `v_last`) outside them. The station is its exact integral: on row segment `i`,
//!   `s = s_i + v_i·τ + ½·a_i·τ²` with `τ = t − t_i`, `a_i = (v_{i+1} − v_i)/(t_{i+1} − t_i)`,
//!   and `s(0) = s0` fixes the constant.
//!
//! Validation ([`SpeedHistory::from_table`], [`SpeedHistory::uniform`]) refuses a history
//! that runs backwards — a negative speed, or times that do not strictly increase — with a
//! message naming the key and the row; the caller adds the file and the place.

use crate::limits::fmt_num;

/// Time (s) at which a constant deceleration `accel < 0` brings a traveller moving at
/// `speed ≥ 0` to rest (zero when it is at rest already); infinite without a deceleration
/// or for a traveller running backwards. Shared with [`crate::moving::Carrier`].
pub fn braking_stop(speed: f64, accel: f64) -> f64 {
    if accel < 0.0 && speed >= 0.0 {
        speed / -accel
    } else {
        f64::INFINITY
    }
}

/// How the speed varies.
#[derive(Debug, Clone, PartialEq)]
enum Law {
    /// Constant acceleration from `speed` at t = 0; a deceleration stops at rest.
    Uniform { speed: f64, accel: f64 },
    /// Piecewise linear speed; `dist[i]` is the distance travelled from `times[0]` to `times[i]`.
    Table {
        times: Vec<f64>,
        speeds: Vec<f64>,
        dist: Vec<f64>,
    },
}

/// A speed history with its station at t = 0. See the module documentation.
#[derive(Debug, Clone, PartialEq)]
pub struct SpeedHistory {
    start: f64,
    law: Law,
    /// Distance travelled from the law's origin to t = 0 (Table), subtracted so `s(0) = start`.
    offset: f64,
}

impl SpeedHistory {
    /// Constant acceleration `accel` (m/s²) from `speed` (m/s, ≥ 0) at station `start` (m).
    /// Errors name the key (`speed`, `accel`, `start`).
    pub fn uniform(start: f64, speed: f64, accel: f64) -> Result<SpeedHistory, String> {
        if !start.is_finite() {
            return Err(format!("`start` = {} is not finite", fmt_num(start)));
        }
        if !(speed.is_finite() && speed >= 0.0) {
            return Err(format!(
                "`speed` = {} m/s runs backwards or is not finite; give a speed ≥ 0 (the direction of travel is the path's)",
                fmt_num(speed)
            ));
        }
        if !accel.is_finite() {
            return Err(format!("`accel` = {} is not finite", fmt_num(accel)));
        }
        Ok(SpeedHistory {
            start,
            law: Law::Uniform { speed, accel },
            offset: 0.0,
        })
    }

    /// A speed table `rows = [[t (s), v (m/s)], …]` from station `start` (m) at t = 0.
    /// `key` names the table in messages (`speed_table`).
    pub fn from_table(start: f64, rows: &[[f64; 2]], key: &str) -> Result<SpeedHistory, String> {
        if !start.is_finite() {
            return Err(format!("`start` = {} is not finite", fmt_num(start)));
        }
        if rows.is_empty() {
            return Err(format!(
                "`{key}` is empty; give rows [t (s), v (m/s)] with increasing t"
            ));
        }
        for (i, r) in rows.iter().enumerate() {
            if !(r[0].is_finite() && r[1].is_finite()) {
                return Err(format!("`{key}`[{i}] is not finite; give finite [t, v]"));
            }
            if r[1] < 0.0 {
                return Err(format!(
                    "`{key}`[{i}] has speed {} m/s: the table runs backwards; give speeds ≥ 0 (the direction of travel is the path's)",
                    fmt_num(r[1])
                ));
            }
            if i > 0 && r[0] <= rows[i - 1][0] {
                return Err(format!(
                    "`{key}`[{i}] has time {} s, not after row {} ({} s): the table runs backwards; list the rows with strictly increasing times",
                    fmt_num(r[0]),
                    i - 1,
                    fmt_num(rows[i - 1][0])
                ));
            }
        }
        let times: Vec<f64> = rows.iter().map(|r| r[0]).collect();
        let speeds: Vec<f64> = rows.iter().map(|r| r[1]).collect();
        let mut dist = vec![0.0];
        for i in 1..rows.len() {
            // Exact integral of a linear v over the segment: the trapezoid.
            let d = 0.5 * (speeds[i] + speeds[i - 1]) * (times[i] - times[i - 1]);
            dist.push(dist[i - 1] + d);
        }
        let mut h = SpeedHistory {
            start,
            law: Law::Table {
                times,
                speeds,
                dist,
            },
            offset: 0.0,
        };
        h.offset = h.distance(0.0);
        Ok(h)
    }

    /// Distance from the law's origin (Uniform: t = 0; Table: its first time).
    fn distance(&self, t: f64) -> f64 {
        match &self.law {
            Law::Uniform { speed, accel } => {
                if t <= 0.0 {
                    return speed * t;
                }
                if *accel < 0.0 {
                    let tt = t.min(braking_stop(*speed, *accel));
                    return speed * tt + 0.5 * accel * tt * tt;
                }
                speed * t + 0.5 * accel * t * t
            }
            Law::Table {
                times,
                speeds,
                dist,
            } => {
                let n = times.len();
                if t <= times[0] {
                    return speeds[0] * (t - times[0]);
                }
                if t >= times[n - 1] {
                    return dist[n - 1] + speeds[n - 1] * (t - times[n - 1]);
                }
                let i = times.partition_point(|x| *x <= t) - 1;
                let tau = t - times[i];
                let a = (speeds[i + 1] - speeds[i]) / (times[i + 1] - times[i]);
                dist[i] + speeds[i] * tau + 0.5 * a * tau * tau
            }
        }
    }

    /// Station at time `t` (m).
    pub fn station(&self, t: f64) -> f64 {
        self.start + self.distance(t) - self.offset
    }

    /// Speed at time `t` (m/s), ≥ 0 for t ≥ 0.
    pub fn speed(&self, t: f64) -> f64 {
        match &self.law {
            Law::Uniform { speed, accel } => {
                if t <= 0.0 {
                    *speed
                } else {
                    (speed + accel * t).max(0.0)
                }
            }
            Law::Table { times, speeds, .. } => {
                let n = times.len();
                if t <= times[0] {
                    return speeds[0];
                }
                if t >= times[n - 1] {
                    return speeds[n - 1];
                }
                let i = times.partition_point(|x| *x <= t) - 1;
                let f = (t - times[i]) / (times[i + 1] - times[i]);
                speeds[i] * (1.0 - f) + speeds[i + 1] * f
            }
        }
    }

    /// Acceleration at time `t` (m/s²): the slope of the segment that starts at or before
    /// `t` (zero outside the table, and after a braking stop).
    pub fn accel(&self, t: f64) -> f64 {
        match &self.law {
            Law::Uniform { speed, accel } => {
                if t < 0.0 || t >= braking_stop(*speed, *accel) {
                    0.0
                } else {
                    *accel
                }
            }
            Law::Table { times, speeds, .. } => {
                let n = times.len();
                if t < times[0] || t >= times[n - 1] {
                    return 0.0;
                }
                let i = times.partition_point(|x| *x <= t) - 1;
                (speeds[i + 1] - speeds[i]) / (times[i + 1] - times[i])
            }
        }
    }

    /// Station at t = 0 (m).
    pub fn start(&self) -> f64 {
        self.start
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Constant deceleration: the closed form before the stop, at rest after it.
    #[test]
    fn braking_stops_and_stays() {
        let h = SpeedHistory::uniform(2.0, 20.0, -4.0).unwrap();
        assert_eq!(h.station(0.0), 2.0);
        assert!((h.station(3.0) - (2.0 + 60.0 - 18.0)).abs() < 1e-12);
        assert!((h.speed(3.0) - 8.0).abs() < 1e-12);
        assert_eq!(h.accel(3.0), -4.0);
        // Stop at t = 5 s after 50 m.
        for t in [5.0, 6.0, 100.0] {
            assert!((h.station(t) - 52.0).abs() < 1e-12);
            assert_eq!(h.speed(t), 0.0);
            assert_eq!(h.accel(t), 0.0);
        }
    }

    /// A table that is one straight line equals the uniform law; the station is the exact
    /// integral (checked against a fine midpoint sum of the speed).
    #[test]
    fn table_integrates_exactly() {
        let rows = [[-1.0, 30.0], [2.0, 24.0], [4.0, 10.0], [5.0, 10.0]];
        let h = SpeedHistory::from_table(5.0, &rows, "speed_table").unwrap();
        assert!((h.station(0.0) - 5.0).abs() < 1e-12);
        let line = SpeedHistory::uniform(5.0, 28.0, -2.0).unwrap();
        for t in [0.0, 0.5, 1.3, 2.0] {
            assert!((h.station(t) - line.station(t)).abs() < 1e-12, "t = {t}");
            assert!((h.speed(t) - line.speed(t)).abs() < 1e-12);
        }
        let n = 100_000;
        let dt = 6.0 / n as f64;
        let sum: f64 = (0..n).map(|i| h.speed((i as f64 + 0.5) * dt) * dt).sum();
        assert!((h.station(6.0) - 5.0 - sum).abs() < 1e-6);
        assert_eq!(h.accel(3.0), -7.0);
        assert_eq!(h.accel(4.5), 0.0);
        assert_eq!(h.speed(9.0), 10.0);
    }

    #[test]
    fn backwards_histories_are_refused_with_the_key_and_row() {
        let e =
            SpeedHistory::from_table(0.0, &[[0.0, 5.0], [1.0, -1.0]], "speed_table").unwrap_err();
        assert!(
            e.contains("`speed_table`[1]") && e.contains("backwards"),
            "{e}"
        );
        let e = SpeedHistory::from_table(0.0, &[[0.0, 5.0], [2.0, 3.0], [1.0, 1.0]], "speed_table")
            .unwrap_err();
        assert!(
            e.contains("`speed_table`[2]") && e.contains("increasing"),
            "{e}"
        );
        let e = SpeedHistory::uniform(0.0, -3.0, 0.0).unwrap_err();
        assert!(e.contains("`speed`"), "{e}");
        assert!(SpeedHistory::from_table(0.0, &[], "speed_table").is_err());
    }
}
