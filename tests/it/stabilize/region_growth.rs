use constraint_stabilization::internals::broad_phase::BodyPair;
use constraint_stabilization::internals::stabilizer::region::*;

fn pair(a: usize, b: usize) -> BodyPair {
    BodyPair::new(a, b).expect("distinct bodies")
}

/// A chain 1-2-...-20 whose first body penetrates the ground (0, fixed)
/// starts with that body and its neighbour, then grows by the pushed
/// body and two hops, then four, and past half the chain becomes all
/// of it.
#[test]
fn a_chain_grows_by_doubling_hops() {
    let bodies: Vec<usize> = (1..=20).collect();
    let pairs: Vec<_> = (1..20).map(|i| pair(i, i + 1)).collect();
    let mut region = Region::new(&bodies, &pairs, &[pair(0, 1)]);
    assert_eq!(region.bodies(), vec![1, 2]);
    assert!(region.holds_still(3) && !region.holds_still(2) && !region.holds_still(0));
    region.grow(&[3]);
    assert_eq!(region.bodies(), vec![1, 2, 3, 4, 5]);
    region.grow(&[6]);
    assert_eq!(region.bodies(), (1..=10).collect::<Vec<_>>());
    assert!(!region.is_whole());
    region.grow(&[11]);
    assert!(region.is_whole());
}

/// With nothing pushed (the region's problem failed) the border grows.
#[test]
fn a_failed_region_grows_its_border() {
    let bodies: Vec<usize> = (1..=20).collect();
    let pairs: Vec<_> = (1..20).map(|i| pair(i, i + 1)).collect();
    let mut region = Region::new(&bodies, &pairs, &[pair(9, 10)]);
    assert_eq!(region.bodies(), (8..=11).collect::<Vec<_>>());
    region.grow(&[]);
    assert_eq!(region.bodies(), (6..=13).collect::<Vec<_>>());
}
