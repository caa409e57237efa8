//! `compare::present`: the files written from a synthetic `Report`, their
//! contents, and the HTML page as headless Chromium renders it.
//!
//! The fixture's images are made to be recognisable in a screenshot:
//! - each variant image is 480 x 320 of one-pixel vertical stripes in two
//!   colours of its own (A_i, B_i). Shown at its size, A_i pixels appear;
//!   the contact sheet halves it, which blends the stripes, so A_i appears
//!   on the page only if the variant's own `<img>` is drawn;
//! - each heat map is 96 x 64 of one colour of its own (H_i), shown nowhere
//!   else.

use std::fs::File;
use std::path::{Path, PathBuf};
use std::process::{Command, Stdio};
use std::time::{Duration, Instant};

use image::{Rgb, RgbImage};
use shadelab::compare::present::{write_presentation, PresentError};
use shadelab::compare::report::{
    pareto_front, Errors, Metric, ReferenceChoice, Report, Timing, VariantResult,
};

const IMAGE_W: u32 = 480;
const IMAGE_H: u32 = 320;
const HEAT_W: u32 = 96;
const HEAT_H: u32 = 64;

/// (name, gpu_ms, model rmse). Phong at 32 segments is dominated by
/// Gouraud at 32: slower and less accurate. The rest form the front.
const VARIANTS: [(&str, f64, f64); 5] = [
    ("flat:segments=8", 2.0, 0.08),
    ("gouraud:segments=32", 3.0, 0.03),
    ("phong:segments=32", 5.0, 0.035),
    ("phong:segments=128", 9.0, 0.01),
    ("raytrace:depth=3,cutoff=0.01", 150.0, 0.0005),
];
const DOMINATED: &str = "phong:segments=32";

fn stripe_a(i: usize) -> [u8; 3] {
    [200, 20 + 40 * i as u8, 60]
}
fn stripe_b(i: usize) -> [u8; 3] {
    [20, 200, 220 - 40 * i as u8]
}
fn heat(i: usize) -> [u8; 3] {
    [60 + 30 * i as u8, 10, 230]
}

/// Writes the fixture's images into `dir` and returns its report. The
/// scene and device names hold markup, to check escaping.
fn fixture(dir: &Path) -> Report {
    let mut variants = Vec::new();
    for (i, &(name, gpu_ms, rmse)) in VARIANTS.iter().enumerate() {
        let stem = shadelab::compare::report::file_stem(name);
        let image = RgbImage::from_fn(IMAGE_W, IMAGE_H, |x, _| {
            Rgb(if x % 2 == 0 { stripe_a(i) } else { stripe_b(i) })
        });
        image.save(dir.join(format!("{stem}.png"))).unwrap();
        RgbImage::from_pixel(HEAT_W, HEAT_H, Rgb(heat(i)))
            .save(dir.join(format!("{stem}-flip.png")))
            .unwrap();
        let k = i as f64;
        variants.push(VariantResult {
            name: name.to_string(),
            variant: name.parse().unwrap(),
            image: format!("{stem}.png"),
            heatmap: format!("{stem}-flip.png"),
            implementation_error: Errors {
                rmse: 1e-5 * (k + 1.0),
                max_abs: 1e-3 * (k + 1.0),
                // Identical to the CPU reference for the first variant.
                psnr: if i == 0 { None } else { Some(90.0 - k) },
                flip_mean: 1e-6 * (k + 1.0),
            },
            model_error: Errors {
                rmse,
                max_abs: rmse * 7.5,
                psnr: Some(-20.0 * rmse.log10()),
                flip_mean: rmse * 1.3 + 0.001,
            },
            local_error: Some(Errors {
                rmse: rmse * 0.5,
                max_abs: rmse * 4.0,
                psnr: Some(-20.0 * (rmse * 0.5).log10()),
                flip_mean: rmse * 0.6,
            }),
            timing: Timing {
                gpu_ms,
                gpu_spread_ms: gpu_ms * 0.05,
                frame_ms: gpu_ms + 30.0 + k,
                frame_spread_ms: 1.5 + k,
                pipeline_ms: 2.5 + 0.25 * k,
                image_ms: 40.0 + 2.0 * k,
            },
            traversal: None,
            non_finite_pixels: 0,
            pareto: false,
        });
    }
    let front = pareto_front(
        &variants
            .iter()
            .map(|v| (v.timing.gpu_ms, v.model_error.rmse))
            .collect::<Vec<_>>(),
    );
    for (v, on) in variants.iter_mut().zip(front) {
        v.pareto = on;
    }
    RgbImage::from_pixel(IMAGE_W, IMAGE_H, Rgb([128, 128, 128]))
        .save(dir.join("reference.png"))
        .unwrap();
    Report {
        scene: "spheres <b>&amp;</b>".into(),
        width: IMAGE_W,
        height: IMAGE_H,
        device: "llvmpipe \"test\" <device>".into(),
        driver: "Mesa <test> 25".into(),
        runs: 5,
        reference: "CPU ray tracer, depth 8, 16 samples".into(),
        reference_image: "reference.png".into(),
        local_reference: "formula per pixel, no shadows".into(),
        local_reference_image: String::new(),
        plot_reference: ReferenceChoice::Global,
        plot_metric: Metric::Rmse,
        shard: None,
        variants,
        budget: None,
        not_run: Vec::new(),
        run: None,
    }
}

