//! Degrees of freedom: the six per node (ux uy uz rx ry rz) and sets of them.
//!
//! Every node carries the same six DOFs, three translations (m) and three rotations (rad)
//! about the node's axes. A [`DofSet`] is a small bit set used for fixities, for the DOFs an
//! element uses at a node, and for the DOFs a rigid link constrains. Nothing here knows about
//! equation numbers; that lives in [`crate::dofmap`].

use serde::{Deserialize, Serialize};
use std::fmt;

/// One of the six nodal degrees of freedom.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum Dof {
    /// Translation along the node's first axis (m).
    Ux = 0,
    /// Translation along the node's second axis (m).
    Uy = 1,
    /// Translation along the node's third axis (m).
    Uz = 2,
    /// Rotation about the node's first axis (rad).
    Rx = 3,
    /// Rotation about the node's second axis (rad).
    Ry = 4,
    /// Rotation about the node's third axis (rad).
    Rz = 5,
}

impl Dof {
    /// All six DOFs in their canonical order.
    pub const ALL: [Dof; 6] = [Dof::Ux, Dof::Uy, Dof::Uz, Dof::Rx, Dof::Ry, Dof::Rz];

    /// Index 0..6 of this DOF within a node.
    pub fn index(self) -> usize {
        self as usize
    }

    /// The DOF with index `i` (0..6).
    pub fn from_index(i: usize) -> Option<Dof> {
        Dof::ALL.get(i).copied()
    }

    /// The model-file name of this DOF (`"ux"` … `"rz"`).
    pub fn name(self) -> &'static str {
        ["ux", "uy", "uz", "rx", "ry", "rz"][self.index()]
    }

    /// Parses a model-file DOF name (case-insensitive).
    pub fn parse(s: &str) -> Option<Dof> {
        let l = s.to_ascii_lowercase();
        Dof::ALL.iter().copied().find(|d| d.name() == l)
    }
}

impl fmt::Display for Dof {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.name())
    }
}

/// A set of nodal DOFs, stored as a 6-bit mask.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Default)]
pub struct DofSet(u8);

impl DofSet {
    /// No DOF.
    pub const NONE: DofSet = DofSet(0);
    /// All six DOFs.
    pub const ALL: DofSet = DofSet(0b11_1111);
    /// The three translations.
    pub const TRANSLATIONS: DofSet = DofSet(0b00_0111);
    /// The three rotations.
    pub const ROTATIONS: DofSet = DofSet(0b11_1000);

    /// A set from a raw mask (bits above the sixth are dropped).
    pub fn from_bits(bits: u8) -> DofSet {
        DofSet(bits & 0b11_1111)
    }

    /// The raw mask.
    pub fn bits(self) -> u8 {
        self.0
    }

    /// A set holding the given DOFs.
    pub fn of(dofs: &[Dof]) -> DofSet {
        DofSet(dofs.iter().fold(0, |m, d| m | (1 << d.index())))
    }

    /// Whether `d` is in the set.
    pub fn contains(self, d: Dof) -> bool {
        self.0 & (1 << d.index()) != 0
    }

    /// The set with `d` added.
    pub fn with(self, d: Dof) -> DofSet {
        DofSet(self.0 | (1 << d.index()))
    }

    /// Union of two sets.
    pub fn union(self, o: DofSet) -> DofSet {
        DofSet(self.0 | o.0)
    }

    /// Number of DOFs in the set.
    pub fn count(self) -> usize {
        self.0.count_ones() as usize
    }

    /// Whether the set is empty.
    pub fn is_empty(self) -> bool {
        self.0 == 0
    }

    /// The DOFs in canonical order.
    pub fn iter(self) -> impl Iterator<Item = Dof> {
        Dof::ALL.into_iter().filter(move |d| self.contains(*d))
    }
}

/// A word of a model file's DOF list (`fix`, a node recorder's `dofs`, a link's `dofs`):
/// one DOF, or a group of them. Matched exactly, as [`Dof`] is.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Deserialize)]
#[serde(rename_all = "lowercase")]
enum DofWord {
    Ux,
    Uy,
    Uz,
    Rx,
    Ry,
    Rz,
    All,
    Translations,
    Rotations,
}

