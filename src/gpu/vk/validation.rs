//! Capture of Khronos validation-layer messages.
//!
//! Each context owns one `MessageLog`; the debug-utils callback appends
//! validation and performance warnings and errors to it, and callers drain it
//! after each piece of GPU work so a message fails the work that caused it.

use std::ffi::{c_void, CStr};
use std::sync::Mutex;

use ash::vk;

#[derive(Default)]
pub struct MessageLog {
    messages: Mutex<Vec<String>>,
}

impl MessageLog {
    pub fn take(&self) -> Vec<String> {
        std::mem::take(&mut *self.messages.lock().unwrap_or_else(|e| e.into_inner()))
    }
}

pub fn messenger_info(log: &MessageLog) -> vk::DebugUtilsMessengerCreateInfoEXT<'static> {
    vk::DebugUtilsMessengerCreateInfoEXT::default()
        .message_severity(
            vk::DebugUtilsMessageSeverityFlagsEXT::WARNING
                | vk::DebugUtilsMessageSeverityFlagsEXT::ERROR,
        )
        // GENERAL is left out: the loader reports harmless driver-discovery
        // notes there that say nothing about our API use.
        .message_type(
            vk::DebugUtilsMessageTypeFlagsEXT::VALIDATION
                | vk::DebugUtilsMessageTypeFlagsEXT::PERFORMANCE,
        )
        .pfn_user_callback(Some(on_message))
        .user_data(log as *const MessageLog as *mut c_void)
}

unsafe extern "system" fn on_message(
    severity: vk::DebugUtilsMessageSeverityFlagsEXT,
    _types: vk::DebugUtilsMessageTypeFlagsEXT,
    data: *const vk::DebugUtilsMessengerCallbackDataEXT<'_>,
    user_data: *mut c_void,
) -> vk::Bool32 {
    // SAFETY: the layer passes a valid callback-data pointer for the duration
    // of the call, and `user_data` is the `MessageLog` that the owning context
    // keeps alive (boxed) until after the messenger is destroyed.
    let (log, text) = unsafe {
        let log = &*(user_data as *const MessageLog);
        let text = if data.is_null() || (*data).p_message.is_null() {
            String::from("(no message text)")
        } else {
            CStr::from_ptr((*data).p_message)
                .to_string_lossy()
                .into_owned()
        };
        (log, text)
    };
    let entry = format!("[{severity:?}] {text}");
    log.messages
        .lock()
        .unwrap_or_else(|e| e.into_inner())
        .push(entry);
    vk::FALSE
}