fn present() -> (tempfile::TempDir, Report) {
    let dir = tempfile::tempdir().unwrap();
    let report = fixture(dir.path());
    write_presentation(&report, dir.path()).expect("write_presentation");
    (dir, report)
}

fn count_near(image: &RgbImage, colour: [u8; 3], tolerance: u8) -> usize {
    image
        .pixels()
        .filter(|p| (0..3).all(|c| p.0[c].abs_diff(colour[c]) <= tolerance))
        .count()
}

#[test]
fn every_file_is_written_and_returned() {
    let dir = tempfile::tempdir().unwrap();
    let report = fixture(dir.path());
    let presented = write_presentation(&report, dir.path()).unwrap();
    let names: Vec<&str> = presented
        .all()
        .iter()
        .map(|p| p.file_name().unwrap().to_str().unwrap())
        .collect();
    assert_eq!(
        names,
        [
            "report.csv",
            "speed-vs-error.png",
            "speed-vs-error.svg",
            "contact-sheet.png",
            "report.html"
        ]
    );
    for p in presented.all() {
        assert_eq!(p.parent().unwrap(), dir.path());
        let len = std::fs::metadata(p).unwrap().len();
        assert!(len > 100, "{} has only {len} bytes", p.display());
    }
    // No temporary file is left behind.
    let mut left: Vec<String> = std::fs::read_dir(dir.path())
        .unwrap()
        .map(|e| e.unwrap().file_name().into_string().unwrap())
        .filter(|n| n.ends_with(".tmp"))
        .collect();
    left.sort();
    assert!(left.is_empty(), "{left:?}");
}

#[test]
fn the_csv_holds_every_figure_of_every_variant() {
    let (dir, report) = present();
    let mut reader = csv::Reader::from_path(dir.path().join("report.csv")).unwrap();
    let header: Vec<String> = reader.headers().unwrap().iter().map(String::from).collect();
    // Spelled out, not taken from `table::COLUMNS`: the published header is
    // a contract, and comparing it with the constant would test nothing.
    assert_eq!(
        header,
        [
            "name",
            "impl_rmse",
            "impl_max_abs",
            "impl_psnr",
            "impl_flip_mean",
            "model_rmse",
            "model_max_abs",
            "model_psnr",
            "model_flip_mean",
            "local_rmse",
            "local_max_abs",
            "local_psnr",
            "local_flip_mean",
            "gpu_ms",
            "gpu_spread_ms",
            "frame_ms",
            "frame_spread_ms",
            "pipeline_ms",
            "image_ms",
            "pareto"
        ]
    );
    let rows: Vec<csv::StringRecord> = reader.records().map(Result::unwrap).collect();
    assert_eq!(rows.len(), report.variants.len());
    let num = |s: &str| -> f64 { s.parse().unwrap_or_else(|_| panic!("not a number: {s}")) };
    for (row, v) in rows.iter().zip(&report.variants) {
        assert_eq!(&row[0], v.name);
        let psnr = |p: Option<f64>| p.unwrap_or(f64::INFINITY);
        let (i, m, t) = (&v.implementation_error, &v.model_error, &v.timing);
        let l = v.local_error.expect("the fixture has local errors");
        let want = [
            i.rmse,
            i.max_abs,
            psnr(i.psnr),
            i.flip_mean,
            m.rmse,
            m.max_abs,
            psnr(m.psnr),
            m.flip_mean,
            l.rmse,
            l.max_abs,
            psnr(l.psnr),
            l.flip_mean,
            t.gpu_ms,
            t.gpu_spread_ms,
            t.frame_ms,
            t.frame_spread_ms,
            t.pipeline_ms,
            t.image_ms,
        ];
        for (k, want) in want.iter().enumerate() {
            // Exact: the CSV writes shortest round-trip decimals.
            assert_eq!(
                num(&row[k + 1]),
                *want,
                "{} column {}",
                v.name,
                header[k + 1]
            );
        }
        assert_eq!(&row[19], if v.pareto { "true" } else { "false" });
    }
    assert_eq!(&rows[0][3], "inf", "the PSNR of identical images");
}

