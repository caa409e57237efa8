//! The memory a render will take, estimated before anything large is
//! allocated, and the limit it must stay under.
//!
//! The estimate is a line per kind of work: a fixed base (the driver, its
//! compiler, the program) plus bytes per object, vertex, triangle and
//! pixel. The coefficients were fitted to peak resident memory measured on
//! three scenes that separate them (a 400k-triangle sphere, the same
//! triangle count as unshared triangles, 200k one-triangle instances) and
//! on large images, then rounded up: the estimate errs high. The GPU's base
//! includes the Khronos validation layer's 25 MB, which the tests turn on.
//! `docs/memory.md` has the measurements and the command that repeats them.

use crate::error::Error;
use crate::msaa::Msaa;
use crate::scene::footprint::{format_bytes, scene_texture_bytes, TEXEL_COPIES};
use crate::scene::{GeometrySize, LoadLimits, Scene};
use crate::shading::Shading;

/// The environment variable that sets the limit when `--max-memory` does not.
pub const LIMIT_ENV: &str = "SHADELAB_MAX_MEMORY";

/// Where a render runs.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Backend {
    Gpu,
    /// The f64 CPU reference.
    Cpu,
}

/// Bytes per unit of one kind of work.
struct Cost {
    base: u64,
    object: u64,
    vertex: u64,
    triangle: u64,
    pixel: u64,
    /// On top of `vertex` and `triangle`, for those that carry vertex
    /// colours or texture coordinates (`GeometrySize::attributed_*`).
    attributed_vertex: u64,
    attributed_triangle: u64,
}

const MIB: u64 = 1 << 20;

fn cost(shading: Shading, backend: Backend) -> Cost {
    // Vertex colours and texture coordinates: 40 bytes a vertex in the
    // model (f64) everywhere, and in each renderer what it keeps of them.
    match (backend, shading) {
        // Flat adds a vertex of its own per face and a face record; the
        // colours travel as a colour per face (host and device).
        (Backend::Gpu, Shading::Flat) => Cost {
            base: 128 * MIB,
            object: 280,
            vertex: 240,
            triangle: 260,
            pixel: 52,
            attributed_vertex: 70,
            attributed_triangle: 30,
        },
        // A colour and coordinate stream, 20 bytes a vertex, host and
        // device.
        (Backend::Gpu, Shading::Gouraud | Shading::Phong) => Cost {
            base: 128 * MIB,
            object: 280,
            vertex: 150,
            triangle: 180,
            pixel: 52,
            attributed_vertex: 80,
            attributed_triangle: 0,
        },
        // Triangles copied into f64 records with their normals, a BVH over
        // them (binary, and for a big tree its 4-wide form beside it, about
        // 30 bytes a triangle on the host and as many on the device);
        // vertices matter only as the scene holds them. Per triangle the
        // corners' colours and coordinates in f64 (120 bytes) and as f32
        // records on the host and the device (80 each).
        // Forward adds its fixed-point film: 24 bytes a pixel on the
        // device and as many read back.
        (Backend::Gpu, Shading::Forward) => Cost {
            pixel: 72 + 48,
            ..cost(Shading::Raytrace, backend)
        },
        // With bounces, 24 bytes a pixel of sums on the device (16 of
        // floats without), read back into a film beside the image.
        (Backend::Gpu, Shading::Raytrace) => Cost {
            base: 164 * MIB,
            object: 280,
            vertex: 60,
            triangle: 660,
            pixel: 72,
            attributed_vertex: 40,
            attributed_triangle: 280,
        },
        // A fixed-point film (24 bytes a pixel) per thread, up to 16.
        (Backend::Cpu, Shading::Forward) => Cost {
            pixel: 128 + 16 * 24,
            ..cost(Shading::Raytrace, backend)
        },
        // Per pixel, beside its colour and signature, its samples'
        // fixed-point sums (24 bytes), and with bounces the film they go
        // into (24).
        (Backend::Cpu, Shading::Raytrace) => Cost {
            base: 16 * MIB,
            object: 280,
            vertex: 60,
            triangle: 560,
            pixel: 128,
            attributed_vertex: 40,
            attributed_triangle: 120,
        },
        // A boxed record of the colour attributes per clipped vertex:
        // one per vertex, three per triangle (about 90 bytes each).
        (Backend::Cpu, _) => Cost {
            base: 16 * MIB,
            object: 280,
            vertex: 260,
            triangle: 720,
            pixel: 64,
            attributed_vertex: 130,
            attributed_triangle: 270,
        },
    }
}

