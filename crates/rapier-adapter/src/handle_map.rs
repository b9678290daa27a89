//! Per-handle storage: values kept by a rapier handle's index together
//! with the handle's generation, so that a value stored for one collider
//! or body is never read through a handle that reuses its slot (rapier
//! hands a removed collider's index to the next one it inserts, with a
//! new generation). rapier's own `Coarena` does the same; this one also
//! holds values that are not `Clone` (the hook's atomics) and is generic
//! over the handle type.

use std::marker::PhantomData;

use crate::rapier::prelude::{ColliderHandle, RigidBodyHandle};

/// A rapier handle: an index into its set and a generation.
pub(crate) trait Handle: Copy {
    /// `(index, generation)`.
    fn parts(self) -> (u32, u32);
    /// The handle of `index` and `generation`.
    fn from_parts(index: u32, generation: u32) -> Self;
}

impl Handle for ColliderHandle {
    #[inline]
    fn parts(self) -> (u32, u32) {
        self.into_raw_parts()
    }
    #[inline]
    fn from_parts(index: u32, generation: u32) -> Self {
        Self::from_raw_parts(index, generation)
    }
}

impl Handle for RigidBodyHandle {
    #[inline]
    fn parts(self) -> (u32, u32) {
        self.into_raw_parts()
    }
    #[inline]
    fn from_parts(index: u32, generation: u32) -> Self {
        Self::from_raw_parts(index, generation)
    }
}

/// The generation of an empty slot (rapier's `Coarena` uses the same).
const EMPTY: u32 = u32::MAX;

/// A value per handle `H`, stored by the handle's index with its
/// generation: [`HandleMap::get`] finds it only through that handle.
#[derive(Clone, Debug)]
pub(crate) struct HandleMap<H, T> {
    slots: Vec<(u32, T)>,
    handle: PhantomData<H>,
}

impl<H, T> Default for HandleMap<H, T> {
    fn default() -> Self {
        Self {
            slots: Vec::new(),
            handle: PhantomData,
        }
    }
}

impl<H: Handle, T> HandleMap<H, T> {
    /// The value of `handle`, if one is stored for it.
    #[inline]
    pub(crate) fn get(&self, handle: H) -> Option<&T> {
        let (index, generation) = handle.parts();
        match self.slots.get(index as usize) {
            Some((g, value)) if *g == generation => Some(value),
            _ => None,
        }
    }

    /// The value of `handle`, mutably, if one is stored for it.
    #[inline]
    pub(crate) fn get_mut(&mut self, handle: H) -> Option<&mut T> {
        let (index, generation) = handle.parts();
        match self.slots.get_mut(index as usize) {
            Some((g, value)) if *g == generation => Some(value),
            _ => None,
        }
    }

    /// The value stored at `index` for whichever handle holds that index,
    /// for an index read from rapier's own structures (its broad-phase
    /// tree's leaves, which hold only live colliders), whose generation
    /// would cost a read of the collider.
    #[inline]
    pub(crate) fn get_by_index(&self, index: u32) -> Option<&T> {
        match self.slots.get(index as usize) {
            Some((g, value)) if *g != EMPTY => Some(value),
            _ => None,
        }
    }

    /// The value of `handle`, made by `make` if none is stored for it (a
    /// value of an older handle in its slot is replaced).
    #[inline]
    pub(crate) fn get_or_insert_with(&mut self, handle: H, make: impl FnMut() -> T) -> &mut T {
        let (index, generation) = handle.parts();
        let index = index as usize;
        if self.slots.len() <= index {
            let mut make = make;
            self.slots.resize_with(index + 1, || (EMPTY, make()));
            self.slots[index].0 = generation;
            return &mut self.slots[index].1;
        }
        let slot = &mut self.slots[index];
        if slot.0 != generation {
            let mut make = make;
            *slot = (generation, make());
        }
        &mut slot.1
    }

    /// Store `value` for `handle` (replacing any value of its slot).
    #[inline]
    pub(crate) fn insert(&mut self, handle: H, value: T)
    where
        T: Default,
    {
        *self.get_or_insert_with(handle, T::default) = value;
    }

    /// Take the value of `handle` out, leaving its slot empty.
    pub(crate) fn remove(&mut self, handle: H) -> Option<T>
    where
        T: Default,
    {
        let (index, generation) = handle.parts();
        match self.slots.get_mut(index as usize) {
            Some(slot) if slot.0 == generation => {
                slot.0 = EMPTY;
                Some(std::mem::take(&mut slot.1))
            }
            _ => None,
        }
    }

    /// The handles with a value, in index order, with their values.
    pub(crate) fn iter(&self) -> impl Iterator<Item = (H, &T)> {
        self.slots
            .iter()
            .enumerate()
            .filter(|(_, (g, _))| *g != EMPTY)
            .map(|(index, (g, value))| (H::from_parts(index as u32, *g), value))
    }

    /// Forget every value (keeping the storage).
    pub(crate) fn clear(&mut self) {
        self.slots.clear();
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A value is found through its own handle only: not through a handle
    /// of another generation in the same slot, and not once removed; a
    /// newer handle's value replaces an older one's.
    #[test]
    fn a_value_is_read_only_through_its_own_handle() {
        let mut map: HandleMap<ColliderHandle, u32> = HandleMap::default();
        let old = ColliderHandle::from_raw_parts(3, 0);
        let new = ColliderHandle::from_raw_parts(3, 1);
        map.insert(old, 7);
        assert_eq!(map.get(old), Some(&7));
        assert_eq!(map.get(new), None);
        assert_eq!(map.get(ColliderHandle::from_raw_parts(2, 0)), None);
        assert_eq!(*map.get_or_insert_with(new, || 9), 9);
        assert_eq!(map.get(old), None);
        assert_eq!(map.get_by_index(3), Some(&9));
        assert_eq!(map.iter().collect::<Vec<_>>(), vec![(new, &9)]);
        assert_eq!(map.remove(old), None);
        assert_eq!(map.remove(new), Some(9));
        assert_eq!(map.get(new), None);
        assert_eq!(map.get_by_index(3), None);
        assert_eq!(map.iter().count(), 0);
    }
}