#[test]
fn the_plot_names_every_variant_and_decodes_at_its_size() {
    let (dir, report) = present();
    let front: Vec<&str> = report
        .variants
        .iter()
        .filter(|v| v.pareto)
        .map(|v| v.name.as_str())
        .collect();
    assert_eq!(front.len(), 4, "the fixture's front");

    let svg = std::fs::read_to_string(dir.path().join("speed-vs-error.svg")).unwrap();
    assert!(svg.contains("<svg"), "not an SVG");
    // Every point is numbered and listed beside the plot, on the front or
    // off it.
    for v in &report.variants {
        assert!(svg.contains(&v.name), "the SVG does not name {}", v.name);
    }
    assert!(svg.contains(DOMINATED));
    // Escaped, as XML needs.
    assert!(svg.contains("spheres &lt;b&gt;&amp;amp;&lt;/b&gt;"));

    let png = image::open(dir.path().join("speed-vs-error.png"))
        .unwrap()
        .to_rgb8();
    assert_eq!(png.dimensions(), (1280, 640));
    // A point per variant in its mode's colour, and the orange front.
    for (mode, colour) in [
        ("flat", [31, 119, 180]),
        ("gouraud", [44, 160, 44]),
        ("phong", [214, 39, 40]),
        ("raytrace", [148, 103, 189]),
        ("pareto", [255, 127, 14]),
    ] {
        assert!(
            count_near(&png, colour, 0) > 20,
            "no {mode} colour in the plot"
        );
    }
}

#[test]
fn the_contact_sheet_shows_every_variant_and_marks_the_front() {
    let (dir, report) = present();
    let sheet = image::open(dir.path().join("contact-sheet.png"))
        .unwrap()
        .to_rgb8();
    let (w, h) = sheet.dimensions();
    // Five thumbnails 240 wide in one row, each with its text below.
    assert!((5 * 240..5 * 300).contains(&w), "width {w}");
    assert!((160 + 40..160 + 300).contains(&h), "height {h}");
    // Each thumbnail: the image halved, its stripes blended.
    for i in 0..VARIANTS.len() {
        let (a, b) = (stripe_a(i), stripe_b(i));
        let mean = [0, 1, 2].map(|c| ((a[c] as u16 + b[c] as u16) / 2) as u8);
        let n = count_near(&sheet, mean, 3);
        assert!(n >= 240 * 150, "thumbnail {i}: {n} pixels of its colour");
    }
    // A 4-pixel orange border around each of the 4 front thumbnails
    // (248 x 168 less 240 x 160), and the legend's 23 x 11 swatch; none
    // around the dominated one.
    let orange = count_near(&sheet, [255, 127, 14], 0);
    let border = 248 * 168 - 240 * 160;
    let front = report.variants.iter().filter(|v| v.pareto).count();
    assert_eq!(front, 4);
    assert!(
        (front * border..front * border + 400).contains(&orange),
        "{orange} orange pixels for {front} front borders of {border}"
    );
    // Text is drawn: dark pixels under the images.
    let text = sheet
        .enumerate_pixels()
        .filter(|(_, y, p)| *y > 52 + 170 && p.0.iter().all(|&c| c < 100))
        .count();
    assert!(text > 500, "only {text} dark pixels of text");
}