/// The peak bytes one render of `size` at `pixels` takes.
pub fn estimate(size: &GeometrySize, pixels: u64, shading: Shading, backend: Backend) -> u64 {
    let c = cost(shading, backend);
    [
        (size.objects, c.object),
        (size.vertices, c.vertex),
        (size.triangles, c.triangle),
        (size.attributed_vertices, c.attributed_vertex),
        (size.attributed_triangles, c.attributed_triangle),
        (pixels, c.pixel),
    ]
    .iter()
    .fold(c.base, |sum, &(n, per)| {
        sum.saturating_add(n.saturating_mul(per))
    })
}

/// The bytes a raster render's samples add where a pixel has several: on
/// the GPU a float colour and a depth per sample (the resolved image is in
/// the per-pixel cost), or with a pass per sample (per-sample shading) a
/// float colour image and its read-back copy per pass; on the CPU
/// reference a colour, depth, ids and pattern cell per sample (its bands
/// hold every row at once).
pub fn multisample_bytes(pixels: u64, shading: Shading, backend: Backend, msaa: Msaa) -> u64 {
    if msaa.samples <= 1 || shading.raster_mode().is_none() {
        return 0;
    }
    let per_sample: u64 = match backend {
        Backend::Gpu if msaa.per_sample => 16 + 16,
        Backend::Gpu => 16 + 4,
        Backend::Cpu => 24 + 8 + 8 + 8 + 16 + 1,
    };
    pixels
        .saturating_mul(u64::from(msaa.samples))
        .saturating_mul(per_sample)
}

/// The bytes a ray trace's photon map adds where the scene asks for
/// caustics: on the GPU the map's buffers and a pass's fixed-point sums
/// per pixel; on the CPU reference a visible point and a state per pixel,
/// and a pass's caustic photons (80 bytes each, as many as it emits at
/// most: a photon kept more than once is rare).
pub fn caustic_bytes(pixels: u64, shading: Shading, backend: Backend, scene: &Scene) -> u64 {
    let caustics = scene.render.caustics;
    if shading != Shading::Raytrace
        || crate::render::caustics::no_caustic(scene).is_some()
        || !caustics.on()
    {
        return 0;
    }
    match backend {
        Backend::Gpu => pixels.saturating_mul(crate::gpu::raytrace::caustics::BYTES_PER_PIXEL + 24),
        Backend::Cpu => pixels
            .saturating_mul(96 + 48)
            .saturating_add(u64::from(caustics.photons_per_pass).saturating_mul(80)),
    }
}

/// The most memory shadelab may plan to use, and how it was set.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct MemoryLimit {
    pub bytes: u64,
    /// "--max-memory 2G", "SHADELAB_MAX_MEMORY=2G", or how the default was
    /// chosen: the message that refuses a scene says it.
    pub source: String,
}

impl MemoryLimit {
    /// `--max-memory` when given, else `SHADELAB_MAX_MEMORY`, else
    /// [`MemoryLimit::machine_default`].
    pub fn resolve(flag: Option<&str>) -> Result<Self, Error> {
        let given = match flag {
            Some(v) => Some((v.to_string(), format!("--max-memory {v}"))),
            None => std::env::var(LIMIT_ENV)
                .ok()
                .filter(|v| !v.trim().is_empty())
                .map(|v| (v.clone(), format!("{LIMIT_ENV}={v}"))),
        };
        match given {
            Some((text, source)) => {
                let bytes = parse_size(&text).ok_or_else(|| {
                    Error::Usage(format!(
                        "{source} is not a memory size; expected a number of bytes with an optional unit, such as 512M, 4G or 1.5GiB"
                    ))
                })?;
                Ok(MemoryLimit { bytes, source })
            }
            None => Ok(Self::machine_default()),
        }
    }

