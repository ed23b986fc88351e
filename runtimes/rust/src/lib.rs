//! max2code Rust runtime.
//!
//! [`smallest_root`] answers "smallest real root of a polynomial in (lo, hi]"
//! with the algorithm of docs/roots.md, operation for operation the same as the
//! C, Python and Modula-2 runtimes, so that the four return the same bits.

pub mod exact;
pub mod roots;
pub mod sim;
pub mod toi;

pub use roots::{smallest_root, MAX_DEGREE};
