//! sward's log: env_logger's lines as `RUST_LOG` asks (warnings by default), and beside them the
//! warnings and errors wgpu's backends report — the Vulkan validation layer's and GL's debug
//! messages — kept so that `--validation` can fail on them for the portable renderer, as it
//! does for the Vulkan renderer's own messages.

use std::sync::Mutex;

/// wgpu's backend messages so far.
static BACKEND_MESSAGES: Mutex<Vec<String>> = Mutex::new(Vec::new());

struct Recorder {
    inner: env_logger::Logger,
}

/// Whether `metadata` is a backend's report: wgpu-hal's warnings and errors, but not EGL's
/// probing of the display platforms it may run on (the machine's, not sward's).
fn from_a_backend(metadata: &log::Metadata) -> bool {
    let target = metadata.target();
    metadata.level() <= log::Level::Warn && target.starts_with("wgpu_hal") && !target.starts_with("wgpu_hal::gles::egl")
}

impl log::Log for Recorder {
    fn enabled(&self, metadata: &log::Metadata) -> bool {
        from_a_backend(metadata) || self.inner.enabled(metadata)
    }

    fn log(&self, record: &log::Record) {
        if from_a_backend(record.metadata()) {
            let line = format!("{}", record.args())
                .split_whitespace()
                .collect::<Vec<_>>()
                .join(" ");
            BACKEND_MESSAGES.lock().unwrap_or_else(|e| e.into_inner()).push(line);
        }
        if self.inner.matches(record) {
            self.inner.log(record);
        }
    }

    fn flush(&self) {
        self.inner.flush();
    }
}

/// Start logging: `RUST_LOG`'s lines (warnings by default, not EGL's probing), and wgpu's
/// backend messages kept for [`take_backend_messages`].
pub fn init() {
    let env = env_logger::Env::default().default_filter_or("warn,wgpu_hal::gles::egl=off");
    let inner = env_logger::Builder::from_env(env).build();
    let most = inner.filter().max(log::LevelFilter::Warn);
    if log::set_boxed_logger(Box::new(Recorder { inner })).is_ok() {
        log::set_max_level(most);
    }
}

/// wgpu's backend messages since the last call.
pub fn take_backend_messages() -> Vec<String> {
    std::mem::take(&mut *BACKEND_MESSAGES.lock().unwrap_or_else(|e| e.into_inner()))
}
