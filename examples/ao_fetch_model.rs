//! The subgroup model of a lane's AO rays traced in one loop whose lanes fetch their next ray
//! together when enough of them wait (a subgroup vote), against rays in rounds (PERF.md step
//! 44): `cargo run --release --example ao_fetch_model -- SCENE BLOCKS`, the time of each
//! against rounds for fetch costs (in interior steps), vote costs and thresholds.

use raygraph::bench::roofline;
use raygraph::scene::{self, LoadOptions};

fn main() -> anyhow::Result<()> {
    let args: Vec<String> = std::env::args().collect();
    let (Some(name), Some(blocks)) = (args.get(1), args.get(2)) else {
        anyhow::bail!("usage: ao_fetch_model SCENE BLOCKS");
    };
    let (s, _) = scene::open(name, &LoadOptions { textures: false, ..Default::default() })?;
    // 64 rays a pixel, the net (the AO layers' default sampling), as `bench roofline` models.
    let subgroups = roofline::ao_subgroup_steps(&s, blocks.parse()?, 64, 2);
    for fetch in [0.0, 1.0, 2.5, 4.0] {
        for vote in [0.0, 0.1] {
            let total = |threshold: f64| subgroups.iter().map(|lanes| roofline::voted_fetch_time(lanes, fetch, vote, threshold).1).sum::<f64>();
            let rounds = total(f64::INFINITY);
            print!("fetch {fetch} vote {vote}: rounds 1.000x");
            for threshold in [0.125, 0.25, 0.375, 0.5, 0.75, 1.0] {
                print!(" | {threshold}: {:.3}x", rounds / total(threshold));
            }
            println!();
        }
    }
    Ok(())
}
