//! The elements one rank of a shared model keeps: those the rank's rows need, every element
//! the assembler evaluates at every step, and those a caller names (the recorders');
//! the others are dropped after the build, their slots left as
//! [`crate::released::Released`] so that no element index shifts
//! ([`Assembler::release_elements`]).
//!
//! **Why this is exact.** A constant element (linear, on fixed connectivity, with constant
//! mass and damping) is evaluated once, when `K`, `M`, `C` and the constant loads are
//! built; after that only the products with those matrices carry it, and the columns a rank
//! keeps of them ([`Assembler::keep_constant_columns`]) are built already. What the
//! assembler evaluates at each step or iteration — the variable elements (the wheels and
//! anything nonlinear), the elements whose mass is re-formed each step, the moving masses'
//! gravity and the carried masses of the vehicles — is kept on every rank, so every rank
//! still forms the same variable triplets and residual terms. Dropping the others changes
//! no number.

use super::Assembler;
use crate::model::Model;
use crate::released::Released;

impl Assembler {
    /// Releases every element that none of the following holds for: it is evaluated after
    /// the build (module documentation); one of its equations `i` has `rows[i]` (the
    /// equations whose columns of `K`, `M`, `C` the rank keeps); `named(user id)` (the
    /// elements a recorder reads). Returns how many were released by this call (elements
    /// released before stay released). Only after [`Assembler::keep_constant_columns`]
    /// answered `true`: the constant matrices are built and the model's structure does not
    /// change (the off-pattern mode never rebuilds it).
    pub fn release_elements(
        &self,
        model: &mut Model,
        rows: &[bool],
        named: &dyn Fn(u64) -> bool,
    ) -> usize {
        if !(self.columns_kept && self.off_pattern) {
            return 0;
        }
        let mut evaluated = vec![false; model.elements.len()];
        let listed = self
            .variable
            .iter()
            .chain(&self.mass_elems)
            .chain(&self.gravity_variable)
            .chain(self.carried_mass.iter().map(|(ei, _)| ei));
        for &ei in listed {
            evaluated[ei] = true;
        }
        let mut released = 0;
        for (ei, entry) in model.elements.iter_mut().enumerate() {
            if evaluated[ei] || Released::is(&*entry.element) || named(entry.id) {
                continue;
            }
            let touches = self.maps[ei].dofs.iter().any(|&(node, d)| {
                self.dofmap
                    .terms_at(node, d)
                    .any(|(e, _)| rows.get(e).copied().unwrap_or(false))
            });
            if !touches {
                entry.element = Box::new(Released::of(&*entry.element));
                released += 1;
            }
        }
        released
    }
}
