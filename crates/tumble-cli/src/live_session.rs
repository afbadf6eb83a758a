//! The transport of `tumble view SCENE`'s live sessions: builds the scene's
//! world, sends the viewer's messages over a WebSocket, one `frame` per step
//! paced to real time, and hands the page's requests (a `spawn`: a ball
//! thrown from the camera) to the library's session between steps. The
//! protocol, requests included, is `tumble::export::live` and
//! `tumble::export::live_session` (viewer/README.md, "Live mode").
//!
//! The WebSocket runs on its own TCP listener (not tiny_http's upgraded
//! stream) so that the socket's read timeout can be set: reading requests
//! never holds up the stream of frames.

use std::io::ErrorKind;
use std::net::{TcpListener, TcpStream};
use std::time::{Duration, Instant};
use tumble::export::live_session::LiveSession;
use tumble::scene::LoadedScene;
use tungstenite::{Message, WebSocket};

/// Text messages that arrive before `due` (at least those already waiting);
/// `Err` when the page closed the connection.
fn read_until(ws: &mut WebSocket<TcpStream>, due: Instant) -> Result<Vec<String>, ()> {
    let mut texts = Vec::new();
    loop {
        let wait = due.saturating_duration_since(Instant::now());
        // A zero wait still drains what is waiting, without blocking.
        let nonblocking = wait.is_zero();
        let configured = if nonblocking {
            ws.get_ref().set_nonblocking(true)
        } else {
            ws.get_ref()
                .set_nonblocking(false)
                .and_then(|_| ws.get_ref().set_read_timeout(Some(wait)))
        };
        configured.map_err(|_| ())?;
        let read = ws.read();
        if nonblocking {
            ws.get_ref().set_nonblocking(false).map_err(|_| ())?;
        }
        match read {
            Ok(Message::Text(t)) => texts.push(t.as_str().to_string()),
            Ok(Message::Close(_)) => return Err(()),
            Ok(_) => {}
            Err(tungstenite::Error::Io(e))
                if matches!(e.kind(), ErrorKind::WouldBlock | ErrorKind::TimedOut) =>
            {
                if Instant::now() >= due {
                    return Ok(texts);
                }
            }
            Err(_) => return Err(()),
        }
        if Instant::now() >= due && nonblocking {
            return Ok(texts);
        }
    }
}

fn send_all(ws: &mut WebSocket<TcpStream>, messages: Vec<String>) -> Result<(), ()> {
    for m in messages {
        ws.send(Message::text(m)).map_err(|_| ())?;
    }
    Ok(())
}

/// Runs one session until the scene's steps are done (then waits for the
/// page to close) or the page goes away.
fn run(scene: &LoadedScene, mut ws: WebSocket<TcpStream>, speed: f64) -> Result<(), ()> {
    let (world, _) = scene.build().map_err(|_| ())?;
    let mut session = LiveSession::new(world);
    send_all(&mut ws, session.start_messages().map_err(|_| ())?)?;
    let started = Instant::now();
    for _ in 0..scene.scene.steps {
        let due = if speed > 0.0 {
            started + Duration::from_secs_f64(session.world.time() / speed)
        } else {
            Instant::now()
        };
        for text in read_until(&mut ws, due)? {
            let replies = session.handle(&text);
            send_all(&mut ws, replies)?;
        }
        session.world.step();
        send_all(&mut ws, vec![session.frame_message()])?;
    }
    // The page keeps its frames: hold the connection until it closes it.
    ws.get_ref().set_read_timeout(None).map_err(|_| ())?;
    loop {
        match ws.read() {
            Ok(Message::Close(_)) | Err(_) => return Ok(()),
            Ok(Message::Text(_)) => send_all(&mut ws, vec![LiveSession::ended_message()])?,
            Ok(_) => {}
        }
    }
}

/// The handshake answer: sessions live at `/live`, anything else is 404.
// The signature is tungstenite's `Callback`: its error is an HTTP response.
#[allow(clippy::result_large_err)]
fn only_live(
    req: &tungstenite::handshake::server::Request,
    resp: tungstenite::handshake::server::Response,
) -> Result<tungstenite::handshake::server::Response, tungstenite::handshake::server::ErrorResponse> {
    if req.uri().path() == "/live" {
        Ok(resp)
    } else {
        let mut not_found = tungstenite::handshake::server::ErrorResponse::new(Some("not found".into()));
        *not_found.status_mut() = tungstenite::http::StatusCode::NOT_FOUND;
        Err(not_found)
    }
}

/// Accepts WebSocket connections on `listener` (path `/live`), each in its
/// own thread with its own simulation of `scene`. Never returns.
pub fn serve(listener: TcpListener, scene: LoadedScene, speed: f64) {
    for stream in listener.incoming() {
        let Ok(stream) = stream else { continue };
        let scene = scene.clone();
        std::thread::spawn(move || {
            if let Ok(ws) = tungstenite::accept_hdr(stream, only_live) {
                // A page that goes away ends its session; nothing to report.
                let _ = run(&scene, ws, speed);
            }
        });
    }
}
