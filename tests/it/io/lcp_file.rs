//! The LCP file reader on malformed input (the well-formed files are read
//! by `solver::lcp_siconos`).

use constraint_stabilization::io::{LcpFileError, parse_lcp};
use constraint_stabilization::solver::SolverError;

#[test]
fn trailing_comment_is_ignored() {
    let lcp = parse_lcp("1\n0\n1\n1\n1 1\n2\n-3\n\nExample: a comment 1 2 3\n").unwrap();
    assert_eq!(lcp.m()[(0, 0)], 2.0);
    assert_eq!(lcp.q()[0], -3.0);
    let lcp = parse_lcp("1 0 1 1 1 1 2 -3 # 4 5").unwrap();
    assert_eq!(lcp.q()[0], -3.0);
}

#[test]
fn malformed_files_are_errors() {
    assert_eq!(
        parse_lcp("").unwrap_err(),
        LcpFileError::Truncated {
            expected: 6,
            found: 0
        }
    );
    assert_eq!(
        parse_lcp("2 0 2 2 2 2 1 0 0 1 -1").unwrap_err(),
        LcpFileError::Truncated {
            expected: 12,
            found: 11
        }
    );
    assert_eq!(
        parse_lcp("1 0 1 1 1 1 2 -3 7").unwrap_err(),
        LcpFileError::TrailingNumbers {
            expected: 8,
            found: 9
        }
    );
    assert_eq!(
        parse_lcp("1 1 1 1 1 1 2 -3").unwrap_err(),
        LcpFileError::UnsupportedStorage(1.0)
    );
    assert!(matches!(
        parse_lcp("1 0 2 1 1 1 2 -3").unwrap_err(),
        LcpFileError::BadHeader(_)
    ));
    assert!(matches!(
        parse_lcp("1.5 0 1 1 1 1 2 -3").unwrap_err(),
        LcpFileError::BadHeader(_)
    ));
    assert!(matches!(
        parse_lcp("-1 0 1 1 1 1 2 -3").unwrap_err(),
        LcpFileError::BadHeader(_)
    ));
    assert_eq!(
        parse_lcp("1 0 1 1 1 1 nan -3").unwrap_err(),
        LcpFileError::Problem(SolverError::NonFinite {
            what: "M",
            index: 0
        })
    );
    assert_eq!(
        parse_lcp("1 0 1 1 1 1 1 inf").unwrap_err(),
        LcpFileError::Problem(SolverError::NonFinite {
            what: "q",
            index: 0
        })
    );
    // A huge n with few numbers is truncated, not a huge allocation.
    assert!(matches!(
        parse_lcp("4000000000 0 4000000000 4000000000 4000000000 4000000000 1").unwrap_err(),
        LcpFileError::Truncated { .. }
    ));
}
