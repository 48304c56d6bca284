//! Islands against a brute-force breadth-first search on random graphs.

use crate::support::proptest_config;
use std::collections::VecDeque;

use constraint_stabilization::internals::broad_phase::BodyPair;
use constraint_stabilization::internals::contact::{Island, IslandError, islands};
use proptest::prelude::*;

/// Oracle: components by BFS over dynamic-dynamic edges, started from every
/// dynamic body that has a pair, in increasing body order.
fn islands_by_bfs(fixed: &[bool], pairs: &[BodyPair]) -> Vec<Island> {
    let n = fixed.len();
    let mut adjacency = vec![Vec::new(); n];
    let mut in_pair = vec![false; n];
    for p in pairs {
        in_pair[p.body_a] = true;
        in_pair[p.body_b] = true;
        if !fixed[p.body_a] && !fixed[p.body_b] {
            adjacency[p.body_a].push(p.body_b);
            adjacency[p.body_b].push(p.body_a);
        }
    }
    let mut component = vec![usize::MAX; n];
    let mut result = Vec::new();
    for start in 0..n {
        if fixed[start] || !in_pair[start] || component[start] != usize::MAX {
            continue;
        }
        let id = result.len();
        let mut bodies = vec![];
        let mut queue = VecDeque::from([start]);
        component[start] = id;
        while let Some(b) = queue.pop_front() {
            bodies.push(b);
            for &c in &adjacency[b] {
                if component[c] == usize::MAX {
                    component[c] = id;
                    queue.push_back(c);
                }
            }
        }
        bodies.sort();
        result.push(Island {
            bodies,
            fixed_bodies: vec![],
            pairs: vec![],
            joints: vec![],
        });
    }
    for (k, p) in pairs.iter().enumerate() {
        let dynamic = if fixed[p.body_a] { p.body_b } else { p.body_a };
        if fixed[dynamic] {
            continue;
        }
        let island = &mut result[component[dynamic]];
        island.pairs.push(k);
        for b in [p.body_a, p.body_b] {
            if fixed[b] && !island.fixed_bodies.contains(&b) {
                island.fixed_bodies.push(b);
            }
        }
    }
    for island in &mut result {
        island.fixed_bodies.sort();
    }
    result
}

fn graph() -> impl Strategy<Value = (Vec<bool>, Vec<BodyPair>)> {
    (1usize..40).prop_flat_map(|n| {
        let fixed = prop::collection::vec(prop::bool::weighted(0.2), n);
        let pairs = prop::collection::vec((0..n, 0..n), 0..(2 * n)).prop_map(|raw| {
            raw.into_iter()
                .filter_map(|(i, j)| BodyPair::new(i, j))
                .collect()
        });
        (fixed, pairs)
    })
}

proptest! {
    #![proptest_config(proptest_config::config(300))]

    #[test]
    fn islands_match_breadth_first_search((fixed, pairs) in graph()) {
        let found = islands(&fixed, &pairs).unwrap();
        prop_assert_eq!(&found, &islands_by_bfs(&fixed, &pairs));
        // Every pair with a dynamic body is in exactly one island.
        let assigned: usize = found.iter().map(|i| i.pairs.len()).sum();
        let dynamic_pairs = pairs.iter().filter(|p| !fixed[p.body_a] || !fixed[p.body_b]).count();
        prop_assert_eq!(assigned, dynamic_pairs);
    }

    #[test]
    fn islands_do_not_depend_on_pair_order((fixed, pairs) in graph()) {
        let mut reversed = pairs.clone();
        reversed.reverse();
        let forward = islands(&fixed, &pairs).unwrap();
        let backward = islands(&fixed, &reversed).unwrap();
        let bodies = |v: &[Island]| v.iter().map(|i| i.bodies.clone()).collect::<Vec<_>>();
        prop_assert_eq!(bodies(&forward), bodies(&backward));
    }
}

#[test]
fn fixed_body_does_not_connect_two_dynamic_bodies() {
    // 0 fixed ground, 1 and 2 on it, 3 on top of 2.
    let fixed = [true, false, false, false];
    let pairs = [
        BodyPair::new(0, 1).unwrap(),
        BodyPair::new(0, 2).unwrap(),
        BodyPair::new(2, 3).unwrap(),
    ];
    let found = islands(&fixed, &pairs).unwrap();
    assert_eq!(
        found,
        vec![
            Island {
                bodies: vec![1],
                fixed_bodies: vec![0],
                pairs: vec![0],
                joints: vec![],
            },
            Island {
                bodies: vec![2, 3],
                fixed_bodies: vec![0],
                pairs: vec![1, 2],
                joints: vec![],
            },
        ]
    );
}

#[test]
fn pair_of_two_fixed_bodies_forms_no_island() {
    let found = islands(&[true, true], &[BodyPair::new(0, 1).unwrap()]).unwrap();
    assert!(found.is_empty());
}

#[test]
fn out_of_range_and_self_pairs_are_errors() {
    let far = BodyPair {
        body_a: 0,
        body_b: 5,
    };
    assert_eq!(
        islands(&[false, false], &[far]),
        Err(IslandError::BodyOutOfRange {
            pair: 0,
            body: 5,
            body_count: 2
        })
    );
    let own = BodyPair {
        body_a: 1,
        body_b: 1,
    };
    assert_eq!(
        islands(&[false, false], &[BodyPair::new(0, 1).unwrap(), own]),
        Err(IslandError::SelfPair { pair: 1, body: 1 })
    );
}
