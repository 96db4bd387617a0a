//! railfem-elements: the built-in element kinds and the rail toolkit.
//!
//! What lives here: `beam3d` (Euler–Bernoulli / Timoshenko 3-D beam), `spring_damper`
//! (six springs and dashpots in a local frame), `mass` (lumped mass with rotary inertia), the moving oscillators
//! [`oscillators`] (`moving_sprung_mass`, `moving_mass`),
//! and [`rail`]: track alignment and cant, rail and wheel profiles, the moving wheel-axle
//! contact element of Ju & Ro (2021), vehicles and the simple theory. Each element kind
//! registers itself with the framework's registry; nothing else lists them.
//!
//! Units are SI throughout: m, kg, s, N, rad.
#![deny(missing_docs)]
// Index loops are the clearest way to write small dense matrix algebra.
#![allow(clippy::needless_range_loop)]

pub mod beam3d;
pub mod force_law;
pub mod mass;
pub mod oscillators;
pub mod rail;
pub mod spring_damper;
pub mod suspension;

/// Does nothing, and is not needed: kept so that code written when it was compiles.
///
/// The built-in kinds register through `inventory`, whose registrations are `#[used]`
/// statics; rustc links every `#[used]` static of each crate in the dependency graph
/// (its synthetic `symbols.o` references them), so a binary that depends on this crate
/// (directly or through `railfem`) finds them in the registry without naming anything of
/// it — `tests/no_link.rs` builds and runs a model through `ModelBuilder` that way.
pub fn link() {}
