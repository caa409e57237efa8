//! shadelab's cache folder: one place that a CI job can keep between runs.
//!
//! `$SHADELAB_CACHE_DIR`, else `$XDG_CACHE_HOME/shadelab`, else
//! `~/.cache/shadelab`. It holds SPIR-V modules that took work to make
//! (`hooks/`: the shaders compiled with a user's lighting hook;
//! `spirv/`: modules specialised to a scene; `bvh/`: the GPU's trees over
//! big meshes, keyed by the triangles) and, unless the user points
//! it elsewhere, Mesa's shader cache (`mesa-<configuration>/`: lavapipe's
//! machine code, the costliest thing a fresh machine makes).
//!
//! Every entry is keyed by all that went into it and is only ever a saving:
//! a folder that cannot be read or written is no cache, never an error.

use std::ffi::OsString;
use std::hash::{Hash, Hasher};
use std::path::{Path, PathBuf};

/// The cache folder, or `None` where no variable names one.
pub fn folder() -> Option<PathBuf> {
    folder_from(|name| std::env::var_os(name))
}

fn folder_from(env: impl Fn(&str) -> Option<OsString>) -> Option<PathBuf> {
    let env = |name| env(name).filter(|v| !v.is_empty());
    env("SHADELAB_CACHE_DIR")
        .map(PathBuf::from)
        .or_else(|| env("XDG_CACHE_HOME").map(|d| PathBuf::from(d).join("shadelab")))
        .or_else(|| env("HOME").map(|d| PathBuf::from(d).join(".cache/shadelab")))
}

/// A stable 64-bit digest of `value` for file names (std's SipHash with its
/// fixed keys: the same in every run of a build; a different Rust may
/// hash differently, which costs one cold run and nothing else).
pub fn digest(value: &impl Hash) -> u64 {
    let mut hasher = std::collections::hash_map::DefaultHasher::new();
    value.hash(&mut hasher);
    hasher.finish()
}

/// Where the module of `key` lives in `kind`'s subfolder.
fn module_path(kind: &str, key: &str) -> Option<PathBuf> {
    entry_path(kind, key, "spv")
}

fn entry_path(kind: &str, key: &str, extension: &str) -> Option<PathBuf> {
    Some(entry_in(&folder()?, kind, key, extension))
}

fn entry_in(folder: &Path, kind: &str, key: &str, extension: &str) -> PathBuf {
    folder
        .join(kind)
        .join(format!("{:016x}.{extension}", digest(&key)))
}

/// The words of a data entry (not a module: `bvh/`) cached under `key` in
/// `kind` of `folder`, if any. The caller checks what they hold.
pub fn read_words(folder: &Path, kind: &str, key: &str) -> Option<Vec<u32>> {
    read_keyed(&entry_in(folder, kind, key, "bin"), key)
}

/// Keeps the words of a data entry under `key` in `kind` of `folder`; best
/// effort.
pub fn write_words(folder: &Path, kind: &str, key: &str, words: &[u32]) {
    write_keyed(&entry_in(folder, kind, key, "bin"), key, words);
}

/// The SPIR-V words cached under `key` in `kind`, if any.
pub fn read_module(kind: &str, key: &str) -> Option<Vec<u32>> {
    read_keyed(&module_path(kind, key)?, key)
}

/// Keeps `words` under `key` in `kind`; best effort.
pub fn write_module(kind: &str, key: &str, words: &[u32]) {
    if let Some(path) = module_path(kind, key) {
        write_keyed(&path, key, words);
    }
}

/// Removes all but the `keep` newest entries (by modification time) of
/// `kind` in `folder`: for kinds whose keys a user can make without end
/// (`bvh/`: a tree per camera position). Best effort.
pub fn keep_newest(folder: &Path, kind: &str, keep: usize) {
    let Ok(entries) = std::fs::read_dir(folder.join(kind)) else {
        return;
    };
    let mut files: Vec<(std::time::SystemTime, PathBuf)> = entries
        .filter_map(|e| {
            let e = e.ok()?;
            let modified = e.metadata().ok()?.modified().ok()?;
            Some((modified, e.path()))
        })
        .collect();
    if files.len() <= keep {
        return;
    }
    files.sort_unstable_by(|a, b| b.cmp(a));
    for (_, path) in &files[keep..] {
        let _ = std::fs::remove_file(path);
    }
}

/// The words in `path`, if the file holds this very key (a hash collision
/// or a torn write reads as a miss).
fn read_keyed(path: &Path, key: &str) -> Option<Vec<u32>> {
    let bytes = std::fs::read(path).ok()?;
    let rest = bytes.strip_prefix(key.as_bytes())?.strip_prefix(b"\n")?;
    if rest.is_empty() || rest.len() % 4 != 0 {
        return None;
    }
    Some(
        rest.chunks_exact(4)
            .map(|c| u32::from_le_bytes([c[0], c[1], c[2], c[3]]))
            .collect(),
    )
}

