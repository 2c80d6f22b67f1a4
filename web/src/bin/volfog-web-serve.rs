//! `volfog-web-serve DIR PORT`: serves the built page (`cargo xtask web --serve` runs
//! it) and prints what the page reports.

#[cfg(not(target_arch = "wasm32"))]
fn main() {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let [dir, port] = args.as_slice() else {
        eprintln!("usage: volfog-web-serve DIR PORT");
        std::process::exit(2);
    };
    let Ok(port) = port.parse::<u16>() else {
        eprintln!("PORT must be a number in 0..=65535, not {port:?}");
        std::process::exit(2);
    };
    let server = match volfog_web::serve::Server::start(std::path::Path::new(dir), port) {
        Ok(s) => s,
        Err(e) => {
            eprintln!("{e}");
            std::process::exit(1);
        }
    };
    println!("open {}", server.url("").trim_end_matches('?'));
    loop {
        if let Some(r) = server.next_report(std::time::Duration::from_secs(3600)) {
            match r.name.as_str() {
                "error" | "done" => println!("{}: {}", r.name, String::from_utf8_lossy(&r.body)),
                _ => println!("{}: {} bytes", r.name, r.body.len()),
            }
        }
    }
}

#[cfg(target_arch = "wasm32")]
fn main() {}