#[test]
fn the_html_is_self_contained_and_holds_every_image() {
    let (dir, report) = present();
    let html = std::fs::read_to_string(dir.path().join("report.html")).unwrap();
    let uri = |file: &str| {
        use base64::Engine;
        let bytes = std::fs::read(dir.path().join(file)).unwrap();
        format!(
            "src=\"data:image/png;base64,{}\"",
            base64::engine::general_purpose::STANDARD.encode(bytes)
        )
    };
    for v in &report.variants {
        assert_eq!(html.matches(&uri(&v.image)).count(), 1, "{} image", v.name);
        assert_eq!(
            html.matches(&uri(&v.heatmap)).count(),
            1,
            "{} heat map",
            v.name
        );
        assert!(html.contains(&v.name));
    }
    assert_eq!(html.matches(&uri("contact-sheet.png")).count(), 1);
    assert_eq!(html.matches(&uri("reference.png")).count(), 1);
    // Every image and heat map, the contact sheet and the reference.
    assert_eq!(html.matches("<img").count(), 2 * report.variants.len() + 2);
    // The plot inline.
    assert_eq!(html.matches("<svg").count(), 1);
    for bad in ["http://", "https://", "src=\"/", "<script", "<link", "url("] {
        assert!(!html.contains(bad), "the page holds {bad}");
    }
    // Every src is a data URI.
    assert_eq!(
        html.matches(" src=\"").count(),
        html.matches(" src=\"data:image/png;base64,").count()
    );
    // Text is escaped.
    assert!(html.contains("spheres &lt;b&gt;&amp;amp;&lt;/b&gt;"));
    assert!(html.contains("llvmpipe &quot;test&quot; &lt;device&gt; (Mesa &lt;test&gt; 25)"));
    assert!(!html.contains("<b>") && !html.contains("<device>"));
    // Pareto rows are marked, and only they.
    assert_eq!(html.matches("<tr class=\"pareto\">").count(), 4);
    assert!(html.contains("Implementation error") && html.contains("Model error"));
}

#[test]
fn missing_or_corrupt_images_are_errors() {
    let dir = tempfile::tempdir().unwrap();
    let report = fixture(dir.path());
    std::fs::write(dir.path().join(&report.variants[2].heatmap), b"not a png").unwrap();
    let e = write_presentation(&report, dir.path()).unwrap_err();
    assert!(matches!(e, PresentError::ReadImage { .. }), "{e}");
    assert!(e.to_string().contains(&report.variants[2].heatmap), "{e}");
    assert!(e.is_bad_input());
    std::fs::remove_file(dir.path().join(&report.variants[2].heatmap)).unwrap();
    let e = write_presentation(&report, dir.path()).unwrap_err();
    assert!(matches!(e, PresentError::ReadImage { .. }), "{e}");
    assert!(!dir.path().join("report.html").exists());

    let empty = Report {
        variants: Vec::new(),
        ..report
    };
    assert!(matches!(
        write_presentation(&empty, dir.path()),
        Err(PresentError::NoVariants)
    ));
}

// --- headless Chromium ------------------------------------------------

const WINDOW: (u32, u32) = (1400, 6000);

/// Chromium's path, or a failure that says how to install it.
fn chromium() -> PathBuf {
    let out = Command::new("which").arg("chromium").output();
    match out {
        Ok(o) if o.status.success() => {
            PathBuf::from(String::from_utf8_lossy(&o.stdout).trim().to_string())
        }
        _ => panic!(
            "chromium is not installed (`which chromium` fails); run `bash ci/install-deps.sh --with-chromium`, which installs Debian's `chromium` package"
        ),
    }
}

struct Run {
    stdout: String,
    stderr: String,
}

/// Runs headless Chromium on `page` with `extra` flags, its own profile
/// folder and console logging on stderr; fails unless it exits 0 within
/// two minutes.
fn run_chromium(work: &Path, page: &Path, extra: &[String]) -> Run {
    let out = work.join("chromium.out");
    let err = work.join("chromium.err");
    let mut child = Command::new(chromium())
        .args([
            "--headless",
            "--disable-gpu",
            "--no-sandbox",
            "--enable-logging=stderr",
            "--v=0",
        ])
        .arg(format!(
            "--user-data-dir={}",
            work.join("profile").display()
        ))
        .args(extra)
        .arg(format!("file://{}", page.display()))
        .stdin(Stdio::null())
        .stdout(File::create(&out).unwrap())
        .stderr(File::create(&err).unwrap())
        .spawn()
        .expect("start chromium");
    let deadline = Instant::now() + Duration::from_secs(120);
    let status = loop {
        if let Some(s) = child.try_wait().unwrap() {
            break s;
        }
        if Instant::now() > deadline {
            let _ = child.kill();
            let _ = child.wait();
            panic!("chromium ran for over 2 minutes");
        }
        std::thread::sleep(Duration::from_millis(50));
    };
    let run = Run {
        stdout: std::fs::read_to_string(&out).unwrap(),
        stderr: std::fs::read_to_string(&err).unwrap(),
    };
    assert!(
        status.success(),
        "chromium exited with {status}; stderr:\n{}",
        run.stderr
    );
    run
}

