//! What more than one command uses, so that no command imports another:
//! the flags they share, how a command fails, progress lines, cases run
//! side by side, shards and their records, run digests, the flags a
//! backend ignores, and the batch of renders that `render --out-dir` and
//! `golden` both run on (with `load_scene`, which every command that
//! renders loads its scenes with).

pub mod args;
pub mod batch;
pub mod cases;
pub mod failure;
pub mod ignored;
pub mod progress;
pub mod run_digest;
pub mod shard_env;
pub mod shards;
