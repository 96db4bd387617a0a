//! How a driver shares its run with other processes ([`Ranks`]): the exchange the
//! partitioned solver's blocks go through ([`super::Driver::set_exchange`]), whether this
//! rank forms the residual of its own rows only ([`super::Driver::keep_own_rows`]), and
//! what the initial mass solve needs of the whole pattern until it is done.

use crate::exchange::Exchange;
use crate::partition::Partitioned;
use std::sync::Arc;

/// A driver's share of a run across ranks; the default is one process.
#[derive(Default)]
pub(crate) struct Ranks {
    /// The ranks the partitioned solver shares its blocks with.
    pub(crate) exchange: Option<Arc<dyn Exchange>>,
    /// Each rank forms the residual of its own rows only.
    pub(crate) own_rows: bool,
    /// With `own_rows`, until [`super::Driver::initialize`] takes it: the initial mass
    /// solve's partitioned solver, split while the whole pattern was at hand.
    pub(crate) mass_split: Option<Partitioned>,
    /// The columns to keep once the initial mass solve is done, when it reads more.
    pub(crate) narrow_after_mass: Option<Vec<bool>>,
}