/// The page's console messages and uncaught exceptions. With
/// `--enable-logging=stderr --v=0` Chromium logs every console message as
/// `[...:INFO:CONSOLE:line] "text", source: URL (line)` (this version logs
/// `console.error` at INFO too, older ones as `ERROR:CONSOLE`), and an
/// uncaught exception as such a line whose text starts `Uncaught`. So any
/// line with `:CONSOLE` or `Uncaught` counts. The rest of stderr (D-Bus,
/// VA-API warnings of a container) is about the browser, not the page.
fn console_errors(stderr: &str) -> Vec<&str> {
    stderr
        .lines()
        .filter(|l| l.contains(":CONSOLE") || l.contains("Uncaught"))
        .collect()
}

#[test]
fn chromium_console_check_sees_errors_on_a_bad_page() {
    // The check must be able to fail: a page that logs an error and throws.
    let work = tempfile::tempdir().unwrap();
    let page = work.path().join("bad.html");
    std::fs::write(
        &page,
        "<!DOCTYPE html><html><body><p>x</p><script>console.error('canary-log'); throw new Error('canary-throw');</script></body></html>",
    )
    .unwrap();
    let run = run_chromium(work.path(), &page, &["--dump-dom".into()]);
    let errors = console_errors(&run.stderr);
    assert!(
        errors.iter().any(|l| l.contains("canary-log")),
        "console.error not seen in:\n{}",
        run.stderr
    );
    assert!(
        errors
            .iter()
            .any(|l| l.contains("Uncaught") && l.contains("canary-throw")),
        "the uncaught exception not seen in:\n{}",
        run.stderr
    );
}

#[test]
fn chromium_renders_the_page_dom_without_errors() {
    let (dir, report) = present();
    let work = tempfile::tempdir().unwrap();
    let run = run_chromium(
        work.path(),
        &dir.path().join("report.html"),
        &["--dump-dom".into()],
    );
    let dom = &run.stdout;
    assert!(dom.contains("</html>"), "no DOM dumped:\n{}", run.stderr);
    for v in &report.variants {
        assert!(dom.contains(&v.name), "the DOM lacks {}", v.name);
    }
    assert_eq!(dom.matches("<img").count(), 2 * report.variants.len() + 2);
    assert!(dom.contains("<svg"), "the plot is not in the DOM");
    let errors = console_errors(&run.stderr);
    assert!(errors.is_empty(), "console errors: {errors:#?}");
}

#[test]
fn chromium_screenshot_shows_every_image() {
    let (dir, report) = present();
    let work = tempfile::tempdir().unwrap();
    let shot = work.path().join("shot.png");
    let run = run_chromium(
        work.path(),
        &dir.path().join("report.html"),
        &[
            format!("--screenshot={}", shot.display()),
            format!("--window-size={},{}", WINDOW.0, WINDOW.1),
            "--force-device-scale-factor=1".into(),
            "--hide-scrollbars".into(),
        ],
    );
    let errors = console_errors(&run.stderr);
    assert!(errors.is_empty(), "console errors: {errors:#?}");
    let image = image::open(&shot)
        .unwrap_or_else(|e| panic!("the screenshot does not decode: {e}"))
        .to_rgb8();
    assert_eq!(image.dimensions(), WINDOW);
    let background = *image.get_pixel(0, 0);
    assert!(
        image.pixels().any(|p| *p != background),
        "the screenshot is blank"
    );
    for (i, v) in report.variants.iter().enumerate() {
        // Half of the image's pixels are A_i, the heat map is all H_i.
        let a = count_near(&image, stripe_a(i), 2);
        assert!(
            a as u32 >= IMAGE_W * IMAGE_H / 2 * 9 / 10,
            "{}: its image shows {a} pixels of its colour",
            v.name
        );
        let hm = count_near(&image, heat(i), 2);
        assert!(
            hm as u32 >= HEAT_W * HEAT_H * 9 / 10,
            "{}: its heat map shows {hm} pixels of its colour",
            v.name
        );
    }
}
