//! Exit codes of docs/design.md section 8 and the messages that go with them.

use std::fmt::Display;
use std::process::ExitCode;

/// The problem was read but not solved.
pub const NOT_SOLVED: u8 = 1;
/// Bad input or usage.
pub const BAD_INPUT: u8 = 2;

/// Prints the error and returns exit code 2.
pub fn bad_input(error: &dyn Display) -> ExitCode {
    eprintln!("stabilize: {error}");
    ExitCode::from(BAD_INPUT)
}

/// Prints the error and returns exit code 1.
pub fn not_solved(error: &dyn Display) -> ExitCode {
    eprintln!("stabilize: not solved: {error}");
    ExitCode::from(NOT_SOLVED)
}
