//! A virtual X server for the tests that open windows (`raygraph view`, the winit example).
//! CI installs `xvfb`; without `Xvfb` these tests fail rather than skip.

use std::io::{BufRead, BufReader};
use std::process::{Child, Command, Stdio};

/// A virtual X server, stopped on drop.
pub struct XServer {
    process: Child,
    /// Its display, `:N`, for `DISPLAY`.
    pub display: String,
}

impl XServer {
    pub fn start() -> XServer {
        let mut process = Command::new("Xvfb")
            .args(["-displayfd", "1", "-screen", "0", "1024x768x24", "-nolisten", "tcp"])
            .stdout(Stdio::piped())
            .stderr(Stdio::null())
            .spawn()
            .unwrap_or_else(|e| panic!("Xvfb is needed for the window tests (apt-get install xvfb; .ci/install-vulkan.sh does): {e}"));
        let mut out = BufReader::new(process.stdout.take().unwrap());
        let mut line = String::new();
        out.read_line(&mut line).unwrap();
        // Keep reading, so that a later write of Xvfb's never meets a closed pipe.
        std::thread::spawn(move || std::io::copy(&mut out, &mut std::io::sink()));
        let n: u32 = line.trim().parse().unwrap_or_else(|_| panic!("Xvfb did not report its display: {line:?}"));
        XServer { process, display: format!(":{n}") }
    }
}

impl Drop for XServer {
    fn drop(&mut self) {
        let _ = self.process.kill();
        let _ = self.process.wait();
    }
}
