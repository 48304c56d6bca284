//! Maps and sets keyed by vertex, edge or face indices while a hull or a
//! polyhedron is built, hashed by foldhash with a fixed seed (as
//! [`crate::broad_phase::PairMap`]). Building a hull of a few hundred
//! points inserts and looks up thousands of such keys; under the standard
//! library's SipHash, hashing and its tables were about two fifths of the
//! time of a test that builds 20,000 random hulls (perf). Every use here is
//! independent of the iteration order (the results are sorted or do not
//! depend on it), so the hasher changes no output.

/// A hash map keyed by indices (or pairs of them), fixed-seed foldhash.
pub(crate) type IndexMap<K, V> = std::collections::HashMap<K, V, foldhash::fast::FixedState>;

/// A hash set of indices (or pairs of them), fixed-seed foldhash.
pub(crate) type IndexSet<K> = std::collections::HashSet<K, foldhash::fast::FixedState>;
