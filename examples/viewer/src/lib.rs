//! # viewer
//!
//! The interactive viewer of the `multires` workspace: open a mesh (OBJ, PLY), look at
//! it (orbit / pan / zoom, flat or smooth shading, wireframe), pick vertices and faces by
//! ray casting, drag them, colour the mesh by scalar fields or labels, undo and redo
//! every edit, save the result. Each editing method is a [`tools::Tool`] with its own
//! panel. A scripted mode replays actions from a JSON file and writes screenshots, for
//! tests and pictures ([`script`]).
//!
//! ```text
//! cargo run --release --example viewer -- [FILE] [--script S.json] [--screenshot OUT.png]
//! ```
//!
//! The GUI stack (`three-d` with `egui`) lives only in this crate. Geometry stays `f64`
//! in the kernel; the viewer converts to `f32` (and cgmath) only to draw
//! ([`render`], [`camera::to_cg`]).
//!
//! Modules: [`app`] (the frame loop: scene, input, script runner, panels), [`camera`]
//! (orbit camera, rays), [`pick`] (BVH ray casting), [`document`] (the mesh or its
//! hierarchy + undo/redo), [`colors`] (scalar fields, labels, colour bar), [`render`] (GPU
//! side), [`tools`] (the tool trait, the parameter tables and the tools), [`script`]
//! (scripted mode), [`save`] (writing meshes), [`recipe_log`] (the edits as an edit
//! recipe), [`format`](mod@format) (numbers and durations for the panels), [`image_view`]
//! (a PNG edited in 2-D with Bendels & Klein's method).

pub mod app;
pub mod camera;
pub mod colors;
pub mod document;
pub mod format;
pub mod image_view;
pub mod pick;
pub mod recipe_log;
pub mod render;
pub mod save;
pub mod script;
pub mod tools;

use std::path::PathBuf;

use clap::Parser;

/// Command line of the viewer.
#[derive(Debug, Parser)]
#[command(
    name = "viewer",
    about = "Interactive viewer and editor for multires meshes",
    after_help = "Without a display, run it under Xvfb:\n  xvfb-run -a -s '-screen 0 1600x1000x24' viewer ...\nScript format: see the `script` module docs (examples/viewer/src/script.rs)."
)]
pub struct Args {
    /// Mesh to open (.obj, .ply), or a picture (.png) to edit in the 2-D image view;
    /// default: the first mesh in data/, else an icosphere.
    pub file: Option<PathBuf>,
    /// Replay the actions of this JSON script, then exit.
    #[arg(long, value_name = "FILE")]
    pub script: Option<PathBuf>,
    /// Write a PNG of the window at the end (after the script, if any), then exit.
    #[arg(long, value_name = "OUT.png")]
    pub screenshot: Option<PathBuf>,
    /// Window size in logical pixels.
    #[arg(long, default_value = "1280x800", value_parser = parse_size)]
    pub size: (u32, u32),
    /// Multisampling (0 to switch off; 4 is smoother, slower on software OpenGL).
    #[arg(long, default_value_t = 4)]
    pub msaa: u8,
    /// Stay open after the script (and after a failed action).
    #[arg(long)]
    pub keep_open: bool,
    /// Subdivide the mesh this many times (1-to-4) after reading it: large test meshes.
    #[arg(long, default_value_t = 0, value_name = "N")]
    pub subdivide: u32,
}

fn parse_size(s: &str) -> Result<(u32, u32), String> {
    let (w, h) = s
        .split_once(['x', 'X'])
        .ok_or_else(|| format!("size {s:?}: want WIDTHxHEIGHT, e.g. 1280x800"))?;
    let w: u32 = w.trim().parse().map_err(|e| format!("width {w:?}: {e}"))?;
    let h: u32 = h.trim().parse().map_err(|e| format!("height {h:?}: {e}"))?;
    if w < 320 || h < 240 {
        return Err(format!("size {w}x{h}: at least 320x240"));
    }
    Ok((w, h))
}

/// Parses the command line and runs the viewer; never returns (the window's event loop
/// ends the process). Exit status: 0 on success, 1 when a script action or a screenshot
/// fails, 2 when the mesh, the script or the window cannot be opened.
pub fn main() -> ! {
    let args = Args::parse();
    run(args)
}

/// Runs the viewer with `args` (see [`main`]).
pub fn run(args: Args) -> ! {
    let script = match &args.script {
        Some(path) => match script::load(path) {
            Ok(actions) => Some(script::expand(actions)),
            Err(e) => {
                eprintln!("viewer: script {}: {e}", path.display());
                std::process::exit(2);
            }
        },
        None => None,
    };
    // A picture opens in the image view, over a mesh of its own.
    let picture = args.file.as_ref().filter(|p| image_view::is_png(p));
    let (mesh, source, report) = match args.file.as_ref().filter(|_| picture.is_none()) {
        // A soup or a mesh cut along seams is read as its surface.
        Some(path) => match document::read_mesh(path) {
            Ok((mesh, report, _)) => (mesh, Some(path.clone()), Some(report)),
            Err(e) => {
                eprintln!("viewer: {e}");
                std::process::exit(2);
            }
        },
        // (A small one: it stays hidden behind the picture.)
        None if picture.is_some() => (halfedge::generators::icosphere(3), None, None),
        None => {
            let (mesh, source) = app::default_mesh();
            (mesh, source, None)
        }
    };
    let mesh = (0..args.subdivide).fold(mesh, |m, _| halfedge::generators::subdivide(&m));
    let title = match picture.or(source.as_ref()) {
        Some(p) => format!(
            "multires viewer — {}",
            p.file_name().unwrap_or_default().to_string_lossy()
        ),
        None => "multires viewer".to_string(),
    };
    let window = three_d::Window::new(three_d::WindowSettings {
        title,
        initial_size: Some(args.size),
        min_size: (320, 240),
        surface_settings: three_d::SurfaceSettings {
            multisamples: args.msaa,
            vsync: false,
            ..Default::default()
        },
        ..Default::default()
    });
    let window = match window {
        Ok(w) => w,
        Err(e) => {
            eprintln!(
                "viewer: cannot open a window ({e}). Without a display, run it under Xvfb: \
                 xvfb-run -a -s '-screen 0 1600x1000x24' ..."
            );
            std::process::exit(2);
        }
    };
    let context = window.gl();
    let mut gui = three_d::GUI::new(&context);
    let doc = document::Document::new(mesh, source, report);
    let mut app = app::App::new(
        &context,
        doc,
        app::Options {
            script,
            screenshot: args.screenshot,
            keep_open: args.keep_open,
        },
    );
    if let Some(path) = picture {
        if let Err(e) = app.load(path) {
            eprintln!("viewer: {e}");
            std::process::exit(2);
        }
    }
    window.render_loop(move |frame| app.frame(frame, &mut gui));
    std::process::exit(0)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn sizes_parse() {
        assert_eq!(parse_size("1280x800"), Ok((1280, 800)));
        assert_eq!(parse_size("640X480"), Ok((640, 480)));
        assert!(parse_size("12x8").is_err());
        assert!(parse_size("wide").is_err());
    }
}