/// Best effort: a cache that cannot be written is no cache. Written to a
/// temporary name, then renamed, so a reader never sees half a module.
fn write_keyed(path: &Path, key: &str, words: &[u32]) {
    let Some(dir) = path.parent() else { return };
    if std::fs::create_dir_all(dir).is_err() {
        return;
    }
    let mut bytes = Vec::with_capacity(key.len() + 1 + words.len() * 4);
    bytes.extend_from_slice(key.as_bytes());
    bytes.push(b'\n');
    bytes.extend(words.iter().flat_map(|w| w.to_le_bytes()));
    // A name of this writer's own, process and write: two threads of one
    // process (the test binaries run many renders side by side) writing
    // the same key would otherwise share a temporary file, and one's rename
    // could publish the other's half-written bytes.
    static WRITES: std::sync::atomic::AtomicU64 = std::sync::atomic::AtomicU64::new(0);
    let write = WRITES.fetch_add(1, std::sync::atomic::Ordering::Relaxed);
    let temp = path.with_extension(format!("tmp{}-{write}", std::process::id()));
    if std::fs::write(&temp, &bytes).is_ok() && std::fs::rename(&temp, path).is_err() {
        let _ = std::fs::remove_file(&temp);
    }
}

/// What changes the machine code lavapipe generates for the same shader,
/// beyond Mesa's own build (which Mesa's cache keys on itself): the CPU's
/// features and the variables that choose the code generator's vector width
/// and options. A cache made under one of these must not be handed to
/// another (a cache shared between runners, or a run with
/// `LP_NATIVE_VECTOR_WIDTH=128`).
const CODEGEN_VARIABLES: [&str; 4] = [
    "LP_NATIVE_VECTOR_WIDTH",
    "GALLIVM_PERF",
    "GALLIVM_DEBUG",
    "LP_PERF",
];

/// The name of Mesa's cache folder for this machine and configuration.
fn mesa_folder_name(cpu_flags: &str, env: impl Fn(&str) -> Option<OsString>) -> String {
    let variables: Vec<(&str, Option<OsString>)> =
        CODEGEN_VARIABLES.iter().map(|&n| (n, env(n))).collect();
    format!("mesa-{:016x}", digest(&(cpu_flags, variables)))
}

/// The CPU's feature flags as the kernel lists them (empty where unknown).
fn cpu_flags() -> String {
    std::fs::read_to_string("/proc/cpuinfo")
        .ok()
        .and_then(|info| {
            info.lines()
                .find(|l| l.starts_with("flags"))
                .map(str::to_string)
        })
        .unwrap_or_default()
}

/// Points Mesa's shader cache into the cache folder (`mesa-<configuration>`,
/// see `CODEGEN_VARIABLES`), or into that subfolder of the folder the user
/// chose (`MESA_SHADER_CACHE_DIR`), unless the user turned it off
/// (`MESA_SHADER_CACHE_DISABLE`).
/// Returns the folder named, if any; Mesa makes it when the driver first
/// uses it, so a command that never opens the GPU leaves nothing behind.
///
/// Sets an environment variable that the driver reads when it loads: call it
/// before any other thread starts (the first thing `main` does).
///
/// Where the cache folder cannot be written (a read-only home, a CI cache
/// mounted read-only), Mesa's cache is turned off instead, which silences
/// the driver's four "Failed to create ... for shader cache" lines per
/// run, and the warning to print is returned: every run then generates
/// its shaders' code again.
pub fn use_for_mesa_shader_cache() -> Result<Option<PathBuf>, String> {
    let env = |name: &str| std::env::var_os(name);
    if env("MESA_SHADER_CACHE_DISABLE").is_some() {
        return Ok(None);
    }
    if let Some(chosen) = env("MESA_SHADER_CACHE_DIR").filter(|d| !d.is_empty()) {
        // The user's folder, but one under it per configuration all the
        // same: lavapipe's own cache key misses LP_NATIVE_VECTOR_WIDTH, and
        // code built at one width crashed renders at another (issue 30).
        let dir = PathBuf::from(chosen).join(mesa_folder_name(&cpu_flags(), env));
        // Only while no other thread runs: getenv in another thread may race.
        std::env::set_var("MESA_SHADER_CACHE_DIR", &dir);
        return Ok(Some(dir));
    }
    let Some(base) = folder() else {
        return Ok(None);
    };
    if let Some(why) = cannot_write(&base) {
        // Only while no other thread runs: getenv in another thread may race.
        std::env::set_var("MESA_SHADER_CACHE_DISABLE", "true");
        return Err(format!(
            "the cache folder {} cannot be written ({why}): every run generates its shaders' code again; set SHADELAB_CACHE_DIR to a folder that can be",
            base.display()
        ));
    }
    let dir = base.join(mesa_folder_name(&cpu_flags(), env));
    // Only while no other thread runs: getenv in another thread may race.
    std::env::set_var("MESA_SHADER_CACHE_DIR", &dir);
    Ok(Some(dir))
}

