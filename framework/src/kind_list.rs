//! What the element, load and recorder registries share: a list of kinds gathered from the
//! static registrations (`inventory::submit!`) and from plugins at run time, sorted by name,
//! looked up by name, a taken name refused ([`KindList`]).

use crate::error::FemError;
use std::sync::Mutex;

/// A registrable kind: a `Copy` descriptor with a type name.
pub trait Kind: Copy + inventory::Collect {
    /// What the kinds are, for messages (`"element"`, `"load"`, `"recorder"`).
    const WHAT: &'static str;
    /// The type name model files use.
    fn name(&self) -> &'static str;
}

/// The kinds registered at run time (plugins) beside the static ones.
pub struct KindList<K: Kind> {
    dynamic: Mutex<Vec<K>>,
}

impl<K: Kind> KindList<K> {
    /// An empty run-time list (a `static`).
    pub const fn new() -> Self {
        KindList {
            dynamic: Mutex::new(Vec::new()),
        }
    }

    /// Registers `kind` at run time; a name that is already registered is refused.
    pub fn register(&self, kind: K) -> Result<(), FemError> {
        if self.find(kind.name()).is_some() {
            return Err(FemError::Plugin(format!(
                "{} type `{}` is already registered; rename the plugin's kind",
                K::WHAT,
                kind.name()
            )));
        }
        self.dynamic
            .lock()
            .unwrap_or_else(|e| e.into_inner())
            .push(kind);
        Ok(())
    }

    /// Every registered kind: static ones first, sorted by name within each source.
    pub fn kinds(&self) -> Vec<K> {
        let mut v: Vec<K> = inventory::iter::<K>.into_iter().copied().collect();
        v.sort_by_key(|k| k.name());
        let mut d = self
            .dynamic
            .lock()
            .unwrap_or_else(|e| e.into_inner())
            .clone();
        d.sort_by_key(|k| k.name());
        v.extend(d);
        v
    }

    /// The kind registered under `name`.
    pub fn find(&self, name: &str) -> Option<K> {
        self.kinds().into_iter().find(|k| k.name() == name)
    }
}

impl<K: Kind> Default for KindList<K> {
    fn default() -> Self {
        Self::new()
    }
}

/// The message for a `type` that no kind is registered under: the registered names and
/// the command that lists their keys (`railfem loads`).
pub fn unknown<K: Kind>(list: &KindList<K>, kind: &str, origin: &str) -> FemError {
    let names: Vec<&str> = list.kinds().iter().map(|k| k.name()).collect();
    FemError::input(
        origin,
        format!(
            "`type` = \"{kind}\" is not a {} type; registered: {} (run `railfem {}s` for their keys; a plugin's type needs --plugin PATH)",
            K::WHAT,
            names.join(", "),
            K::WHAT
        ),
    )
}
