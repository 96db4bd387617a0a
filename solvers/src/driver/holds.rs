//! What the contacts' active sets are held at between the driver's attempts
//! ([`ActiveSetHolds`]): the two flags the held retry ([`crate::held_active_set`]) and the
//! first iteration of a step set and the elements' evaluation reads.

/// What the contacts' active sets are held at, between the driver's attempts.
#[derive(Debug, Clone, Copy, Default)]
pub(crate) struct ActiveSetHolds {
    /// The held retry ([`crate::held_active_set`]) holds them.
    pub(crate) retry: bool,
    /// This step's first iteration holds them
    /// ([`railfem_framework::model::FirstActiveSet`]).
    pub(crate) first: bool,
}
