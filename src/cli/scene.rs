//! `raygraph scene`: a scene's statistics, its export as binary glTF or as a Mitsuba 3 scene,
//! and an orbit camera track around it.

use super::args::{DuplicateArgs, GltfSceneArg};
use anyhow::Result;
use raygraph::scene::{self, track::Track, ImportReport, LoadOptions, Scene};
use std::path::PathBuf;

#[derive(clap::Subcommand)]
pub(crate) enum SceneCommand {
    /// Print triangles, meshes, instances, materials, alpha modes, textures, bounds, lights,
    /// camera presets, texture fallbacks and what the file uses that raygraph approximates or
    /// ignores.
    Info {
        /// A built-in scene name or a .gltf/.glb file.
        scene: String,
        #[command(flatten)]
        source: SceneSource,
    },
    /// Write a scene (built-in or loaded) as binary glTF (OUT.glb), or as a Mitsuba 3 scene
    /// (OUT.xml, with its PLY meshes and images beside it; tools/mitsuba/).
    Export {
        scene: String,
        out: PathBuf,
        #[command(flatten)]
        source: SceneSource,
    },
    /// Write an orbit camera track around a scene (a starting point for recorded tracks).
    Orbit {
        scene: String,
        out: PathBuf,
        /// Length in seconds.
        #[arg(long, default_value_t = 10.0)]
        seconds: f32,
    },
}

/// How a scene is opened for `scene info` and `scene export`: its copies, the atrium's seed
/// and the glTF file's scene.
#[derive(clap::Args)]
pub(crate) struct SceneSource {
    #[command(flatten)]
    copies: DuplicateArgs,
    #[arg(long, default_value_t = raygraph::scene::procedural::ATRIUM_DEFAULT_SEED)]
    seed: u64,
    #[command(flatten)]
    gltf: GltfSceneArg,
}

impl SceneSource {
    /// The scene `spec` with its textures, copied as asked, and its import report.
    fn open(self, spec: &str) -> Result<(Scene, ImportReport)> {
        let (s, report) = scene::open(spec, &LoadOptions { textures: true, seed: self.seed, gltf_scene: self.gltf.gltf_scene })?;
        Ok((self.copies.apply(s), report))
    }
}

/// `raygraph scene info`, `scene export` and `scene orbit`.
pub(crate) fn run(command: SceneCommand) -> Result<()> {
    match command {
        SceneCommand::Info { scene, source } => {
            let (s, report) = source.open(&scene)?;
            print!("{}", raygraph::scene::info::describe(&s, Some(&report)));
        }
        SceneCommand::Export { scene, out, source } => {
            let (s, _) = source.open(&scene)?;
            export(&s, &out)?;
        }
        SceneCommand::Orbit { scene, out, seconds } => {
            let (s, _) = scene::open(&scene, &LoadOptions { textures: false, ..Default::default() })?;
            let b = s.bounds();
            let radius = 0.5 * b.diagonal().max(1e-3);
            let track = Track::orbit(b.center(), radius * 1.6, radius * 0.5, seconds, 12, s.camera().fov_y.to_degrees());
            track.save(&out)?;
            println!("wrote {} ({} key-frames, {} frames at {} fps)", out.display(), track.keys.len(), track.frame_count(), track.fps);
        }
    }
    Ok(())
}

/// Writes `s` to `out`: a Mitsuba 3 scene where its extension is `.xml`, binary glTF otherwise.
fn export(s: &Scene, out: &std::path::Path) -> Result<()> {
    if out.extension().is_some_and(|e| e.eq_ignore_ascii_case("xml")) {
        let e = raygraph::scene::export_mitsuba::write_mitsuba(s, out)?;
        for w in &e.warnings {
            eprintln!("warning: {w}");
        }
        println!("wrote {} ({} shapes, {} lights, {} files)", out.display(), e.shapes, e.lights, e.files.len());
    } else {
        raygraph::scene::export::write_glb(s, out)?;
        println!("wrote {} ({} triangles, {} meshes, {} textures)", out.display(), s.triangle_count(), s.meshes().len(), s.textures().len());
    }
    Ok(())
}
