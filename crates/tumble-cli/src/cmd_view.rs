//! `tumble view`: serves the web viewer (`viewer/dist`) on 127.0.0.1 and
//! either plays a recorded `.glb` or steps a scene file live, streaming the
//! viewer's JSON messages (viewer/README.md, "Live mode") over a WebSocket
//! at `/live` on a second port (printed in the page's URL). HTTP by
//! `tiny_http`, WebSockets by `tungstenite` ([`crate::live_session`]); each
//! WebSocket session runs its own simulation, and the page may add bodies
//! to it (`spawn`).

use crate::CliError;
use clap::Args;
use std::io::Write;
use std::path::{Component, Path, PathBuf};
use tiny_http::{Header, Request, Response, Server};
use tumble::scene::{load_scene, LoadedScene};

/// Arguments of `tumble view`.
#[derive(Args)]
#[command(after_long_help = VIEW_EXAMPLES)]
pub struct ViewArgs {
    /// A recording (.glb, written by `tumble run --out`) or a scene file
    /// (.toml, .json) to simulate live.
    #[arg(value_name = "SCENE|FILE.glb")]
    input: PathBuf,
    /// Port on 127.0.0.1 (0 picks a free one).
    #[arg(long, default_value_t = 8123)]
    port: u16,
    /// Do not open a browser; just print the URL.
    #[arg(long)]
    no_open: bool,
    /// The built viewer (default: viewer/dist of this source tree, or
    /// $TUMBLE_VIEWER_DIR).
    #[arg(long, value_name = "DIR")]
    viewer_dir: Option<PathBuf>,
    /// Live mode: simulated seconds per wall-clock second (0 = as fast as
    /// the simulation runs).
    #[arg(long, default_value_t = 1.0)]
    speed: f64,
}

const VIEW_EXAMPLES: &str = "\
Examples:
  tumble view out/tori_pass.glb            play a recording
  tumble view examples/scenes/domino.toml  simulate live in the browser
  tumble view examples/scenes/tower_game.toml   click to throw balls at a tower
  tumble view --no-open --port 9000 examples/scenes/chain.toml

The page is served until you stop the command (Ctrl-C). Live mode starts a
fresh simulation for each page load and runs the scene's steps, paced to
real time (--speed); a click in the 3D view throws a ball from the camera
at the point clicked (the page sends a `spawn` message over the WebSocket,
which listens on a second port named in the URL). The viewer is built by
`bash viewer/scripts/setup.sh && (cd viewer && npm run build)` (or `make demo`).";

/// What the page shows.
enum Source {
    Recording(PathBuf),
    Live(Box<LoadedScene>),
}

fn default_viewer_dir() -> PathBuf {
    if let Some(dir) = std::env::var_os("TUMBLE_VIEWER_DIR") {
        return PathBuf::from(dir);
    }
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../../viewer/dist")
}

fn content_type(path: &Path) -> &'static str {
    match path.extension().and_then(|e| e.to_str()).unwrap_or("") {
        "html" => "text/html; charset=utf-8",
        "js" => "text/javascript; charset=utf-8",
        "css" => "text/css; charset=utf-8",
        "json" | "map" => "application/json",
        "glb" => "model/gltf-binary",
        "png" => "image/png",
        "svg" => "image/svg+xml",
        _ => "application/octet-stream",
    }
}

fn header(text: &str) -> Header {
    text.parse::<Header>().expect("static header")
}

/// The file under `root` for a URL path, refusing anything that leaves it.
fn static_file(root: &Path, url_path: &str) -> Option<PathBuf> {
    let rel = url_path.trim_start_matches('/');
    let rel = if rel.is_empty() { "index.html" } else { rel };
    let rel = Path::new(rel);
    if rel.components().any(|c| !matches!(c, Component::Normal(_))) {
        return None;
    }
    let full = root.join(rel);
    full.is_file().then_some(full)
}

