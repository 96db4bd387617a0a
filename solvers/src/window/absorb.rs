//! The absorbing layer at the activity window's edges: damping that grows towards a held
//! block, so that the waves the load sends along the structure die out before the held
//! block, which is a fixed wall, can send them back.
//!
//! **Why.** A held block's interior is prescribed ([`crate::window`]): a wave reaching it
//! is reflected whole, comes back to the load after `2D/c` (`D` the distance to the held
//! block, `c` the wave's group velocity) and changes the wheel forces; with the paper's
//! train at Δt = 0.5 ms the difference to the full model first appears at `2D/c` and
//! grows with time (`docs/activity-window.md`, "Why the window erred").
//!
//! **What.** In the active blocks' interiors within `L` (the layer's thickness) of the
//! nearest held region, each equation `i` at station `s` gets mass-proportional damping
//! added to the diagonal of the constant damping matrix,
//!
//! ```text
//! C_ii = C⁰_ii + α(s)·M_ii,   α(s) = α_max·ξ²,   ξ = clamp(d(s)/L, 0, 1),
//! ```
//!
//! `d(s)` the distance from the layer's inner edge towards the held side (the layer ahead
//! of the load ends at the first station of the held blocks ahead, the layer behind at the
//! last station of the blocks held behind). A quadratic ramp from zero makes the change of
//! impedance gradual, so the layer itself reflects little (Semblat, Lenti & Gandomzadeh
//! 2011, IJNME 85, whose layers grow Rayleigh damping the same way).
//!
//! **How much.** Mass-proportional damping `α·M` makes every undamped motion decay as
//! `e^{−αt/2}` (each mode of `M·ẍ + α·M·ẋ + K·x = 0` has the damping ratio `α/(2ω)`, hence
//! the decay rate `ζω = α/2`). A wave crossing the layer at group velocity `c` therefore
//! loses the factor `exp(−∫α/(2c) ds)` on its way; across the layer, to the wall and back,
//!
//! ```text
//! R = exp(−2·∫₀ᴸ α_max·(s/L)²/(2c) ds) = exp(−α_max·L/(3c)),
//! α_max = 3·c·ln(1/R)/L,
//! ```
//!
//! the amplitude `R` the wall returns. [`LayerSettings::for_reflection`] picks `α_max` by
//! this rule.
//!
//! **The energy.** The layer is part of `C`: its work `∫(C·v)ᵀ·dq` is the ledger's damping
//! work (`crate::energy`), so the balance still closes; the layer's `α·M` is positive
//! semi-definite, so it only takes energy out.
//!
//! **What it costs.** A change of `C` changes the effective matrix of the blocks it
//! touches: the layer is moved only when the held set changes (a block joins or leaves),
//! and then only the blocks whose `α` changed are factored anew
//! ([`crate::partition::Partitioned::constant_changed`]); a held block's `C` is its own
//! `C⁰` again.

use crate::driver::Driver;
use std::collections::hash_map::Entry;

/// The layer's thickness and the largest damping in it.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct LayerSettings {
    /// Thickness `L` along the track (m).
    pub thickness: f64,
    /// The mass-proportional damping `α_max` at the held side (1/s).
    pub alpha_max: f64,
}

impl LayerSettings {
    /// The layer of thickness `thickness` (m) that returns the amplitude `reflection` of
    /// a wave of group velocity `speed` (m/s): `α_max = 3·c·ln(1/R)/L` (module
    /// documentation).
    pub fn for_reflection(thickness: f64, speed: f64, reflection: f64) -> LayerSettings {
        LayerSettings {
            thickness,
            alpha_max: 3.0 * speed * (1.0 / reflection).ln() / thickness,
        }
    }

    /// `α(s)` of a station `s` with the held region ahead starting at `ahead` and the one
    /// behind ending at `behind` (`None`: nothing held on that side).
    pub fn alpha(&self, s: f64, ahead: Option<f64>, behind: Option<f64>) -> f64 {
        let l = self.thickness;
        let ramp = |d: f64| {
            let xi = (d / l).clamp(0.0, 1.0);
            self.alpha_max * xi * xi
        };
        let a = ahead.map_or(0.0, |e| ramp(s - (e - l)));
        let b = behind.map_or(0.0, |e| ramp((e + l) - s));
        a.max(b)
    }
}

/// The layer's state: the equations it changed, with their own `C⁰_ii`, `M_ii` and the
/// `α` applied now.
#[derive(Debug, Clone, Default)]
pub struct AbsorbingLayer {
    settings: Option<LayerSettings>,
    /// Per equation touched so far: `(C⁰_ii, M_ii, α)`.
    touched: std::collections::HashMap<usize, [f64; 3]>,
    /// Block factorizations the layer's moves asked for.
    refactored: usize,
}

impl AbsorbingLayer {
    /// A layer with `settings` (`None`: no layer; the window then holds as before).
    pub fn new(settings: Option<LayerSettings>) -> AbsorbingLayer {
        AbsorbingLayer {
            settings,
            ..Default::default()
        }
    }

