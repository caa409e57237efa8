//! How a command fails: an error that knows its exit status, made from
//! the library's errors (the statuses are in `docs/cli.md`).

/// An error that knows its exit status.
#[derive(Debug, Clone)]
pub struct Failure {
    pub code: u8,
    pub message: String,
}

impl Failure {
    /// Bad input or usage: exit status 2.
    pub fn usage(message: String) -> Self {
        Failure { code: 2, message }
    }
}

impl From<shadelab::Error> for Failure {
    fn from(e: shadelab::Error) -> Self {
        Failure {
            code: e.exit_code() as u8,
            message: e.to_string(),
        }
    }
}

impl From<shadelab::gpu::GpuError> for Failure {
    fn from(e: shadelab::gpu::GpuError) -> Self {
        shadelab::Error::from(e).into()
    }
}

impl From<shadelab::scene::SceneError> for Failure {
    fn from(e: shadelab::scene::SceneError) -> Self {
        shadelab::Error::from(e).into()
    }
}

impl From<shadelab::output::OutputError> for Failure {
    fn from(e: shadelab::output::OutputError) -> Self {
        shadelab::Error::from(e).into()
    }
}
