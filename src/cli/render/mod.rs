//! `shadelab render`: one scene in one mode into one image file
//! (`single.rs`), or a batch of scenes and modes into a folder
//! (`out_dir.rs`) on the batch machinery that `golden` renders with too
//! (`plan.rs`, `batch.rs`); or a forward render split into shards and
//! merged (`shard.rs`).

mod args;
mod batch;
mod image;
mod out_dir;
mod plan;
mod scene;
mod shard;
mod single;
mod stats;

pub use args::RenderArgs;
pub use batch::{non_finite_failure, Batch, CaseView, Made};
pub use image::image_metadata;
pub use plan::file_name;
pub use scene::load_scene;
pub use single::run;
