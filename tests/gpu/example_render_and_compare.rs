//! `examples/render_and_compare.rs` run as a reader would run it: the example
//! is documentation, and this fails when it stops compiling, errors, or
//! prints figures that no longer parse or no longer show agreement.

#[allow(dead_code)] // The example's `main`: the tests call its `run`.
#[path = "../../examples/render_and_compare.rs"]
mod example;

use shadelab::check::CheckThresholds;
use shadelab::shading::Shading;

/// The example's report for `args`, or its error message.
fn run(args: &[&str]) -> Result<String, String> {
    let args: Vec<String> = args.iter().map(|a| a.to_string()).collect();
    let mut out = Vec::new();
    example::run(&args, &mut out).map_err(|e| e.to_string())?;
    Ok(String::from_utf8(out).expect("the report is UTF-8"))
}

/// The figure `name` on the line for `pixels` ("interior", ...).
fn figure(report: &str, pixels: &str, name: &str) -> f64 {
    let line = report
        .lines()
        .find(|l| l.split_whitespace().next() == Some(pixels))
        .unwrap_or_else(|| panic!("no `{pixels}` line in:\n{report}"));
    let mut words = line.split_whitespace();
    words
        .by_ref()
        .find(|w| *w == name)
        .unwrap_or_else(|| panic!("no `{name}` on `{line}`"));
    let value = words.next().unwrap_or_default();
    value
        .parse()
        .unwrap_or_else(|_| panic!("`{name}` is `{value}` on `{line}`, not a number"))
}

/// The report shows the GPU and the CPU reference agreeing as `check`
/// requires: the example measures interior pixels exactly as `check` does
/// (the CPU reference's `near_edge` mask), so `check`'s thresholds for the
/// mode apply. Those were measured on the default scene and every scene in
/// `assets/` (largest interior error 8.4e-5 raster, 1.2e-3 ray tracing;
/// see `CheckThresholds`), so a failure here is a real disagreement, not
/// noise. Elsewhere a figure must merely be a finite number: at a
/// silhouette one side may cover a pixel the other leaves as background.
fn assert_agreement(report: &str, shading: Shading) {
    let limits = CheckThresholds::for_shading(shading);
    let interior = figure(report, "interior", "max_abs");
    assert!(
        interior <= limits.interior_max_abs,
        "interior max_abs {interior} > {}:\n{report}",
        limits.interior_max_abs
    );
    let flip = figure(report, "flip_mean", "flip_mean");
    assert!(
        flip <= limits.flip_mean,
        "FLIP mean {flip} > {}:\n{report}",
        limits.flip_mean
    );
    for pixels in ["all", "interior", "silhouette"] {
        for name in ["max_abs", "p99_abs", "rmse"] {
            let v = figure(report, pixels, name);
            assert!(v.is_finite() && v >= 0.0, "{pixels} {name} {v}:\n{report}");
        }
    }
}

#[test]
fn default_scene_in_phong() {
    let report = run(&[]).unwrap_or_else(|e| panic!("{e}"));
    assert!(report.starts_with("scene "), "{report}");
    assert!(report.contains("640x480, phong"), "{report}");
    assert_agreement(&report, Shading::Phong);
}

#[test]
fn scene_file_and_mode_arguments() {
    let scene = concat!(env!("CARGO_MANIFEST_DIR"), "/assets/rt-mesh.toml");
    let report = run(&[scene, "raytrace"]).unwrap_or_else(|e| panic!("{e}"));
    assert!(report.contains("320x240, raytrace"), "{report}");
    assert_agreement(&report, Shading::Raytrace);
}

#[test]
fn bad_input_is_an_error_not_a_panic() {
    let e = run(&["scene.toml", "glossy"]).unwrap_err();
    assert!(e.contains("unknown shading mode `glossy`"), "{e}");
    let e = run(&["/nonexistent/scene.toml"]).unwrap_err();
    assert!(e.contains("/nonexistent/scene.toml"), "{e}");
    let e = run(&["a.toml", "phong", "extra"]).unwrap_err();
    assert!(e.starts_with("usage:"), "{e}");
}
