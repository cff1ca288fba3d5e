//! The test suite runs under the Khronos validation layer, set up by README's test command
//! (`VK_INSTANCE_LAYERS`, and `VK_LAYER_SETTINGS_PATH` pointing at `.ci/vk_layer_settings.txt`,
//! which stops the process at the first validation error). This checks that net: a child
//! process makes one invalid Vulkan call through wgpu-hal (a buffer of size 0,
//! VUID-VkBufferCreateInfo-size-00912) and must be stopped by the layer with SIGTRAP before the
//! call returns.

use std::os::unix::process::ExitStatusExt;
use std::process::Command;

const CHILD: &str = "RAYGRAPH_VALIDATION_CHILD";

#[test]
fn a_validation_error_stops_the_test_process() {
    if std::env::var_os(CHILD).is_some() {
        make_an_invalid_vulkan_call();
        println!("the invalid call returned: the validation layer did not stop the process");
        std::process::exit(3);
    }
    let layers = std::env::var("VK_INSTANCE_LAYERS").unwrap_or_default();
    assert!(
        layers.contains("VK_LAYER_KHRONOS_validation") && std::env::var_os("VK_LAYER_SETTINGS_PATH").is_some(),
        "the tests run under the validation layer: use the test command in README.md (VK_INSTANCE_LAYERS, VK_LAYER_SETTINGS_PATH)"
    );
    let out = Command::new(std::env::current_exe().unwrap())
        .args(["--exact", "a_validation_error_stops_the_test_process", "--nocapture", "--test-threads", "1"])
        .env(CHILD, "1")
        .output()
        .unwrap();
    let stdout = String::from_utf8_lossy(&out.stdout);
    println!("child: {:?}\n{stdout}", out.status);
    assert!(stdout.contains("VUID-VkBufferCreateInfo-size-00912"), "the layer reported the error");
    assert_eq!(out.status.signal(), Some(5), "the layer stopped the process with SIGTRAP: {:?}", out.status);
}

fn make_an_invalid_vulkan_call() {
    let gpu = raygraph::runtime::Gpu::new().expect("a Vulkan adapter (lavapipe in CI)");
    // SAFETY: the raw device outlives the call (`gpu` is alive); the buffer, if the driver
    // makes one, is destroyed at once and never used. The size of 0 is the point: the
    // validation layer must stop the process before the call reaches the driver.
    unsafe {
        let hal = gpu.device().as_hal::<wgpu::hal::api::Vulkan>().expect("the Vulkan back-end");
        let raw = hal.raw_device();
        let info = ash::vk::BufferCreateInfo::default().size(0).usage(ash::vk::BufferUsageFlags::STORAGE_BUFFER);
        if let Ok(buffer) = raw.create_buffer(&info, None) {
            raw.destroy_buffer(buffer, None);
        }
    }
}
