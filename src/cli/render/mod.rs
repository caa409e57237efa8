//! `shadelab render`: one scene in one mode into one image file
//! (`single.rs`), or a batch of scenes and modes into a folder
//! (`out_dir.rs`) on the batch machinery that `golden` renders with too
//! (`common/batch/`); or a forward render split into shards and merged
//! (`shard.rs`).

mod out_dir;
mod shard;
mod single;
mod stats;

pub use single::run;
