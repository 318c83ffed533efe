//! Resources shared by the apps of several communities run in one process.
//!
//! One MOOS community is one MOOSDB; on real vehicles communities meet only through a medium:
//! the water between acoustic modems, a radio or Wi-Fi link between surfaced vehicles. When
//! `coug run` runs a whole fleet in one process, the apps that stand for those media (a
//! simulated modem, an in-process bridge) must reach one object across communities. A
//! [`Shared`] is that meeting place: a set of named objects of any type, created by the first
//! app that asks for one and handed to every later app that asks with the same type and name.
//!
//! A single mission gets a fresh [`Shared`] in its [`crate::antler::Launch`]; a fleet run gives
//! every community's launch a clone of the same one.

use std::any::{Any, TypeId};
use std::sync::{Arc, Mutex, PoisonError};

use rustc_hash::FxHashMap;

type Slot = Arc<dyn Any + Send + Sync>;

/// Named objects shared across the communities of one run (cheap to clone: clones share the
/// same set).
#[derive(Clone, Default)]
pub struct Shared {
    objects: Arc<Mutex<FxHashMap<(TypeId, String), Slot>>>,
}

impl Shared {
    /// An empty set.
    pub fn new() -> Shared {
        Shared::default()
    }

    /// The object of type `T` named `name`, made with `make` if nobody has asked for it yet.
    /// Objects of different types may share a name.
    pub fn get_or_insert_with<T, F>(&self, name: &str, make: F) -> Arc<T>
    where
        T: Any + Send + Sync,
        F: FnOnce() -> T,
    {
        let key = (TypeId::of::<T>(), name.to_string());
        let mut objects = self.objects.lock().unwrap_or_else(PoisonError::into_inner);
        let slot = objects
            .entry(key)
            .or_insert_with(|| Arc::new(make()) as Slot)
            .clone();
        drop(objects);
        // The key's TypeId is T's, so the downcast cannot fail.
        slot.downcast::<T>()
            .unwrap_or_else(|_| unreachable!("a shared slot holds the type of its key"))
    }

    /// The object of type `T` named `name`, if one was made.
    pub fn get<T: Any + Send + Sync>(&self, name: &str) -> Option<Arc<T>> {
        let key = (TypeId::of::<T>(), name.to_string());
        let objects = self.objects.lock().unwrap_or_else(PoisonError::into_inner);
        let slot = objects.get(&key)?.clone();
        drop(objects);
        slot.downcast::<T>().ok()
    }

    /// How many objects the set holds.
    pub fn len(&self) -> usize {
        self.objects
            .lock()
            .unwrap_or_else(PoisonError::into_inner)
            .len()
    }

    /// True when nobody has made an object yet.
    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }
}

impl std::fmt::Debug for Shared {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("Shared")
            .field("objects", &self.len())
            .finish()
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::sync::atomic::{AtomicU32, Ordering};

    #[test]
    fn the_first_asker_makes_the_object_and_later_ones_share_it() {
        let shared = Shared::new();
        let other_community = shared.clone();
        let a = shared.get_or_insert_with("acoustic", || AtomicU32::new(7));
        let b = other_community.get_or_insert_with("acoustic", || AtomicU32::new(99));
        a.fetch_add(1, Ordering::SeqCst);
        assert_eq!(b.load(Ordering::SeqCst), 8);
        assert_eq!(shared.len(), 1);
    }

    #[test]
    fn names_and_types_are_separate_keys() {
        let shared = Shared::new();
        let x = shared.get_or_insert_with("radio", || AtomicU32::new(1));
        let y = shared.get_or_insert_with("acoustic", || AtomicU32::new(2));
        let z = shared.get_or_insert_with("radio", || String::from("text"));
        assert_eq!(x.load(Ordering::SeqCst), 1);
        assert_eq!(y.load(Ordering::SeqCst), 2);
        assert_eq!(z.as_str(), "text");
        assert_eq!(shared.len(), 3);
        assert!(shared.get::<u64>("radio").is_none());
        assert_eq!(
            shared.get::<String>("radio").as_deref().map(String::as_str),
            Some("text")
        );
    }

    #[test]
    fn separate_launches_do_not_share() {
        let a = Shared::new();
        let b = Shared::new();
        a.get_or_insert_with("acoustic", || AtomicU32::new(1));
        assert!(b.get::<AtomicU32>("acoustic").is_none());
        assert!(b.is_empty());
    }
}
