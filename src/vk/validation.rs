//! Capture of validation-layer messages.
//!
//! Every warning and error the Khronos layer reports is recorded (not just printed) so that a
//! test can fail on it. Each message carries the pass it was raised in: the innermost
//! command-buffer label the layer reports, or, for messages raised outside a labelled
//! region (queue submission, object destruction), the phase the renderer declared last.

use ash::vk;
use std::ffi::CStr;
use std::fmt;
use std::sync::{Arc, Mutex};

/// One message from the validation layer (or the loader) at warning or error severity.
#[derive(Clone, Debug)]
pub struct ValidationMessage {
    pub severity: Severity,
    /// The VUID or message id name, e.g. `VUID-VkBufferCreateInfo-size-00912` or
    /// `SYNC-HAZARD-WRITE-AFTER-WRITE`.
    pub id: String,
    /// The pass (command-buffer label) or renderer phase the message was raised in.
    pub pass: String,
    pub text: String,
}

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Severity {
    Warning,
    Error,
}

impl fmt::Display for ValidationMessage {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "[{:?}] pass `{}`: {}: {}", self.severity, self.pass, self.id, self.text)
    }
}

#[derive(Default)]
struct LogState {
    messages: Vec<ValidationMessage>,
    /// GPU allocations still live when their device was destroyed (gpu-allocator's report).
    leaks: Vec<String>,
    /// The renderer phase to blame when the layer reports no command-buffer label.
    phase: String,
}

/// Shared, thread-safe record of validation messages for one instance.
#[derive(Clone, Default)]
pub struct ValidationLog {
    state: Arc<Mutex<LogState>>,
}

impl ValidationLog {
    pub fn new() -> Self {
        let log = Self::default();
        log.set_phase("instance");
        log
    }

    /// Declares what the renderer is doing now (e.g. "submit", "shutdown"), for messages the
    /// layer raises outside any command-buffer label.
    pub fn set_phase(&self, phase: &str) {
        let mut s = self.state.lock().unwrap_or_else(|p| p.into_inner());
        s.phase.clear();
        s.phase.push_str(phase);
    }

    /// Removes and returns every message recorded so far.
    pub fn take(&self) -> Vec<ValidationMessage> {
        std::mem::take(&mut self.state.lock().unwrap_or_else(|p| p.into_inner()).messages)
    }

    /// Records an allocation that was never freed (reported at device destruction).
    pub fn record_leak(&self, what: String) {
        eprintln!("leak: {what}");
        self.state.lock().unwrap_or_else(|p| p.into_inner()).leaks.push(what);
    }

    /// Removes and returns every leak recorded so far.
    pub fn take_leaks(&self) -> Vec<String> {
        std::mem::take(&mut self.state.lock().unwrap_or_else(|p| p.into_inner()).leaks)
    }

    fn record(&self, severity: Severity, id: String, label: Option<String>, text: String) {
        let mut s = self.state.lock().unwrap_or_else(|p| p.into_inner());
        let pass = label.unwrap_or_else(|| s.phase.clone());
        let msg = ValidationMessage { severity, id, pass, text };
        // Print as it happens as well: a crash later must not swallow the cause.
        eprintln!("validation: {msg}");
        s.messages.push(msg);
    }

    /// The pointer handed to the messenger as user data. It stays valid while `self` (the
    /// instance owning it) is alive; the messenger is destroyed before the instance.
    pub(crate) fn as_user_data(&self) -> *mut std::ffi::c_void {
        Arc::as_ptr(&self.state) as *mut std::ffi::c_void
    }
}

/// Messages ignored, by their exact id name as the layer reports it, each with the reason.
/// Not a false positive but a notice about a choice we make: the best-practices check warns
/// about every instance that enables a special-use extension, and VK_EXT_debug_utils is how
/// these messages reach us at all (the 1.3.239 layer prefixes the id with `UNASSIGNED-`;
/// without the prefix this entry never matched). Nothing else is ignored: every other
/// best-practices and synchronization warning fails a test (tests/best_practices.rs).
pub const IGNORED: &[(&str, &str)] = &[(
    "UNASSIGNED-BestPractices-vkCreateInstance-specialuse-extension-debugging",
    "debug_utils is enabled on purpose: it delivers the validation messages",
)];

/// The debug-utils messenger callback. Never unwinds (a panic across `extern "system"` would
/// abort), never returns TRUE (the call that triggered the message proceeds as in production).
pub(crate) unsafe extern "system" fn messenger_callback(
    severity: vk::DebugUtilsMessageSeverityFlagsEXT,
    _types: vk::DebugUtilsMessageTypeFlagsEXT,
    data: *const vk::DebugUtilsMessengerCallbackDataEXT<'_>,
    user_data: *mut std::ffi::c_void,
) -> vk::Bool32 {
    if data.is_null() || user_data.is_null() {
        return vk::FALSE;
    }
    let sev = if severity.contains(vk::DebugUtilsMessageSeverityFlagsEXT::ERROR) {
        Severity::Error
    } else if severity.contains(vk::DebugUtilsMessageSeverityFlagsEXT::WARNING) {
        Severity::Warning
    } else {
        return vk::FALSE;
    };
    let _ = std::panic::catch_unwind(|| {
        // SAFETY: the layer passes a valid callback-data struct for the duration of the call,
        // and `user_data` is the `Mutex<LogState>` of a `ValidationLog` that outlives the
        // messenger (see `as_user_data`).
        let (data, state) = unsafe { (&*data, &*(user_data as *const Mutex<LogState>)) };
        let cstr = |p: *const std::ffi::c_char| {
            if p.is_null() {
                String::new()
            } else {
                unsafe { CStr::from_ptr(p) }.to_string_lossy().into_owned()
            }
        };
        let id = cstr(data.p_message_id_name);
        if IGNORED.iter().any(|(ignored, _)| *ignored == id) {
            return;
        }
        let label = if data.cmd_buf_label_count > 0 && !data.p_cmd_buf_labels.is_null() {
            // SAFETY: count and pointer come together from the layer.
            let labels =
                unsafe { std::slice::from_raw_parts(data.p_cmd_buf_labels, data.cmd_buf_label_count as usize) };
            labels.last().map(|l| cstr(l.p_label_name))
        } else {
            None
        };
        let log = ValidationLog { state: unsafe { borrow_arc(state) } };
        log.record(sev, id, label, cstr(data.p_message));
    });
    vk::FALSE
}

/// Rebuilds an `Arc` from the raw pointer without taking ownership of the count.
///
/// # Safety
/// `state` must point into a live `Arc<Mutex<LogState>>`.
unsafe fn borrow_arc(state: &Mutex<LogState>) -> Arc<Mutex<LogState>> {
    let ptr = state as *const Mutex<LogState>;
    // SAFETY: the caller guarantees `ptr` came from `Arc::as_ptr` of a live Arc; bumping the
    // count first keeps the count balanced when the rebuilt Arc is dropped.
    unsafe {
        Arc::increment_strong_count(ptr);
        Arc::from_raw(ptr)
    }
}