fn respond_file(request: Request, path: &Path) {
    let result = match std::fs::read(path) {
        Ok(bytes) => request.respond(
            Response::from_data(bytes)
                .with_header(header(&format!("Content-Type: {}", content_type(path))))
                .with_header(header("Cache-Control: no-store")),
        ),
        Err(e) => {
            request.respond(Response::from_string(format!("cannot read file: {e}")).with_status_code(500))
        }
    };
    // A client that went away is not our error.
    let _ = result;
}

fn not_found(request: Request) {
    let _ = request.respond(Response::from_string("not found").with_status_code(404));
}

/// Runs the verb (serves until the process is stopped).
pub fn run(args: &ViewArgs) -> Result<(), CliError> {
    let input = |m: String| CliError::Input(m);
    if !(args.speed.is_finite() && args.speed >= 0.0) {
        return Err(input(format!(
            "--speed must be finite and >= 0, got {}",
            args.speed
        )));
    }
    let is_glb = args
        .input
        .extension()
        .and_then(|e| e.to_str())
        .is_some_and(|e| e.eq_ignore_ascii_case("glb"));
    let source = if is_glb {
        if !args.input.is_file() {
            return Err(input(format!("{}: no such file", args.input.display())));
        }
        Source::Recording(args.input.clone())
    } else {
        let loaded = load_scene(&args.input).map_err(|e| input(e.to_string()))?;
        // Build once now so that a scene the world rejects fails here, not in the page.
        loaded.build().map_err(|e| input(e.to_string()))?;
        Source::Live(Box::new(loaded))
    };
    let dist = args.viewer_dir.clone().unwrap_or_else(default_viewer_dir);
    if !dist.join("index.html").is_file() {
        return Err(input(format!(
            "the web viewer is not built ({} has no index.html): run \
             `bash viewer/scripts/setup.sh && (cd viewer && npm run build)` in the repository, \
             or pass --viewer-dir",
            dist.display()
        )));
    }
    let server = Server::http(("127.0.0.1", args.port))
        .map_err(|e| input(format!("cannot listen on 127.0.0.1:{}: {e}", args.port)))?;
    let port = server
        .server_addr()
        .to_ip()
        .map(|a| a.port())
        .ok_or_else(|| CliError::Internal("server has no IP address".into()))?;
    let base = format!("http://127.0.0.1:{port}");
    let url = match &source {
        Source::Recording(_) => format!("{base}/?file=/recording.glb"),
        Source::Live(scene) => {
            let listener = std::net::TcpListener::bind(("127.0.0.1", 0))
                .map_err(|e| CliError::Internal(format!("cannot listen for WebSockets on 127.0.0.1: {e}")))?;
            let ws_port = listener
                .local_addr()
                .map_err(|e| CliError::Internal(e.to_string()))?
                .port();
            let (scene, speed) = ((**scene).clone(), args.speed);
            std::thread::spawn(move || crate::live_session::serve(listener, scene, speed));
            format!("{base}/?live=ws://127.0.0.1:{ws_port}/live")
        }
    };
    // Errors writing to stdout (a closed pipe) must not stop the server.
    let mut stdout = std::io::stdout();
    let _ = writeln!(
        stdout,
        "tumble view: serving {} at {url}\n(Ctrl-C stops the server)",
        args.input.display()
    );
    let _ = stdout.flush();
    if !args.no_open {
        if let Err(e) = open::that_detached(&url) {
            eprintln!("tumble view: could not open a browser ({e}); open the URL above");
        }
    }
    for request in server.incoming_requests() {
        let path = request.url().split(['?', '#']).next().unwrap_or("/").to_string();
        match (&source, path.as_str()) {
            (Source::Recording(file), "/recording.glb") => respond_file(request, file),
            _ => match static_file(&dist, &path) {
                Some(file) => respond_file(request, &file),
                None => not_found(request),
            },
        }
    }
    Ok(())
}