    /// Three quarters of the memory this process may use: the machine's
    /// (`MemTotal`), or its control group's limit where that is lower, so a
    /// container's limit is respected, under cgroup v2 (`memory.max`) or
    /// v1 (`memory.limit_in_bytes`). 8 GiB where neither can be read.
    pub fn machine_default() -> Self {
        // Read once a process: a kept device resolves the limit at every
        // render (the Python package), and the files do not change.
        static MACHINE: std::sync::OnceLock<MemoryLimit> = std::sync::OnceLock::new();
        MACHINE.get_or_init(Self::read_machine).clone()
    }

    /// [`MemoryLimit::machine_default`], read from the system's files.
    fn read_machine() -> Self {
        let meminfo = std::fs::read_to_string("/proc/meminfo").ok();
        let own = std::fs::read_to_string("/proc/self/cgroup").unwrap_or_default();
        let group = control_group_files(&own)
            .iter()
            .filter_map(|f| std::fs::read_to_string(f).ok())
            .filter_map(|text| text.trim().parse::<u64>().ok())
            .min()
            .map(|bytes| bytes.to_string());
        Self::default_from(meminfo.as_deref(), group.as_deref())
    }

    /// [`MemoryLimit::machine_default`] from the texts of `/proc/meminfo`
    /// and the control group's `memory.max` (`"max"` when unlimited).
    fn default_from(meminfo: Option<&str>, group_max: Option<&str>) -> Self {
        let total = meminfo.and_then(mem_total);
        let group = group_max.and_then(|text| text.trim().parse::<u64>().ok());
        match (total, group) {
            (None, None) => MemoryLimit {
                bytes: 8 << 30,
                source: "the default when the machine's memory cannot be read".into(),
            },
            (total, group) => {
                let usable = total.unwrap_or(u64::MAX).min(group.unwrap_or(u64::MAX));
                MemoryLimit {
                    bytes: usable / 4 * 3,
                    source: format!(
                        "the default, 3/4 of this machine's {}",
                        format_bytes(usable)
                    ),
                }
            }
        }
    }

    /// The limit as the scene loader applies it to each glTF file.
    pub fn load_limits(&self) -> LoadLimits {
        LoadLimits {
            max_bytes: self.bytes,
            source: self.source.clone(),
        }
    }

    /// Refuses `scene` when rendering it would exceed the limit: the
    /// largest of the GPU renders plus the largest of the CPU ones (a
    /// command such as `check` holds one of each at a time). Returns the
    /// estimate.
    /// `name` names the scene in the message.
    pub fn check(
        &self,
        name: &str,
        scene: &Scene,
        gpu: &[Shading],
        cpu: &[Shading],
    ) -> Result<u64, Error> {
        let pixels = u64::from(scene.image.width) * u64::from(scene.image.height);
        let size_for = |s: Shading| GeometrySize::of_scene(scene, s.raster_mode().is_some());
        let largest = |modes: &[Shading], backend| {
            modes
                .iter()
                .map(|&s| {
                    let samples = multisample_bytes(pixels, s, backend, scene.render.msaa)
                        .saturating_add(caustic_bytes(pixels, s, backend, scene));
                    (
                        estimate(&size_for(s), pixels, s, backend).saturating_add(samples),
                        s,
                    )
                })
                .max_by_key(|e| e.0)
        };
        let size = size_for(
            match (largest(gpu, Backend::Gpu), largest(cpu, Backend::Cpu)) {
                (Some((_, s)), _) | (None, Some((_, s))) => s,
                (None, None) => Shading::Phong,
            },
        );
        let (g, c) = (largest(gpu, Backend::Gpu), largest(cpu, Backend::Cpu));
        // Image textures: the scene's texels once, and with a GPU render
        // its texture table on the host and the buffer on the device
        // (`TEXEL_COPIES` in all); the CPU reference reads the scene's.
        let texels = scene_texture_bytes(scene);
        let texture_bytes = texels.saturating_mul(if g.is_some() { TEXEL_COPIES } else { 1 });
        let total = g
            .map_or(0, |e| e.0)
            .saturating_add(c.map_or(0, |e| e.0))
            .saturating_add(texture_bytes);
        if total <= self.bytes {
            return Ok(total);
        }
        let work = match (g, c) {
            (Some((_, s)), None) => format!("rendering it in {s} mode"),
            (None, Some((_, s))) => format!("rendering it in {s} mode with the CPU reference"),
            (Some((_, gs)), Some((_, cs))) => {
                format!("rendering it in {gs} mode on the GPU and {cs} mode on the CPU")
            }
            (None, None) => "rendering it".into(),
        };
        let raster = gpu.iter().chain(cpu).any(|s| s.raster_mode().is_some());
        let work = match scene.render.msaa.samples {
            n if n > 1 && raster => format!("{work} with {n} samples per pixel"),
            _ => work,
        };
        let textures = if texels > 0 {
            format!(", {} of textures", format_bytes(texture_bytes))
        } else {
            String::new()
        };
        Err(Error::OverMemory(format!(
            "{name}: {work} at {}x{} would take about {} ({} objects, {} triangles, {} vertices{textures}), over the memory limit of {} ({}); raise the limit with --max-memory or {LIMIT_ENV}, or lower the resolution or the geometry",
            scene.image.width,
            scene.image.height,
            format_bytes(total),
            size.objects,
            size.triangles,
            size.vertices,
            format_bytes(self.bytes),
            self.source
        )))
    }
}

