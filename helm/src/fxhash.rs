//! A small, fast, non-cryptographic hasher for the helm's string-keyed maps (info buffer,
//! duplicate filter). The keys are MOOS variable names and filter keys chosen by the mission,
//! not by an adversary, so SipHash's flooding resistance buys nothing here.

use std::collections::{HashMap, HashSet};
use std::hash::{BuildHasherDefault, Hasher};

/// Multiply-rotate word hasher (the scheme of the Firefox/rustc "Fx" hash).
#[derive(Debug, Default, Clone, Copy)]
pub(crate) struct FxHasher {
    hash: u64,
}

const K: u64 = 0x517c_c1b7_2722_0a95;

impl FxHasher {
    #[inline]
    fn add(&mut self, word: u64) {
        self.hash = (self.hash.rotate_left(5) ^ word).wrapping_mul(K);
    }
}

impl Hasher for FxHasher {
    #[inline]
    fn write(&mut self, bytes: &[u8]) {
        self.add(bytes.len() as u64);
        let mut chunks = bytes.chunks_exact(8);
        for c in &mut chunks {
            let mut w = [0u8; 8];
            w.copy_from_slice(c);
            self.add(u64::from_le_bytes(w));
        }
        let rest = chunks.remainder();
        if !rest.is_empty() {
            let mut w = [0u8; 8];
            w[..rest.len()].copy_from_slice(rest);
            self.add(u64::from_le_bytes(w));
        }
    }
    #[inline]
    fn write_u8(&mut self, i: u8) {
        self.add(u64::from(i));
    }
    #[inline]
    fn write_u64(&mut self, i: u64) {
        self.add(i);
    }
    #[inline]
    fn write_usize(&mut self, i: usize) {
        self.add(i as u64);
    }
    #[inline]
    fn finish(&self) -> u64 {
        self.hash
    }
}

/// A `HashMap` with [`FxHasher`].
pub(crate) type FxHashMap<K, V> = HashMap<K, V, BuildHasherDefault<FxHasher>>;

/// A `HashSet` with [`FxHasher`].
pub(crate) type FxHashSet<K> = HashSet<K, BuildHasherDefault<FxHasher>>;

#[cfg(test)]
mod tests {
    use super::*;
    use std::hash::{BuildHasher, BuildHasherDefault};

    #[test]
    fn equal_strings_hash_equal_and_lengths_matter() {
        let b = BuildHasherDefault::<FxHasher>::default();
        assert_eq!(b.hash_one("NAV_X"), b.hash_one(String::from("NAV_X")));
        assert_ne!(b.hash_one("NAV_X"), b.hash_one("NAV_Y"));
        // The length is mixed in, so a zero-padded tail does not collide.
        assert_ne!(b.hash_one("A"), b.hash_one("A\0"));
        let mut m: FxHashMap<String, u32> = FxHashMap::default();
        for (i, k) in ["a", "bb", "ccc", "dddddddd", "eeeeeeeee"]
            .iter()
            .enumerate()
        {
            m.insert(k.to_string(), i as u32);
        }
        assert_eq!(m.get("dddddddd"), Some(&3));
        assert_eq!(m.get("eeeeeeeee"), Some(&4));
        assert_eq!(m.get("e"), None);
    }
}
