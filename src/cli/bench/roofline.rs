//! `raygraph bench roofline`: bytes per ray of Table 3's tests and the load-bound ceiling they
//! give (`raygraph::bench::roofline`); no GPU.

use super::output::write_results;
use anyhow::{Context, Result};
use raygraph::bench::rays::{miss_outside_camera, MISS_INSIDE_PRESET, STRESS_PRESET};
use raygraph::bench::roofline;
use raygraph::scene::{self, LoadOptions};
use std::path::PathBuf;

/// The arguments of `raygraph bench roofline`.
#[derive(clap::Args)]
pub(crate) struct RooflineArgs {
    #[arg(long)]
    quick: bool,
    /// A `bench rays` results CSV whose compute rows give the achieved GigaRays/s.
    #[arg(long)]
    rays: Option<PathBuf>,
    /// Aggregate L1 bandwidth in bytes/s (default: the H100's).
    #[arg(long)]
    bandwidth: Option<f64>,
    #[arg(long, default_value = "bench-results/roofline")]
    out: PathBuf,
}

/// `raygraph bench roofline`: the scene workload on each scene, then the Miss and Stress tests.
pub(crate) fn run(args: RooflineArgs) -> Result<()> {
    let bandwidth = args.bandwidth.unwrap_or(roofline::H100_L1_BYTES_PER_S);
    // The subgroup model: `blocks` x `blocks` subgroups over the frame, `primary_rays` a pixel
    // for the primary tests (Table 3's 64).
    let (stride, ao_rays, blocks, primary_rays, scenes): (u32, u32, u32, u32, &[&str]) =
        if args.quick { (160, 4, 2, 4, &["box", "organic"]) } else { (16, 64, 12, 64, &["box", "organic", "atrium"]) };
    let no_textures = LoadOptions { textures: false, ..Default::default() };
    let mut rows = Vec::new();
    for name in scenes {
        let (s, _) = scene::open(name, &no_textures)?;
        let mut row = roofline::scene_workload(&s, stride, ao_rays, bandwidth);
        // The AO layers' default sampling, the net (index 2).
        row.subgroup_share = Some(roofline::subgroup_share_ao(&s, blocks, ao_rays, 2));
        rows.push(row);
    }
    let (atrium, _) = scene::open(if args.quick { "organic" } else { "atrium" }, &no_textures)?;
    let mut cameras = vec![("Miss (outside)", miss_outside_camera(&atrium))];
    if let Ok(inside) = atrium.preset(MISS_INSIDE_PRESET) {
        cameras.push(("Miss (inside)", inside));
    }
    cameras.push(("Stress", atrium.preset(STRESS_PRESET).map_err(anyhow::Error::msg)?));
    for (test, camera) in cameras {
        let mut row = roofline::primary_workload(test, &atrium, &camera, stride, bandwidth);
        row.subgroup_share = Some(roofline::subgroup_share_primary(&atrium, &camera, blocks, primary_rays));
        rows.push(row);
    }
    if let Some(path) = &args.rays {
        let text = std::fs::read_to_string(path).with_context(|| format!("could not read {}", path.display()))?;
        roofline::with_achieved(&mut rows, &text);
    }
    write_results(&args.out, &[("roofline.csv", roofline::csv(&rows)), ("roofline.md", roofline::markdown(&rows, bandwidth, stride))])
}
