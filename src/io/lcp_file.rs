//! The dense LCP file format of the Siconos numerics test suite
//! (`tests/data/siconos/README.md`).
//!
//! Whitespace-separated numbers:
//!
//! ```text
//! n            size
//! 0            storage type (0 = dense, the only type supported)
//! n n          rows, columns
//! n n          rows, columns again
//! n*n numbers  M in COLUMN-MAJOR order (each printed line is a column of M)
//! n numbers    q
//! ```
//!
//! The first token that is not a number (text, or a `#`) starts a trailing
//! comment that is ignored. Too few numbers, extra numbers before the
//! comment, inconsistent sizes, a storage type other than 0 and non-finite
//! entries are errors.

use std::path::Path;

use nalgebra::{DMatrix, DVector};
use thiserror::Error;

use crate::solver::{Lcp, SolverError};

/// Why an LCP file could not be read.
#[derive(Debug, Error, Clone, PartialEq)]
pub enum LcpFileError {
    /// The file could not be read.
    #[error("cannot read {path}: {message}")]
    Io {
        /// The path.
        path: String,
        /// The operating system's message.
        message: String,
    },
    /// A header entry is not a non-negative integer or disagrees with `n`.
    #[error("bad header: {0}")]
    BadHeader(String),
    /// Only dense storage (type 0) is supported.
    #[error("storage type {0} is not supported (only 0, dense)")]
    UnsupportedStorage(f64),
    /// Fewer numbers than the header announces.
    #[error("expected {expected} numbers, found {found}")]
    Truncated {
        /// Numbers the header implies (header included).
        expected: usize,
        /// Numbers found.
        found: usize,
    },
    /// More numbers than the header announces, before any comment.
    #[error("expected {expected} numbers, found {found}: extra numbers before the comment")]
    TrailingNumbers {
        /// Numbers the header implies (header included).
        expected: usize,
        /// Numbers found.
        found: usize,
    },
    /// The numbers do not form a valid LCP (a NaN, say).
    #[error("invalid problem: {0}")]
    Problem(#[from] SolverError),
}

/// Number of header tokens: `n, storage, n, n, n, n`.
const HEADER_LEN: usize = 6;

/// Reads an LCP file.
pub fn read_lcp_file(path: impl AsRef<Path>) -> Result<Lcp, LcpFileError> {
    let path = path.as_ref();
    let text = std::fs::read_to_string(path).map_err(|e| LcpFileError::Io {
        path: path.display().to_string(),
        message: e.to_string(),
    })?;
    parse_lcp(&text)
}

/// Parses the text of an LCP file.
pub fn parse_lcp(text: &str) -> Result<Lcp, LcpFileError> {
    let numbers = leading_numbers(text);
    if numbers.len() < HEADER_LEN {
        return Err(LcpFileError::Truncated {
            expected: HEADER_LEN,
            found: numbers.len(),
        });
    }
    let n = header_size(numbers[0], "n")?;
    if numbers[1] != 0.0 {
        return Err(LcpFileError::UnsupportedStorage(numbers[1]));
    }
    for (k, &v) in numbers[2..HEADER_LEN].iter().enumerate() {
        if header_size(v, "dimension")? != n {
            return Err(LcpFileError::BadHeader(format!(
                "dimension {} is {v}, expected n = {n}",
                k + 1
            )));
        }
    }
    let expected = n
        .checked_mul(n)
        .and_then(|nn| nn.checked_add(n + HEADER_LEN))
        .ok_or_else(|| LcpFileError::BadHeader(format!("n = {n} is too large")))?;
    let found = numbers.len();
    if found < expected {
        return Err(LcpFileError::Truncated { expected, found });
    }
    if found > expected {
        return Err(LcpFileError::TrailingNumbers { expected, found });
    }
    let body = &numbers[HEADER_LEN..];
    let m = DMatrix::from_column_slice(n, n, &body[..n * n]);
    let q = DVector::from_column_slice(&body[n * n..]);
    Ok(Lcp::new(m, q)?)
}

/// The whitespace-separated tokens up to the first that is not a number.
fn leading_numbers(text: &str) -> Vec<f64> {
    text.split_whitespace()
        .map_while(|token| {
            if token.starts_with('#') {
                None
            } else {
                token.parse::<f64>().ok()
            }
        })
        .collect()
}

fn header_size(value: f64, what: &str) -> Result<usize, LcpFileError> {
    let ok = value.is_finite() && value >= 0.0 && value.fract() == 0.0 && value <= u32::MAX as f64;
    if ok {
        Ok(value as usize)
    } else {
        Err(LcpFileError::BadHeader(format!(
            "{what} = {value} is not a non-negative integer"
        )))
    }
}
