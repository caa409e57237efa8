//! The docs kept true: every path they name exists, the synopses match
//! `--help`, and the README's tour and docs/golden.md's recipe run as
//! written.

#[path = "../common/mod.rs"]
mod common;

mod golden_recipe;
mod paths;
mod readme_tour;
mod synopses;
