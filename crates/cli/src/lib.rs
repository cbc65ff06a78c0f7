//! The `strata` command's library: what its commands do (scene loading with import warnings,
//! device choice, render, study, merge, …), for the `strata` binary (`src/main.rs`, which parses
//! the command line) and for the Python bindings (`crates/python`), so that both load, choose and
//! report alike.
//!
//! Owns: device choice, progress display, Ctrl-C handling, output naming.
//! Must not know: how rendering works (it calls the library crates).

/// `println!` that returns the write error (a closed pipe, as in `strata bench | head`) instead
/// of panicking; `main` treats a broken pipe as the reader having had enough.
macro_rules! out {
    ($($arg:tt)*) => {{
        use std::io::Write as _;
        writeln!(std::io::stdout(), $($arg)*)?
    }};
}

pub mod bench;
pub mod convert;
pub mod device;
pub mod info;
pub mod merge;
pub mod part;
pub mod progress;
pub mod render;
pub mod scene;
pub mod study;