impl DofWord {
    fn set(self) -> DofSet {
        match self {
            DofWord::Ux => DofSet::of(&[Dof::Ux]),
            DofWord::Uy => DofSet::of(&[Dof::Uy]),
            DofWord::Uz => DofSet::of(&[Dof::Uz]),
            DofWord::Rx => DofSet::of(&[Dof::Rx]),
            DofWord::Ry => DofSet::of(&[Dof::Ry]),
            DofWord::Rz => DofSet::of(&[Dof::Rz]),
            DofWord::All => DofSet::ALL,
            DofWord::Translations => DofSet::TRANSLATIONS,
            DofWord::Rotations => DofSet::ROTATIONS,
        }
    }
}

/// In a model file a set is one word or a list of words, each a DOF name or `"all"`,
/// `"translations"`, `"rotations"` (`fix = "all"`, `dofs = ["uz", "ry"]`); a word outside
/// them is refused with the list of valid ones (serde's message, at the word's key path).
impl<'de> Deserialize<'de> for DofSet {
    fn deserialize<D: serde::Deserializer<'de>>(d: D) -> Result<DofSet, D::Error> {
        struct Words;
        impl<'de> serde::de::Visitor<'de> for Words {
            type Value = DofSet;
            fn expecting(&self, f: &mut fmt::Formatter) -> fmt::Result {
                f.write_str("a DOF name (ux, uy, uz, rx, ry, rz, all, translations, rotations) or a list of them")
            }
            fn visit_str<E: serde::de::Error>(self, v: &str) -> Result<DofSet, E> {
                use serde::de::IntoDeserializer;
                DofWord::deserialize(v.into_deserializer()).map(DofWord::set)
            }
            fn visit_seq<A: serde::de::SeqAccess<'de>>(
                self,
                mut seq: A,
            ) -> Result<DofSet, A::Error> {
                let mut set = DofSet::NONE;
                while let Some(w) = seq.next_element::<DofWord>()? {
                    set = set.union(w.set());
                }
                Ok(set)
            }
        }
        d.deserialize_any(Words)
    }
}

/// Written as the list of its DOF names in canonical order (`["uz", "ry"]`).
impl Serialize for DofSet {
    fn serialize<S: serde::Serializer>(&self, s: S) -> Result<S::Ok, S::Error> {
        s.collect_seq(self.iter().map(Dof::name))
    }
}

impl fmt::Display for DofSet {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let names: Vec<&str> = self.iter().map(Dof::name).collect();
        write!(f, "[{}]", names.join(", "))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn read_write_and_count() {
        let read = |t: &str| serde_json::from_str::<DofSet>(t).map_err(|e| e.to_string());
        let s = read(r#"["ux", "rz"]"#).unwrap();
        assert_eq!(s.count(), 2);
        assert!(s.contains(Dof::Ux) && s.contains(Dof::Rz) && !s.contains(Dof::Uy));
        assert_eq!(read(r#""all""#).unwrap(), DofSet::ALL);
        assert_eq!(
            read(r#"["rotations", "ux"]"#).unwrap(),
            DofSet::ROTATIONS.with(Dof::Ux)
        );
        assert_eq!(serde_json::to_string(&s).unwrap(), r#"["ux","rz"]"#);
        // Outside the words, or another case: refused with the list.
        for bad in [r#"["uz", "uq"]"#, r#""RZ""#] {
            let e = read(bad).unwrap_err();
            assert!(
                e.contains("expected one of `ux`, `uy`, `uz`, `rx`, `ry`, `rz`, `all`, `translations`, `rotations`"),
                "{e}"
            );
        }
        assert!(read("3").unwrap_err().contains("a DOF name"));
        assert_eq!(DofSet::TRANSLATIONS.union(DofSet::ROTATIONS), DofSet::ALL);
    }
}