/// Why nothing can be written in `dir` (or, where it does not exist yet,
/// in the nearest folder above it that does, where it would be made);
/// `None` when a probe file can be made and removed. Leaves nothing.
fn cannot_write(dir: &Path) -> Option<String> {
    let mut existing = dir;
    while !existing.exists() {
        existing = existing.parent()?;
    }
    let probe = existing.join(format!(".shadelab-probe.{}.tmp", std::process::id()));
    match std::fs::write(&probe, b"") {
        Ok(()) => {
            let _ = std::fs::remove_file(&probe);
            None
        }
        Err(e) => Some(e.to_string()),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_folder_is_writable_where_it_or_the_folder_it_would_be_made_in_is() {
        let dir = tempfile::tempdir().unwrap();
        assert_eq!(cannot_write(&dir.path().join("not/yet/made")), None);
        assert!(!dir.path().join("not").exists(), "the probe made a folder");
        let blocker = dir.path().join("file");
        std::fs::write(&blocker, b"").unwrap();
        assert!(cannot_write(&blocker.join("cache")).is_some());
        assert_eq!(
            std::fs::read_dir(dir.path()).unwrap().count(),
            1,
            "the probe stayed"
        );
    }

    #[test]
    fn only_the_newest_entries_of_a_kind_are_kept() {
        let dir = tempfile::tempdir().unwrap();
        let kind = dir.path().join("bvh");
        std::fs::create_dir_all(&kind).unwrap();
        let start = std::time::SystemTime::UNIX_EPOCH + std::time::Duration::from_secs(1_000_000);
        for k in 0..5u64 {
            let path = kind.join(format!("{k}.bin"));
            let file = std::fs::File::create(&path).unwrap();
            file.set_modified(start + std::time::Duration::from_secs(k))
                .unwrap();
        }
        keep_newest(dir.path(), "bvh", 2);
        let mut left: Vec<String> = std::fs::read_dir(&kind)
            .unwrap()
            .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
            .collect();
        left.sort();
        assert_eq!(left, ["3.bin", "4.bin"]);
        // A folder that is not there is no error.
        keep_newest(dir.path(), "none", 2);
    }

    #[test]
    fn a_cached_module_reads_back_only_under_its_own_key() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("hooks").join("m.spv");
        let words = vec![0x0723_0203, 1, 2, 0xdead_beef];
        write_keyed(&path, "key one", &words);
        assert_eq!(read_keyed(&path, "key one"), Some(words.clone()));
        assert_eq!(read_keyed(&path, "key two"), None);
        // A torn file (a word cut short) is a miss, not a bad module.
        let mut bytes = std::fs::read(&path).unwrap();
        bytes.pop();
        std::fs::write(&path, bytes).unwrap();
        assert_eq!(read_keyed(&path, "key one"), None);
    }

    #[test]
    fn the_folder_follows_the_variables_in_order() {
        fn env<'a>(pairs: &'a [(&str, &str)]) -> impl Fn(&str) -> Option<OsString> + 'a {
            move |name: &str| {
                pairs
                    .iter()
                    .find(|(n, _)| *n == name)
                    .map(|(_, v)| OsString::from(v))
            }
        }
        let all = [
            ("SHADELAB_CACHE_DIR", "/a"),
            ("XDG_CACHE_HOME", "/b"),
            ("HOME", "/c"),
        ];
        assert_eq!(folder_from(env(&all)), Some(PathBuf::from("/a")));
        assert_eq!(
            folder_from(env(&[("SHADELAB_CACHE_DIR", ""), ("XDG_CACHE_HOME", "/b")])),
            Some(PathBuf::from("/b/shadelab"))
        );
        assert_eq!(
            folder_from(env(&[("HOME", "/c")])),
            Some(PathBuf::from("/c/.cache/shadelab"))
        );
        assert_eq!(folder_from(env(&[])), None);
    }

    /// A cache made for one code generator configuration is never handed to
    /// another: the vector width, the CPU and the generator's options each
    /// name a folder of their own; unrelated variables do not.
    #[test]
    fn mesa_gets_a_folder_per_code_generator_configuration() {
        let with = |name: &'static str, value: &'static str| {
            move |n: &str| (n == name).then(|| OsString::from(value))
        };
        let none = |_: &str| None;
        let base = mesa_folder_name("flags: avx2 avx512f", none);
        assert_eq!(base, mesa_folder_name("flags: avx2 avx512f", none));
        assert_ne!(base, mesa_folder_name("flags: avx2", none));
        for variable in CODEGEN_VARIABLES {
            assert_ne!(
                base,
                mesa_folder_name("flags: avx2 avx512f", with(variable, "128")),
                "{variable}"
            );
        }
        assert_eq!(
            base,
            mesa_folder_name("flags: avx2 avx512f", with("LP_NUM_THREADS", "8"))
        );
    }
}