    /// The settings.
    pub fn settings(&self) -> Option<LayerSettings> {
        self.settings
    }

    /// Blocks factored anew because the layer moved, so far.
    pub fn refactored(&self) -> usize {
        self.refactored
    }

    /// Moves the layer to the window's present edges: `blocks` gives each block's interior
    /// equations with their stations, `active` which blocks are solved, `top` the top
    /// equations next to the blocks (the separators: always solved) with their stations,
    /// `ahead`/`behind` the held regions' edges. Sets `C_ii` of every equation whose `α`
    /// changes (a held block's back to `C⁰_ii`) and has what changed factored anew.
    pub fn apply(
        &mut self,
        driver: &mut Driver,
        blocks: &[(&[usize], &[f64])],
        active: &[bool],
        top: (&[usize], &[f64]),
        ahead: Option<f64>,
        behind: Option<f64>,
    ) -> Result<(), String> {
        let Some(settings) = self.settings else {
            return Ok(());
        };
        let mut values = Vec::new();
        let mut changed = Vec::new();
        let groups = blocks
            .iter()
            .zip(active)
            .map(|(&g, &on)| (g, on))
            .chain(std::iter::once((top, true)));
        let mut top_changed = false;
        for (b, ((eqs, stations), on)) in groups.enumerate() {
            let before = values.len();
            for (&i, &s) in eqs.iter().zip(stations) {
                let alpha = if on {
                    settings.alpha(s, ahead, behind)
                } else {
                    0.0
                };
                let old = self.touched.get(&i).map_or(0.0, |t| t[2]);
                if alpha == old {
                    continue;
                }
                if let Entry::Vacant(e) = self.touched.entry(i) {
                    let [c, m] = driver.asm.constant_diagonal(i).ok_or_else(|| {
                        format!("equation {i} has no diagonal entry for the absorbing layer")
                    })?;
                    e.insert([c, m, 0.0]);
                }
                let entry = self.touched.get_mut(&i).expect("inserted above");
                entry[2] = alpha;
                // α = 0 gives back C⁰_ii itself, not a sum that rounds.
                let c = if alpha == 0.0 {
                    entry[0]
                } else {
                    entry[0] + alpha * entry[1]
                };
                values.push((i, c));
            }
            if values.len() > before {
                if b < blocks.len() {
                    changed.push(b);
                } else {
                    top_changed = true;
                }
            }
        }
        if values.is_empty() {
            return Ok(());
        }
        driver.asm.set_damping_diagonal(&values)?;
        driver.linear.forget_constant_values();
        driver
            .linear
            .partitioned_mut()
            .ok_or("the absorbing layer needs the partitioned solver")?
            .constant_changed(&changed, top_changed)?;
        driver.constant_changed = true;
        self.refactored += changed.len();
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::LayerSettings;

    /// The profile: zero at the inner edge, `α_max/4` halfway (the quadratic ramp),
    /// `α_max` at the held side and beyond; the larger of the two sides where both reach.
    #[test]
    fn the_ramp_is_quadratic_from_the_inner_edge_to_the_held_side() {
        let l = LayerSettings {
            thickness: 40.0,
            alpha_max: 100.0,
        };
        let ahead = Some(200.0);
        assert_eq!(l.alpha(150.0, ahead, None), 0.0);
        assert_eq!(l.alpha(160.0, ahead, None), 0.0);
        assert!((l.alpha(180.0, ahead, None) - 25.0).abs() < 1e-12);
        assert_eq!(l.alpha(200.0, ahead, None), 100.0);
        assert_eq!(l.alpha(230.0, ahead, None), 100.0);
        let behind = Some(0.0);
        assert!((l.alpha(30.0, None, behind) - 6.25).abs() < 1e-12);
        assert_eq!(l.alpha(-5.0, None, behind), 100.0);
        assert_eq!(l.alpha(100.0, ahead, behind), 0.0);
        // Both sides within reach (a short window): the larger.
        let near = Some(50.0);
        assert!((l.alpha(35.0, near, behind) - 100.0 * (25.0f64 / 40.0).powi(2)).abs() < 1e-12);
    }

    /// `α_max = 3·c·ln(1/R)/L` returns `R`: the amplitude factor of a wave crossing the
    /// layer to the wall and back, `exp(−2·∫α(s)/(2c) ds)`, integrated here by the midpoint
    /// rule over the profile itself (error ~1e-8 with 4 000 intervals).
    #[test]
    fn the_layer_returns_the_amplitude_it_was_sized_for() {
        let (c, r) = (1500.0, 0.01);
        for thickness in [20.0, 100.0] {
            let l = LayerSettings::for_reflection(thickness, c, r);
            let n = 4000;
            let h = thickness / n as f64;
            let integral: f64 = (0..n)
                .map(|k| l.alpha(((k as f64) + 0.5) * h, Some(thickness), None) * h)
                .sum();
            let returned = (-2.0 * integral / (2.0 * c)).exp();
            assert!((returned / r - 1.0).abs() < 1e-6, "{returned} for {r}");
        }
    }
}