/// The most resident memory this process has held so far (`VmHWM`), where
/// the system tells it (Linux); `None` elsewhere.
pub fn peak_resident_bytes() -> Option<u64> {
    let status = std::fs::read_to_string("/proc/self/status").ok()?;
    let line = status.lines().find(|l| l.starts_with("VmHWM:"))?;
    let kib: u64 = line.split_whitespace().nth(1)?.parse().ok()?;
    kib.checked_mul(1024)
}

fn mem_total(meminfo: &str) -> Option<u64> {
    let line = meminfo.lines().find(|l| l.starts_with("MemTotal:"))?;
    let kib: u64 = line.split_whitespace().nth(1)?.parse().ok()?;
    kib.checked_mul(1024)
}

/// "512M", "4G", "1.5GiB", "2 gb", "1000000": bytes, with binary units
/// (K, M, G, T, with or without "B" or "iB"). `None` for anything else,
/// zero and non-finite numbers included.
pub fn parse_size(text: &str) -> Option<u64> {
    let text = text.trim();
    let split = text
        .find(|c: char| !(c.is_ascii_digit() || c == '.'))
        .unwrap_or(text.len());
    let (number, unit) = text.split_at(split);
    let value: f64 = number.parse().ok()?;
    let unit = unit.trim().to_ascii_lowercase();
    let unit = unit
        .strip_suffix("ib")
        .or_else(|| unit.strip_suffix('b'))
        .unwrap_or(&unit);
    let scale: u64 = match unit {
        "" => 1,
        "k" => 1 << 10,
        "m" => 1 << 20,
        "g" => 1 << 30,
        "t" => 1 << 40,
        _ => return None,
    };
    let bytes = value * scale as f64;
    (bytes.is_finite() && bytes >= 1.0 && bytes < u64::MAX as f64).then_some(bytes as u64)
}

