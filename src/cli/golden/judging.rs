//! `golden`'s judging of one case as the batch hands it over: a render
//! that failed is the case's error; one that rendered says what made it
//! (its key, the hook's source) and is judged by the library
//! (`shadelab::golden::judge`), its time the judging's and the render's.

use std::time::Instant;

use shadelab::golden::{clear_pictures, mark_settings, CaseRender, JudgeOptions, Judged};

use crate::cli::common::batch::{non_finite_failure, CaseView, Made};
use crate::cli::common::failure::Failure;
use shadelab::render::described::image_metadata;

/// Compares case `view`'s render with its reference; writes what a person
/// needs to see a failure, and the references made or blessed.
pub(super) fn judge_case(
    options: &JudgeOptions,
    view: &CaseView,
    made: Result<Made, Failure>,
    started: Instant,
) -> Judged {
    let time = || started.elapsed().as_secs_f64();
    clear_pictures(&options.out, view.file_name);
    let mut made = match made {
        Ok(made) => made,
        Err(failure) => return Judged::error(failure.into(), time()),
    };
    // What made the reference, as it will say: its key and the hook's
    // source, beside render's settings.
    mark_settings(&mut made.settings, view.name, made.hook_source.as_deref());
    made.metadata = image_metadata(view.name, &made.device, &made.settings);
    // An image with NaN is never a reference, nor blessed into one.
    if let Some(failure) = non_finite_failure(&made) {
        return Judged::error(failure.into(), time());
    }
    let render = CaseRender {
        file: view.file_name,
        image: &made.rendered.image,
        metadata: &made.metadata,
        settings: &made.settings,
        device: &made.device,
        driver: made.driver.as_deref(),
    };
    match options.judge(&render) {
        Ok(mut judged) => {
            // The render's time too: JUnit's time is the case's.
            judged.time_s = time() + made.rendered.timings.total_ms / 1e3;
            judged
        }
        Err(error) => Judged::error(error.into(), time()),
    }
}
