//! `examples/winit_surface.rs` under Xvfb on lavapipe: the example opens its own window,
//! instance, surface and device, renders the raster graph into the window, is resized after the
//! first frame (the executor is built again at the new size), presents at least three frames
//! and exits. It checks frames and sizes, not pixels: a swapchain image cannot be read back
//! once presented, and Xvfb's screen has no reader here; the pixels the example draws are the
//! raster graph's, which tests/cli.rs checks byte for byte against the library. A test
//! without the default harness (`harness = false` in `Cargo.toml`): winit's event
//! loop must run on the main thread.

mod common;

#[allow(dead_code)] // `main` and `SIZE` are the example's; the test calls its `run`
#[path = "../examples/winit_surface.rs"]
mod winit_surface;

fn main() {
    let x = common::xvfb::XServer::start();
    std::env::set_var("DISPLAY", &x.display);
    std::env::remove_var("WAYLAND_DISPLAY");
    let args = ["--frames", "3", "--resize", "200x120"].map(String::from);
    let (presented, size) = winit_surface::run(args.into_iter()).unwrap_or_else(|e| panic!("the winit example failed: {e:#}"));
    assert!(presented >= 3, "the example presents the frames it was asked for, not {presented}");
    assert_eq!(size, (200, 120), "the last frame is presented at the new window size");
    println!("test the_winit_example_presents_frames_and_follows_a_resize ... ok");
}
