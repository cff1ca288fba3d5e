//! `examples/winit_surface.rs` under Xvfb on lavapipe: the example opens its own window,
//! instance, surface and device, renders the raster graph into the window for three frames and
//! exits. A test without the default harness (`harness = false` in `Cargo.toml`): winit's event
//! loop must run on the main thread.

mod common;

#[allow(dead_code)] // `main` and `SIZE` are the example's; the test calls its `run`
#[path = "../examples/winit_surface.rs"]
mod winit_surface;

fn main() {
    let x = common::xvfb::XServer::start();
    std::env::set_var("DISPLAY", &x.display);
    std::env::remove_var("WAYLAND_DISPLAY");
    let presented = winit_surface::run(["--frames".to_string(), "3".to_string()].into_iter()).unwrap_or_else(|e| panic!("the winit example failed: {e:#}"));
    assert_eq!(presented, 3, "the example presents the frames it was asked for");
    println!("test the_winit_example_presents_three_frames ... ok");
}
