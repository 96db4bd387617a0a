//! `relative_motion`, the plugin's recorder kind: the motion of one node relative to
//! another, `x_to − x_from` for each DOF asked (a spring's deflection, a suspension's
//! stroke, a bearing's drift), as displacement, velocity or acceleration.
//!
//! Both nodes' values are in their own axes, as the built-in node recorder writes them; for
//! nodes whose axes differ the difference is taken component by component all the same.

use railfem_framework::lookup::ModelLookup;
use railfem_framework::recorder::Quantity;
use railfem_framework::recorder_kind::{
    RecordState, RecordedColumns, RecorderBuild, RecorderEntry, RecorderKind,
};
use railfem_framework::registry::Params;
use railfem_framework::{Dof, FemError};

railfem_framework::element_params! {
    /// Model-file keys of `relative_motion`.
    pub struct RelativeMotionParams {
        /// Node id of the reference node.
        from: u64 [""],
        /// Node id of the moving node.
        to: u64 [""],
        /// DOFs to write (ux … rz), in the nodes' axes.
        dofs: Vec<Dof> [""],
        /// disp, vel or acc.
        quantity: Quantity [""] = "disp",
    }
}

/// A resolved relative-motion recorder.
pub struct RelativeMotion {
    ids: (u64, u64),
    nodes: (usize, usize),
    dofs: Vec<Dof>,
    quantity: Quantity,
}

impl RecordedColumns for RelativeMotion {
    fn columns(&self) -> Vec<String> {
        self.dofs
            .iter()
            .map(|d| {
                format!(
                    "{}_{}_d{} [{}]",
                    self.ids.1,
                    self.ids.0,
                    d.name(),
                    self.quantity.unit(d.index() >= 3)
                )
            })
            .collect()
    }

    fn row(&mut self, s: &mut RecordState, out: &mut Vec<f64>) -> Result<(), FemError> {
        for &d in &self.dofs {
            out.push(
                s.node(self.nodes.1, d, self.quantity) - s.node(self.nodes.0, d, self.quantity),
            );
        }
        Ok(())
    }
}

fn build(
    entry: &RecorderEntry,
    model: &dyn ModelLookup,
    origin: &str,
) -> Result<Box<dyn RecordedColumns>, FemError> {
    let p: RelativeMotionParams = entry.parse(origin)?;
    let index = |id: u64, key: &str| {
        model.node_index(id).ok_or_else(|| {
            FemError::input(
                origin,
                format!(
                    "`{key}` = {id}: no such node; define it in a [[node]] table or fix the id"
                ),
            )
        })
    };
    let nodes = (index(p.from, "from")?, index(p.to, "to")?);
    if p.dofs.is_empty() {
        return Err(FemError::input(
            origin,
            "`dofs` is empty; name at least one, e.g. [\"uz\"]",
        ));
    }
    Ok(Box::new(RelativeMotion {
        ids: (p.from, p.to),
        nodes,
        dofs: p.dofs,
        quantity: p.quantity,
    }))
}

/// The recorder kind this plugin exports.
pub const RELATIVE_MOTION: RecorderKind = RecorderKind {
    name: "relative_motion",
    description: "motion of one node relative to another (x_to − x_from) per DOF",
    params: <RelativeMotionParams as Params>::docs,
    build: RecorderBuild::Factory(build),
};
