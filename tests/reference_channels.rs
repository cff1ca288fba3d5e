//! Every ray-traced channel of the full ray-tracing graph against the f64 reference renderer,
//! pixel by pixel (`raygraph::selftest::channels`, the code `raygraph selftest` runs; its module
//! docs give the scenes, metric and tolerances), on every back-end and layout: lavapipe must
//! run every one.

mod common;

use raygraph::selftest::channels::{scenes, ChannelProject, ChannelScene};
use raygraph::selftest::{suite_variants, Target};

#[test]
fn every_ray_traced_channel_matches_the_f64_reference_per_pixel() {
    let gpu = common::gpu();
    let shaders = common::repo().join("shaders");
    let project = ChannelProject::new().unwrap();
    let mut failures = Vec::new();
    for scene in scenes().unwrap() {
        let scene = ChannelScene::new(scene, &project);
        println!("{}", scene.describe());
        for variant in suite_variants("reference-channels") {
            let target = Target { gpu: &gpu, variant, shaders: &shaders };
            assert_eq!(target.not_applicable(), None, "CI must test every back-end ({})", variant.name);
            let mut notes = Vec::new();
            let result = target.run_case_with(|t, notes| scene.compare(&project, t, notes), &mut notes);
            notes.iter().for_each(|n| println!("{n}"));
            if let Err(e) = result {
                failures.push(e);
            }
        }
    }
    assert!(failures.is_empty(), "{}", failures.join("\n"));
}
