//! The live compliance table: one entry per cloth and kind of constraint
//! (stretch, shear, bending, crease, facet), read by both backends at every
//! step, so a slider that changes a compliance needs no rebuild and keeps
//! the state.
//!
//! A constraint holds the index of its entry (`slot`) and a factor
//! (`compliance`): it projects with compliance `compliance * table[slot]`.
//! Constraints built from a material have factor 1 (or `1 / length` for
//! the hinges of paper, whose stiffness is per unit length); entry 0 is
//! always 1, so a constraint in slot 0 keeps the compliance it was built with.

use crate::model::{ClothPart, Model};

/// What a live compliance applies to, within one cloth.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum ComplianceKind {
    /// Structural edges ([`crate::Material::stretch_compliance`]).
    Stretch = 0,
    /// Diagonal edges of grids ([`crate::Material::shear_compliance`]).
    Shear = 1,
    /// Bending, dihedral, isometric or skip-one ([`crate::Material::bend_compliance`]).
    Bend = 2,
    /// Mountain and valley hinges of paper, per unit length
    /// ([`crate::paper::PaperStiffness::crease_compliance`]).
    Crease = 3,
    /// Facet hinges of paper, per unit length
    /// ([`crate::paper::PaperStiffness::facet_compliance`]).
    Facet = 4,
}

/// Kinds per cloth.
const KINDS: usize = 5;

/// The slot of a stretch that holds whatever the compliances (a cloth
/// with a strain limit, paper): no table entry.
pub const ALWAYS_HELD: u32 = u32::MAX;

/// The table a constraint in slot 0 reads: its compliance as built.
pub const AS_BUILT: &[f32] = &[1.0];

/// Every cloth's live compliances, slot 0 first.
#[derive(Clone, Debug, PartialEq)]
pub struct Compliances {
    values: Vec<f32>,
}

impl Compliances {
    /// The compliances of `model`'s materials and paper stiffness.
    pub fn of(model: &Model) -> Self {
        let mut values = vec![1.0];
        for cloth in &model.cloths {
            let m = &cloth.material;
            let paper = cloth
                .paper
                .as_ref()
                .map(|p| p.stiffness)
                .unwrap_or_default();
            values.extend([
                m.stretch_compliance,
                m.shear_compliance,
                m.bend_compliance,
                paper.crease_compliance,
                paper.facet_compliance,
            ]);
        }
        Compliances { values }
    }

    /// The slot of cloth `cloth`'s compliance of `kind`.
    pub fn slot(cloth: usize, kind: ComplianceKind) -> u32 {
        (1 + cloth * KINDS + kind as usize) as u32
    }

    /// Cloth `cloth`'s compliance of `kind`, if the cloth exists.
    pub fn get(&self, cloth: usize, kind: ComplianceKind) -> Option<f32> {
        self.values.get(Self::slot(cloth, kind) as usize).copied()
    }

    /// The compliance in `slot` as the table holds it (negative as zero),
    /// if the slot exists.
    pub fn at(&self, slot: u32) -> Option<f32> {
        self.values.get(slot as usize).map(|v| v.max(0.0))
    }

    /// The slot that decides whether cloth `index`'s stretch is held (it
    /// is while its live stretch compliance is zero), or [`ALWAYS_HELD`]
    /// where a strain limit holds it whatever the compliance.
    pub fn held_slot(cloth: &ClothPart, index: usize) -> u32 {
        match cloth.material.max_strain {
            Some(_) => ALWAYS_HELD,
            None => Self::slot(index, ComplianceKind::Stretch),
        }
    }

    /// Whether `slot` ([`Compliances::held_slot`]) holds its cloth's
    /// stretch now.
    pub fn holds(&self, slot: u32) -> bool {
        slot == ALWAYS_HELD || self.at(slot) == Some(0.0)
    }

    /// Cloth `cloth`'s compliance of `kind`, to change from the next step
    /// on (a negative value counts as zero), if the cloth exists.
    pub fn get_mut(&mut self, cloth: usize, kind: ComplianceKind) -> Option<&mut f32> {
        self.values.get_mut(Self::slot(cloth, kind) as usize)
    }

    /// The table, slot by slot, negative values as zero.
    pub fn table(&self) -> impl Iterator<Item = f32> + '_ {
        self.values.iter().map(|v| v.max(0.0))
    }

    /// Copies the table (negative values as zero) into `out`, reusing its memory.
    pub fn write_to(&self, out: &mut Vec<f32>) {
        out.clear();
        out.extend(self.table());
    }

    /// Number of slots.
    pub fn len(&self) -> usize {
        self.values.len()
    }

    /// Whether the table is empty (never: slot 0 is always there).
    pub fn is_empty(&self) -> bool {
        self.values.is_empty()
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::material::Material;
    use crate::mesh::GridSpec;

    #[test]
    fn slots_follow_cloths_and_kinds_and_slot_zero_is_one() {
        let mut model = Model::default();
        for stretch in [1e-3, 2e-3] {
            let material = Material {
                stretch_compliance: stretch,
                ..Material::default()
            };
            let mesh = GridSpec::new(2, 2, [1.0, 1.0]).build();
            model.add_cloth("c", mesh, material, &[], false);
        }
        let mut c = Compliances::of(&model);
        assert_eq!(c.len(), 11);
        assert_eq!(c.get(1, ComplianceKind::Stretch), Some(2e-3));
        *c.get_mut(0, ComplianceKind::Bend).unwrap() = -1.0;
        let table: Vec<f32> = c.table().collect();
        assert_eq!(table[0], 1.0);
        assert_eq!(
            table[Compliances::slot(0, ComplianceKind::Bend) as usize],
            0.0
        );
        assert_eq!(c.get(2, ComplianceKind::Stretch), None);
    }
}
