//! The page's log: every record goes to the browser console, and those at warning level and
//! above (features chosen out at start-up, import notes) are also kept for the page's log
//! panel.

use std::sync::Mutex;

static KEPT: Mutex<Vec<String>> = Mutex::new(Vec::new());

struct ConsoleLog;

impl log::Log for ConsoleLog {
    fn enabled(&self, metadata: &log::Metadata) -> bool {
        metadata.level() <= log::Level::Info && (metadata.target().starts_with("raygraph") || metadata.level() <= log::Level::Warn)
    }

    fn log(&self, record: &log::Record) {
        if !self.enabled(record.metadata()) {
            return;
        }
        let line = format!("{}: {}", record.level(), record.args());
        match record.level() {
            log::Level::Error => web_sys::console::error_1(&line.clone().into()),
            log::Level::Warn => web_sys::console::warn_1(&line.clone().into()),
            _ => web_sys::console::log_1(&line.clone().into()),
        }
        if record.level() <= log::Level::Warn || record.target().starts_with("raygraph::runtime::gpu") {
            if let Ok(mut kept) = KEPT.lock() {
                kept.push(line);
            }
        }
    }

    fn flush(&self) {}
}

static LOGGER: ConsoleLog = ConsoleLog;

/// Installs the logger (once; later calls do nothing).
pub fn install() {
    if log::set_logger(&LOGGER).is_ok() {
        log::set_max_level(log::LevelFilter::Info);
    }
}

/// The kept lines since the last call.
pub fn take() -> Vec<String> {
    KEPT.lock().map(|mut k| std::mem::take(&mut *k)).unwrap_or_default()
}
