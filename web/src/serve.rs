//! The page's server on 127.0.0.1: the built page's files with their content types,
//! and what the page posts to `/report/<name>` (`error`, `done`, and the read-back
//! data), handed to whoever waits for it. `cargo xtask web --serve` and the browser
//! test both run it.

use std::path::{Path, PathBuf};
use std::sync::mpsc;
use std::time::Duration;

/// One report the page posted: its name (`/report/<name>`) and body.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Report {
    /// The name after `/report/`.
    pub name: String,
    /// The body, as posted.
    pub body: Vec<u8>,
}

/// A running server; it stops when dropped.
pub struct Server {
    /// The port it listens on (127.0.0.1).
    pub port: u16,
    reports: mpsc::Receiver<Report>,
    server: std::sync::Arc<tiny_http::Server>,
    thread: Option<std::thread::JoinHandle<()>>,
}

/// The server could not start.
#[derive(Debug, thiserror::Error)]
#[error("cannot serve {dir} on 127.0.0.1:{port}: {reason}")]
pub struct ServeError {
    /// The folder to serve.
    pub dir: PathBuf,
    /// The port asked for (0: any free one).
    pub port: u16,
    /// Why.
    pub reason: String,
}

fn content_type(file: &Path) -> &'static str {
    match file.extension().and_then(|e| e.to_str()) {
        Some("html") => "text/html; charset=utf-8",
        Some("js" | "mjs") => "text/javascript",
        Some("wasm") => "application/wasm",
        Some("json") => "application/json",
        _ => "text/plain; charset=utf-8",
    }
}

fn respond(request: tiny_http::Request, base: &Path, reports: &mpsc::Sender<Report>) {
    let url = request.url().split('?').next().unwrap_or("/").to_string();
    if let Some(name) = url.strip_prefix("/report/") {
        let name = name.to_string();
        let mut request = request;
        let mut body = Vec::new();
        let _ = std::io::Read::read_to_end(request.as_reader(), &mut body);
        let _ = request.respond(tiny_http::Response::empty(204));
        let _ = reports.send(Report { name, body });
        return;
    }
    let path = if url == "/" {
        "index.html"
    } else {
        url.trim_start_matches('/')
    };
    let file = base.join(path);
    match std::fs::File::open(&file) {
        Ok(f) if !path.split('/').any(|c| c == "..") => {
            let header = tiny_http::Header::from_bytes("Content-Type", content_type(&file))
                .expect("a valid header");
            let _ = request.respond(tiny_http::Response::from_file(f).with_header(header));
        }
        _ => {
            let _ = request.respond(tiny_http::Response::empty(404));
        }
    }
}

impl Server {
    /// Serves `dir` on 127.0.0.1:`port` (0 picks a free port).
    pub fn start(dir: &Path, port: u16) -> Result<Self, ServeError> {
        let fail = |reason: String| ServeError {
            dir: dir.to_path_buf(),
            port,
            reason,
        };
        if !dir.join("index.html").is_file() {
            return Err(fail(
                "it holds no index.html (build it with `cargo xtask web`)".into(),
            ));
        }
        let server = std::sync::Arc::new(
            tiny_http::Server::http(("127.0.0.1", port)).map_err(|e| fail(e.to_string()))?,
        );
        let port = server
            .server_addr()
            .to_ip()
            .map(|a| a.port())
            .ok_or_else(|| fail("not an IP address".into()))?;
        let (tx, reports) = mpsc::channel();
        let base = dir.to_path_buf();
        let listener = server.clone();
        let thread = std::thread::spawn(move || {
            for request in listener.incoming_requests() {
                respond(request, &base, &tx);
            }
        });
        Ok(Self {
            port,
            reports,
            server,
            thread: Some(thread),
        })
    }

    /// The page's address with `query` (e.g. `check=320x180`).
    pub fn url(&self, query: &str) -> String {
        format!("http://127.0.0.1:{}/index.html?{query}", self.port)
    }

    /// The next report, waiting at most `timeout`.
    pub fn next_report(&self, timeout: Duration) -> Option<Report> {
        self.reports.recv_timeout(timeout).ok()
    }
}

impl Drop for Server {
    fn drop(&mut self) {
        self.server.unblock();
        if let Some(t) = self.thread.take() {
            let _ = t.join();
        }
    }
}
