//! The build of one rank of a model shared among processes ([`Driver::new_across_ranks`]):
//! the partitioned solver split on the pattern of `K`, `M`, `C` before any value exists,
//! so that the assembler forms only the columns the rank keeps
//! ([`railfem_framework::assembly::Assembler::new_on_columns`]).
//!
//! The split is what [`Driver::keep_own_rows`] makes from the whole matrices after the
//! build, in the same order: the solver's blocks and the rows the rank keeps
//! ([`Partitioned::rows_kept`]: its blocks' interiors and the base top set), then the
//! initial mass solve's own split (its default block size), whose rows the rank keeps too
//! until that solve is done. Both read the pattern only ([`Partitioned::prepare`]), so they
//! are the splits of the whole-matrix path, and the columns formed are those that path
//! keeps: the answers are the same to the bit.

use super::Driver;
use crate::exchange::Exchange;
use crate::partition::{PartitionOptions, Partitioned};
use railfem_framework::assembly::ColumnChoice;
use railfem_framework::model::SolverChoice;
use std::sync::Arc;

/// The splits a rank makes on the pattern.
pub(super) struct RankSplit {
    /// The partitioned solver, split and sharing its blocks with the ranks.
    pub(super) partition: Partitioned,
    /// The initial mass solve's solver, split the same way with its own block size.
    pub(super) mass: Partitioned,
    /// The rows (columns of `K`, `M`, `C`) the rank keeps for the run.
    pub(super) keep: Vec<bool>,
    /// `keep` and the rows the mass solve's split reads: the columns formed at the build.
    pub(super) until_mass: Vec<bool>,
}

impl RankSplit {
    /// The splits of a model that runs the partitioned solver, on `choice`'s pattern;
    /// `None` for another solver or one process.
    pub(super) fn on_pattern(
        choice: &ColumnChoice,
        exchange: &Arc<dyn Exchange>,
        options: PartitionOptions,
    ) -> Option<RankSplit> {
        if choice.solver != SolverChoice::Partitioned || exchange.size() < 2 {
            return None;
        }
        let split = |symmetric: bool, options: PartitionOptions| {
            let mut p = Partitioned::new(symmetric, options);
            p.set_exchange(exchange.clone());
            p.prepare(choice.pattern);
            p
        };
        let partition = split(choice.symmetric, options);
        let keep = partition.rows_kept()?;
        let mass = split(true, PartitionOptions::default());
        let mut until_mass = keep.clone();
        if let Some(more) = mass.rows_kept() {
            for (k, m) in until_mass.iter_mut().zip(more) {
                *k |= m;
            }
        }
        Some(RankSplit {
            partition,
            mass,
            keep,
            until_mass,
        })
    }
}

impl Driver {
    /// Takes a rank's splits made at the build: the driver shares the blocks with the
    /// ranks and forms the residual of its own rows, as after [`Driver::keep_own_rows`],
    /// and releases the elements its rows do not need.
    pub(super) fn take_rank_split(&mut self, exchange: Arc<dyn Exchange>, split: RankSplit) {
        let RankSplit {
            partition,
            mass,
            keep,
            until_mass,
        } = split;
        self.asm
            .settle_across_ranks(&|flag| crate::exchange::any_rank(Some(exchange.as_ref()), flag));
        self.linear.set_partitioned(partition);
        self.ranks.exchange = Some(exchange);
        self.release_unneeded_elements(&keep);
        if until_mass != keep {
            self.ranks.narrow_after_mass = Some(keep);
        }
        self.ranks.mass_split = Some(mass);
        self.ranks.own_rows = true;
    }
}
