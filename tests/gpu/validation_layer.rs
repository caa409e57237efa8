//! The validation layer is really on in the tests, and its messages are
//! caught: otherwise "no validation message" would pass vacuously.

use crate::common;

#[test]
fn an_invalid_call_is_reported() {
    let context = common::gpu();
    let messages = context.provoke_validation_message();
    assert!(
        messages.iter().any(|m| m.contains("usage")),
        "the validation layer should report a buffer with no usage flags; got {messages:?}"
    );
    // The log is drained: the next check starts clean.
    assert!(context.check_validation().is_ok());
}