/// The files that may hold this process's memory limit, from the text of
/// `/proc/self/cgroup`: cgroup v2's `memory.max` (line `0::PATH`) and
/// v1's `memory.limit_in_bytes` (the line whose controllers hold
/// `memory`), each at the mount's root (what a container sees) and under
/// the group's own path (what a host's process sees). Missing ones are
/// skipped by the reader; v1's "no limit" is a huge number, which the
/// machine's memory then undercuts.
fn control_group_files(proc_self_cgroup: &str) -> Vec<std::path::PathBuf> {
    let root = std::path::Path::new("/sys/fs/cgroup");
    let mut files = vec![
        root.join("memory.max"),
        root.join("memory/memory.limit_in_bytes"),
    ];
    for line in proc_self_cgroup.lines() {
        let mut parts = line.splitn(3, ':');
        let (Some(_), Some(controllers), Some(path)) = (parts.next(), parts.next(), parts.next())
        else {
            continue;
        };
        let path = path.trim_start_matches('/');
        if path.is_empty() || path.split('/').any(|c| c == "..") {
            continue;
        }
        if controllers.is_empty() {
            files.push(root.join(path).join("memory.max"));
        } else if controllers.split(',').any(|c| c == "memory") {
            files.push(root.join("memory").join(path).join("memory.limit_in_bytes"));
        }
    }
    files
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::scene::default_scene;

    /// Several samples add per sample a float colour and a depth on the
    /// GPU, or with a pass per sample a float colour image and its
    /// read-back copy; one sample adds nothing, nor does the ray tracer.
    #[test]
    fn samples_cost_what_the_drawing_holds_per_sample() {
        let msaa = |text: &str| text.parse::<Msaa>().unwrap();
        let gpu = |m: &str, s| multisample_bytes(1000, s, Backend::Gpu, msaa(m));
        assert_eq!(gpu("1", Shading::Phong), 0);
        assert_eq!(gpu("4", Shading::Phong), 1000 * 4 * 20);
        assert_eq!(gpu("8,per-sample", Shading::Gouraud), 1000 * 8 * 32);
        assert_eq!(gpu("4", Shading::Raytrace), 0);
        let cpu = multisample_bytes(1000, Shading::Flat, Backend::Cpu, msaa("16"));
        assert_eq!(cpu, 1000 * 16 * 65);
    }

    #[test]
    fn sizes_parse_with_binary_units() {
        assert_eq!(parse_size("512M"), Some(512 << 20));
        assert_eq!(parse_size("4G"), Some(4 << 30));
        assert_eq!(parse_size("1.5GiB"), Some(3 << 29));
        assert_eq!(parse_size(" 2 gb "), Some(2 << 30));
        assert_eq!(parse_size("1000000"), Some(1_000_000));
        assert_eq!(parse_size("64k"), Some(64 << 10));
        for bad in ["", "G", "0", "-1G", "1X", "1.2.3M", "nanG", "1e400"] {
            assert_eq!(parse_size(bad), None, "{bad}");
        }
    }

    #[test]
    fn the_default_is_three_quarters_of_the_machine_or_its_control_group() {
        let meminfo = "MemTotal:       25165824 kB\n"; // 24 GiB
        let default = |m, g| MemoryLimit::default_from(m, g).bytes;
        assert_eq!(default(Some(meminfo), None), 18 << 30);
        assert_eq!(default(Some(meminfo), Some("max\n")), 18 << 30);
        assert_eq!(default(Some(meminfo), Some("4294967296\n")), 3 << 30);
        assert_eq!(default(Some(meminfo), Some("68719476736")), 18 << 30);
        assert_eq!(default(None, Some("4294967296")), 3 << 30);
        assert_eq!(default(None, None), 8 << 30);
        assert_eq!(default(Some("garbage"), Some("max")), 8 << 30);
        let named = MemoryLimit::default_from(Some(meminfo), None).source;
        assert!(named.contains("24 GiB"), "{named}");
    }

    #[test]
    fn the_control_group_limit_is_looked_for_under_cgroup_v1_and_v2() {
        let v1 = "12:memory:/docker/abc\n11:cpu,cpuacct:/docker/abc\n";
        let files = control_group_files(v1);
        assert!(files.contains(&"/sys/fs/cgroup/memory/memory.limit_in_bytes".into()));
        assert!(files.contains(&"/sys/fs/cgroup/memory/docker/abc/memory.limit_in_bytes".into()));
        assert!(!files.iter().any(|f| f.to_string_lossy().contains("cpu")));
        let v2 = "0::/user.slice/session-1.scope\n";
        let files = control_group_files(v2);
        assert!(files.contains(&"/sys/fs/cgroup/memory.max".into()));
        assert!(files.contains(&"/sys/fs/cgroup/user.slice/session-1.scope/memory.max".into()));
        // A path that climbs out is not followed.
        assert_eq!(control_group_files("0::/../etc\n").len(), 2);
    }

    #[test]
    fn mem_total_reads_proc_meminfo() {
        let text = "MemTotal:       24588020 kB\nMemFree:  1 kB\n";
        assert_eq!(mem_total(text), Some(24588020 * 1024));
        assert_eq!(mem_total("MemFree: 1 kB\n"), None);
    }

    #[test]
    fn the_estimate_grows_with_every_input() {
        let size = GeometrySize {
            objects: 10,
            vertices: 1000,
            triangles: 2000,
            attributed_vertices: 0,
            attributed_triangles: 0,
        };
        for shading in Shading::BY_DEFAULT {
            for backend in [Backend::Gpu, Backend::Cpu] {
                let e = |s: &GeometrySize, px| estimate(s, px, shading, backend);
                let base = e(&size, 100);
                assert!(e(&size, 101) > base);
                for bump in [(1, 0, 0), (0, 1, 0), (0, 0, 1)] {
                    let mut more = size;
                    more.add(bump.0, bump.1, bump.2);
                    assert!(e(&more, 100) > base, "{shading} {backend:?} {bump:?}");
                }
                // Vertex colours or texture coordinates cost more.
                let mut attributed = size;
                attributed.add_attributed(1000, 2000);
                assert!(
                    e(&attributed, 100) > base,
                    "{shading} {backend:?} attributes"
                );
            }
        }
    }

    #[test]
    fn check_refuses_just_over_the_estimate_and_names_the_work() {
        let scene = default_scene();
        // Ray tracing and Phong on the GPU, flat on the CPU, as `check` would.
        let check = |limit: &MemoryLimit| {
            limit.check(
                "default",
                &scene,
                &[Shading::Phong, Shading::Raytrace],
                &[Shading::Flat],
            )
        };
        let unlimited = MemoryLimit {
            bytes: u64::MAX,
            source: "test".into(),
        };
        let need = check(&unlimited).unwrap();
        let traced = GeometrySize::of_scene(&scene, false);
        let tessellated = GeometrySize::of_scene(&scene, true);
        assert!(traced.triangles < tessellated.triangles);
        let px = 640 * 480;
        assert_eq!(
            need,
            estimate(&traced, px, Shading::Raytrace, Backend::Gpu)
                + estimate(&tessellated, px, Shading::Flat, Backend::Cpu)
        );
        let at = MemoryLimit {
            bytes: need,
            source: "--max-memory X".into(),
        };
        assert!(check(&at).is_ok());
        let under = MemoryLimit {
            bytes: need - 1,
            ..at
        };
        let e = check(&under).unwrap_err();
        assert_eq!(e.exit_code(), 2);
        let e = e.to_string();
        assert!(
            e.starts_with("default: rendering it")
                && e.contains("raytrace mode on the GPU and flat mode on the CPU")
                && e.contains("640x480")
                && e.contains("--max-memory X"),
            "{e}"
        );
    }

    /// An image counts once for the scene and `TEXEL_COPIES` times with a
    /// GPU render (its texture table, host and device), each shared
    /// texture once.
    #[test]
    fn image_textures_count_per_copy_and_once_per_texture() {
        use crate::scene::{ImageTexture, Pattern, Sampler, Texture, UvTransform};
        // Against a checker, whose surfaces carry the same coordinates.
        let mut plain = default_scene();
        let checker = Pattern::Checker {
            scale: 1.0,
            colors: [glam::DVec3::ONE; 2],
        };
        plain.materials[0].pattern = Some(checker.clone());
        plain.materials[1].pattern = Some(checker);
        let mut textured = plain.clone();
        // 64 x 64 with its chain: 5461 texels of 12 bytes.
        let image = std::sync::Arc::new(ImageTexture {
            name: "t".into(),
            texture: Texture::new(64, 64, vec![[0.5; 3]; 64 * 64]),
            sampler: Sampler::GLTF_DEFAULT,
            transform: UvTransform::IDENTITY,
        });
        textured.materials[0].pattern = Some(Pattern::Image(image.clone()));
        textured.materials[1].pattern = Some(Pattern::Image(image));
        let unlimited = MemoryLimit {
            bytes: u64::MAX,
            source: "test".into(),
        };
        let cost = |scene: &Scene, gpu: &[Shading], cpu: &[Shading]| {
            unlimited.check("s", scene, gpu, cpu).unwrap()
        };
        let one_copy = 5461 * 12;
        let gpu = [Shading::Phong];
        let cpu = [Shading::Flat];
        assert_eq!(
            cost(&textured, &gpu, &[]) - cost(&plain, &gpu, &[]),
            TEXEL_COPIES * one_copy
        );
        assert_eq!(
            cost(&textured, &[], &cpu) - cost(&plain, &[], &cpu),
            one_copy
        );
        let need = cost(&textured, &gpu, &cpu);
        let e = MemoryLimit {
            bytes: need - 1,
            source: "test".into(),
        }
        .check("s", &textured, &gpu, &cpu)
        .unwrap_err()
        .to_string();
        assert!(e.contains("of textures"), "{e}");
    }
}
